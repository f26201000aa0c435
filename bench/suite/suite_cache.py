"""Generated sequences, cached by what made them.

Cache entry = CACHE_DIR/<row id>-<key>/ where key is a hash of the rgbdi-sim arguments, the text
of the row's --config, the rgbdi-sim binary's --version line, (bag rows) rawlog-convert's
--version line and arguments, and (hybrid rows) the recording's file names, sizes and times.
An entry holds what rgbdi-slam needs:
  sequence.rawlog, slam.ini (the configuration to run with), groundtruth.tum, simulation.ini,
  sim_config.ini, generation.json (commands, times); bag rows also vins_config.yaml and the
  converter's report.
Generation writes a temporary directory and renames it when complete, so a killed run leaves no
half entry. Bag rows delete the bag and the simulator's own rawlog after conversion (1.5 MB per
frame each); the converted rawlog is what a user of the published layout runs on.
"""
import hashlib
import json
import os
import re
import shutil
import subprocess
import threading
import time


def tool_version(binary):
    """--version names the release only: the binary's own bytes tell one build from another, so
    a changed simulator or converter regenerates the sequences it made."""
    out = subprocess.run([binary, "--version"], capture_output=True, text=True, check=True)
    h = hashlib.sha256()
    with open(binary, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return out.stdout.strip() + " sha256:" + h.hexdigest()[:16]


def probe_sim_keys(sim, work_dir, values):
    """The [sim] keys this rgbdi-sim accepts, tried with the values the rows use (values: key ->
    one row's value): all together first (keys that only go together, such as the two IMU stream
    rates, are then judged together), and only when that is refused each key alone. A duration
    too short for any profile makes an accepted configuration fail later (exit 1), while a key
    the simulator does not know or a value out of its range fails on the configuration (exit 2,
    naming the key). Returns (accepted keys, {refused key: the simulator's message})."""
    os.makedirs(work_dir, exist_ok=True)

    def attempt(name, keys):
        ini = os.path.join(work_dir, f"probe_{name}.ini")
        with open(ini, "w") as f:
            f.write("[sim]\n" + "".join(f"{k} = {values[k]}\n" for k in keys))
        p = subprocess.run([sim, "--profile", "handheld", "--duration", "0.01", "--config", ini,
                            "--out", os.path.join(work_dir, "probe_out")],
                           capture_output=True, text=True)
        lines = p.stderr.strip().splitlines()
        return p.returncode != 2, (lines[-1].strip() if lines else "refused")

    keys = sorted(values)
    ok, _ = attempt("all", keys)
    accepted, refused = (keys, {}) if ok else ([], {})
    if not ok:
        for k in keys:
            ok, why = attempt(k, [k])
            if ok:
                accepted.append(k)
            else:
                refused[k] = why
    shutil.rmtree(os.path.join(work_dir, "probe_out"), ignore_errors=True)
    return accepted, refused


def sim_has_recorded_profile(sim):
    h = subprocess.run([sim, "--help"], capture_output=True, text=True)
    return "--recording" in h.stdout and "recorded" in h.stdout


def row_config_text(row, accepted_keys):
    keys = {k: v for k, v in row["sim_keys"].items() if k in accepted_keys}
    lines = ["; [sim] keys drawn by bench/suite for " + row["id"], "[sim]"]
    lines += [f"{k} = {v}" for k, v in keys.items()]
    return "\n".join(lines) + "\n", sorted(set(row["sim_keys"]) - set(keys))


def sim_arguments(row, config_path):
    a = ["--profile", row["profile"], "--seed", str(row["seed"]), "--fps", f"{row['fps']:g}"]
    if row["recording"]:
        a += ["--recording", row["recording"]]
    if row["duration_s"] is not None:
        a += ["--duration", f"{row['duration_s']:g}"]
    if row["speed_preset"]:
        a += ["--speed", row["speed_preset"]]
    if row["layout"] != "files":
        a += ["--embedded-images"]
    if row["layout"] == "bag":
        a += ["--bag"]
    a += row["extra_args"] + ["--config", config_path]
    return a


def entry_key(row, config_text, sim_version, convert_version):
    what = {"sim_args": sim_arguments(row, "ROW.ini"), "config": config_text,
            "sim_version": sim_version, "layout": row["layout"]}
    if row["layout"] == "bag":
        what["convert"] = [convert_version, "--camera-yaml"]
    if row["recording"] and os.path.isdir(row["recording"]):
        # a recording replaced in place regenerates its rows
        what["recording_files"] = sorted(
            (os.path.relpath(os.path.join(d, f), row["recording"]),
             os.path.getsize(os.path.join(d, f)), int(os.path.getmtime(os.path.join(d, f))))
            for d, _, files in os.walk(row["recording"]) for f in files)
    return hashlib.sha256(json.dumps(what, sort_keys=True).encode()).hexdigest()[:16]


def _timed(cmd, time_path, log_path):
    """Runs cmd under /usr/bin/time -v; returns (exit status, wall s, CPU s)."""
    with open(log_path, "w") as log:
        t0 = time.monotonic()
        rc = subprocess.run(["/usr/bin/time", "-v", "-o", time_path] + cmd, stdout=log,
                            stderr=subprocess.STDOUT).returncode
        wall = time.monotonic() - t0
    cpu = 0.0
    try:
        t = open(time_path).read()
        cpu = sum(float(re.search(p, t).group(1)) for p in
                  (r"User time \(seconds\): ([0-9.]+)", r"System time \(seconds\): ([0-9.]+)"))
    except (OSError, AttributeError):
        pass
    return rc, wall, cpu


class SequenceCache:
    def __init__(self, cache_dir, sim, convert, accepted_keys):
        self.dir = cache_dir
        self.sim, self.convert = sim, convert
        self.accepted = accepted_keys
        self.sim_version = tool_version(sim)
        self.convert_version = tool_version(convert)
        os.makedirs(cache_dir, exist_ok=True)
        self._lock = threading.Lock()

    def entry(self, row):
        text, _ = row_config_text(row, self.accepted)
        key = entry_key(row, text, self.sim_version, self.convert_version)
        return os.path.join(self.dir, f"{row['id']}-{key}")

    def ensure(self, row):
        """The entry of the row, generated when missing. Returns (path, generation info or None
        when cached). Raises RuntimeError naming the failing step and its log."""
        path = self.entry(row)
        if os.path.isfile(os.path.join(path, "generation.json")):
            os.utime(path)  # last use, for whoever prunes the cache
            return path, None
        tmp = f"{path}.tmp{os.getpid()}"
        shutil.rmtree(tmp, ignore_errors=True)
        os.makedirs(tmp)
        text, _ = row_config_text(row, self.accepted)
        cfg = os.path.join(tmp, "row.ini")
        with open(cfg, "w") as f:
            f.write(text)
        sim_dir = os.path.join(tmp, "sim")
        cmd = [self.sim] + sim_arguments(row, cfg) + ["--out", sim_dir]
        info = {"sim_command": cmd, "steps": {}}
        rc, wall, cpu = _timed(cmd, os.path.join(tmp, "sim.time"), os.path.join(tmp, "sim.log"))
        info["steps"]["rgbdi-sim"] = {"wall_s": wall, "cpu_s": cpu}
        if rc != 0:
            raise RuntimeError(f"rgbdi-sim failed (exit {rc}): see {tmp}/sim.log")
        for f in ("groundtruth.tum", "simulation.ini"):
            shutil.move(os.path.join(sim_dir, f), os.path.join(tmp, f))
        if row["layout"] == "bag":
            self._convert(tmp, sim_dir, info)
        else:
            shutil.move(os.path.join(sim_dir, "sequence.rawlog"),
                        os.path.join(tmp, "sequence.rawlog"))
            if row["layout"] == "files":  # the rawlog's images, found by its name
                shutil.move(os.path.join(sim_dir, "sequence_Images"),
                            os.path.join(tmp, "sequence_Images"))
            shutil.copy(os.path.join(sim_dir, "config.ini"), os.path.join(tmp, "slam.ini"))
        # the simulator's configuration for rgbdi-slam, also kept for bag rows (for reference)
        shutil.move(os.path.join(sim_dir, "config.ini"), os.path.join(tmp, "sim_config.ini"))
        shutil.rmtree(sim_dir)
        with open(os.path.join(tmp, "generation.json"), "w") as f:
            json.dump(info, f, indent=1)
        try:
            os.rename(tmp, path)
        except OSError:
            # another suite process finished the same entry first: keep theirs
            if not os.path.isfile(os.path.join(path, "generation.json")):
                raise
            shutil.rmtree(tmp, ignore_errors=True)
        return path, info

    def _convert(self, tmp, sim_dir, info):
        # rgbdi-sim --bag writes the bag's VINS-RGBD calibration next to it, as a user has it.
        yaml = os.path.join(sim_dir, "vins_config.yaml")
        if not os.path.isfile(yaml):
            raise RuntimeError(f"{sim_dir}: rgbdi-sim --bag wrote no vins_config.yaml "
                               "(an rgbdi-sim older than the suite?)")
        shutil.copy(yaml, os.path.join(tmp, "vins_config.yaml"))
        out = os.path.join(tmp, "sequence.rawlog")
        cmd = [self.convert, os.path.join(sim_dir, "sequence.bag"), "-o", out, "--camera-yaml",
               yaml, "--quiet"]
        info["convert_command"] = cmd
        rc, wall, cpu = _timed(cmd, os.path.join(tmp, "convert.time"),
                               os.path.join(tmp, "convert.log"))
        info["steps"]["rawlog-convert"] = {"wall_s": wall, "cpu_s": cpu}
        if rc != 0:
            raise RuntimeError(f"rawlog-convert failed (exit {rc}): see {tmp}/convert.log")
        os.rename(os.path.join(tmp, "sequence.ini"), os.path.join(tmp, "slam.ini"))

    def prune(self, max_bytes, in_use):
        with self._lock:
            return prune_cache(self.dir, max_bytes, in_use)


def prune_cache(cache_dir, max_bytes, in_use):
    """Deletes complete entries (with generation.json), least recently used (oldest mtime of
    the entry directory) first, until the cache holds at most max_bytes; never an entry in
    in_use. Returns the names deleted, in deletion order."""
    entries = []
    for name in os.listdir(cache_dir):
        path = os.path.join(cache_dir, name)
        if not os.path.isfile(os.path.join(path, "generation.json")):
            continue
        size = sum(os.path.getsize(os.path.join(d, f)) for d, _, files in os.walk(path)
                   for f in files)
        entries.append((os.path.getmtime(path), path, size))
    total = sum(e[2] for e in entries)
    deleted = []
    for _, path, size in sorted(entries):
        if total <= max_bytes:
            break
        if path in in_use:
            continue
        shutil.rmtree(path, ignore_errors=True)
        total -= size
        deleted.append(os.path.basename(path))
    return deleted
