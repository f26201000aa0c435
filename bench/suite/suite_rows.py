"""The rows of a tier: the suite file's conditions x seeds, with each seed's drawn world and motion.

A row is a plain dict: id (unique, names the sequence and the run), condition (what the tables
group by), profile, seed, fps, layout ('bag', 'rawlog' or 'files'), duration_s (None: the recording's
length), sim_keys ([sim] keys of its --config), extra rgbdi-sim arguments, and for hybrid rows the
recording directory.
"""
import hashlib
import json
import os

PROFILES = ["handheld", "wheeled_circle", "wheeled_slopes", "tracked_slopes"]
# bag: rgbdi-sim --bag, converted by rawlog-convert (raw images in the rawlog, as a user of the
# published dataset has them); rawlog: rgbdi-sim's rawlog with the images inside; files: its
# rawlog with the images as PNG and range files beside it (MRPT's layout for large datasets).
LAYOUTS = ["bag", "rawlog", "files"]
WORLD_KEYS = ["world_seed", "room_margin_m", "furniture_density", "furniture_lateral_max_m",
              "texture_contrast", "exposure_gain_amplitude", "exposure_period_s"]


def load_definition(path):
    """The suite file, checked: errors name the file and the entry."""
    try:
        with open(path) as f:
            d = json.load(f)
    except OSError as e:
        raise ValueError(f"{path}: {e.strerror}")
    except json.JSONDecodeError as e:
        raise ValueError(f"{path}: not JSON: {e}")
    validate_definition(d, path)
    return d


def validate_definition(d, path):
    def fail(where, what):
        raise ValueError(f"{path}: {where}: {what}")
    for section in ("draw", "profiles", "rates", "hard_cases", "recordings", "tiers", "compare"):
        if not isinstance(d.get(section), dict):
            fail(section, "missing (an object)")
    for k, v in d.get("sensor", {}).items():
        if not k.startswith("_") and not isinstance(v, (int, float)):
            fail(f"sensor.{k}", "a number")
    for k in WORLD_KEYS + ["speed_factor", "speed_m_s_fast"]:
        r = d["draw"].get(k)
        if not isinstance(r, dict) or not isinstance(r.get("min"), (int, float)) or \
                not isinstance(r.get("max"), (int, float)) or r["min"] > r["max"]:
            fail(f"draw.{k}", "needs numbers min <= max")
    if not d["draw"].get("wheeled_slopes_speed"):
        fail("draw.wheeled_slopes_speed", "needs a list of speed presets")
    for p in PROFILES:
        prof = d["profiles"].get(p)
        if not isinstance(prof, dict) or not (prof.get("speed_preset") or
                                              isinstance(prof.get("speed_m_s"), (int, float))):
            fail(f"profiles.{p}", "needs speed_m_s [m/s] or speed_preset: true")
    for name, r in d["rates"].items():
        if name.startswith("_"):
            continue
        if not isinstance(r.get("fps"), (int, float)) or r.get("layout") not in LAYOUTS:
            fail(f"rates.{name}", "needs fps and layout " + "|".join(LAYOUTS))
    for name, t in d["tiers"].items():
        where = f"tiers.{name}"
        if not t.get("seeds") or "duration_s" not in t:
            fail(where, "needs seeds and duration_s")
        dur = t["duration_s"]
        for v in (dur.values() if isinstance(dur, dict) else [dur]):
            if v is not None and not (isinstance(v, (int, float)) and v > 0):
                fail(f"{where}.duration_s", "seconds > 0, null (the profile's own length) or "
                     "an object of those per rate")
        rates = list(t.get("rates", []))
        rates += (t.get("handheld_fast") or {}).get("rates", [])
        rates += (t.get("hybrid") or {}).get("rates", [])
        if t.get("hard"):
            rates.append(t["hard"].get("rate"))
            for p in t["hard"].get("profiles", []):
                if p not in PROFILES:
                    fail(f"{where}.hard.profiles", f"unknown profile '{p}'")
        for r in rates:
            if r not in d["rates"] or r.startswith("_"):
                fail(where, f"unknown rate '{r}' (the file defines "
                     f"{', '.join(k for k in d['rates'] if not k.startswith('_'))})")
    for k in ("worse_ratio", "much_worse_ratio", "median_tolerance", "max_much_worse_fraction"):
        if not isinstance(d["compare"].get(k), (int, float)):
            fail(f"compare.{k}", "missing (a number)")


def unit_draw(name, seed, key):
    """A number in [0, 1) that depends only on (name, seed, key): the first 52 bits of
    SHA-256, so the same on every machine and Python version."""
    h = hashlib.sha256(f"{name}:{seed}:{key}".encode()).hexdigest()
    return int(h[:13], 16) / float(16 ** 13)


def draw_value(spec, u):
    if spec.get("int"):
        # whole numbers min..max inclusive
        return spec["min"] + min(int(u * (spec["max"] - spec["min"] + 1)),
                                 spec["max"] - spec["min"])
    return round(spec["min"] + u * (spec["max"] - spec["min"]), 4)


def draw_sim_keys(definition, name, seed, profile, fast=False):
    """The [sim] keys of (name, seed): world keys always; speed_m_s around the profile's
    default (or in the fast range), or None for wheeled_slopes, which draws a speed preset.
    Returns (keys, speed_preset)."""
    d = definition["draw"]
    keys = {k: draw_value(d[k], unit_draw(name, seed, k)) for k in WORLD_KEYS}
    # The D435i's sensor effects, the same on every row (a recording keeps its real IMU).
    for k, v in definition.get("sensor", {}).items():
        if not k.startswith("_") and not (profile == "recorded" and k.startswith("imu_")):
            keys[k] = v
    preset = None
    if profile == "recorded":
        return keys, None
    if definition["profiles"][profile].get("speed_preset"):
        choices = d["wheeled_slopes_speed"]
        preset = choices[min(int(unit_draw(name, seed, "speed") * len(choices)), len(choices) - 1)]
    elif fast:
        keys["speed_m_s"] = draw_value(d["speed_m_s_fast"], unit_draw(name, seed, "speed"))
    else:
        factor = draw_value(d["speed_factor"], unit_draw(name, seed, "speed"))
        keys["speed_m_s"] = round(definition["profiles"][profile]["speed_m_s"] * factor, 4)
    return keys, preset


def _row(definition, rid, condition, name, profile, seed, rate, duration, fast=False):
    r = definition["rates"][rate]
    keys, preset = draw_sim_keys(definition, name, seed, profile, fast)
    return {"id": rid, "condition": condition, "profile": profile, "seed": seed,
            "rate": rate, "fps": r["fps"], "layout": r["layout"], "duration_s": duration,
            "sim_keys": keys, "speed_preset": preset, "extra_args": [], "recording": None}


def hard_args(case, start_s):
    if "blackout" in case:
        return ["--blackout", f"{start_s:g}:{case['duration_s']:g}:{case['blackout']}"]
    if "spin_turns" in case:
        return ["--spin", f"{start_s:g}:{case['duration_s']:g}:{case['spin_turns']:g}"]
    if "time_offset_s" in case:
        return ["--time-offset", f"{case['time_offset_s']:g}"]
    raise ValueError(f"hard case {case} has none of blackout, spin_turns, time_offset_s")


def tier_duration(t, rate):
    """[s] of a tier's rows at a rate: duration_s is one value for every rate or an object per
    rate; None = the profile's own length (doc/simulator.md)."""
    d = t["duration_s"]
    return d.get(rate) if isinstance(d, dict) else d


def planned_duration_s(definition, row):
    """[s] of data a row will have: its duration_s, or for None the profile's own length from
    suite.json (a hybrid row's recording length is unknown here: None)."""
    if row["duration_s"] is not None:
        return row["duration_s"]
    prof = definition["profiles"].get(row["profile"], {})
    own = prof.get("own_duration_s")
    if isinstance(own, dict):
        return own.get(row["speed_preset"] or "normal")
    if own is not None:
        return own
    speed = row["sim_keys"].get("speed_m_s", prof.get("speed_m_s"))
    if prof.get("own_length_m") and speed:
        return prof.get("own_overhead_s", 0.0) + prof["own_length_m"] / speed
    return None


def tier_rows(definition, tier, repo_root):
    """Every row of the tier, in a fixed order."""
    if tier not in definition["tiers"]:
        raise ValueError(f"unknown tier '{tier}' (the suite file has "
                         f"{', '.join(definition['tiers'])})")
    t = definition["tiers"][tier]
    rows = []
    for p in PROFILES:
        for rate in t["rates"]:
            for s in t["seeds"]:
                rows.append(_row(definition, f"{p}_s{s}_{rate}", f"{p} {rate}", p, p, s, rate,
                                 tier_duration(t, rate)))
    fast = t.get("handheld_fast")
    if fast:
        for rate in fast["rates"]:
            for s in fast["seeds"]:
                rows.append(_row(definition, f"handheld_fast_s{s}_{rate}",
                                 f"handheld_fast {rate}", "handheld_fast", "handheld", s, rate,
                                 tier_duration(t, rate), fast=True))
    hard = t.get("hard")
    if hard:
        start = round(hard["start_fraction"] * hard["duration_s"], 3)
        for kind, case in definition["hard_cases"].items():
            if kind.startswith("_"):
                continue
            for p in hard["profiles"]:
                for s in hard["seeds"]:
                    r = _row(definition, f"hard_{kind}_{p}_s{s}_{hard['rate']}",
                             f"hard {kind} {hard['rate']}", p, p, s, hard["rate"],
                             hard["duration_s"])
                    r["extra_args"] = hard_args(case, start)
                    rows.append(r)
    hybrid = t.get("hybrid")
    if hybrid:
        for name, rel in definition["recordings"].items():
            if name.startswith("_"):
                continue
            for rate in hybrid["rates"]:
                for s in hybrid["seeds"]:
                    r = _row(definition, f"recorded_{name}_s{s}_{rate}",
                             f"recorded {name} {rate}", f"recorded:{name}", "recorded", s, rate,
                             None)
                    r["recording"] = os.path.normpath(os.path.join(repo_root, rel))
                    rows.append(r)
    ids = [r["id"] for r in rows]
    if len(set(ids)) != len(ids):
        raise ValueError("the suite file gives two rows the same id")
    return rows
