#!/usr/bin/python3
"""rgbdi benchmark suite (doc/benchmark-suite.md): plan | run | report | compare.

  suite.py plan    [--tier quick|full]
  suite.py run     [--tier T] [--label L] [--build DIR] [--sim-build DIR] [--jobs 1|2]
                   [--only REGEX] [--duration S] [--resume]
  suite.py report  LABEL
  suite.py compare OLD_LABEL NEW_LABEL

Paths: SUITE_OUT (default out/suite): runs in SUITE_OUT/runs/<label>/; SUITE_CACHE (default
SUITE_OUT/cache): generated sequences; SUITE_CACHE_MAX_GB: bound of the cache (LRU eviction).
"""
import argparse
import concurrent.futures
import datetime
import json
import os
import re
import signal
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import suite_cache  # noqa: E402
import suite_journal  # noqa: E402
import suite_report  # noqa: E402
import suite_rows  # noqa: E402
import suite_run  # noqa: E402
import suite_stats  # noqa: E402

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
# cache bytes per 640 x 480 frame: raw colour + 16-bit depth inside a rawlog (bag and rawlog
# layouts), PNG + compressed range files beside it (files layout)
BYTES_PER_FRAME = {"bag": 1.5e6, "rawlog": 1.5e6, "files": 0.5e6}
# while a bag row is generated the simulator's bag and rawlog and the converted rawlog coexist
GENERATION_PEAK_FACTOR = {"bag": 3.0, "rawlog": 1.0, "files": 1.0}
# [s] assumed for a hybrid row, whose recording's length the plan does not know (the suite's
# recordings are 60-90 s)
HYBRID_DURATION_BOUND_S = 120.0
COMPARE_METRICS = ["ate_odometry", "ate_online", "ate_final", "cpu_s"]
ACCURACY_METRICS = ["ate_odometry", "ate_online", "ate_final"]
TITLES = {"ate_odometry": "ATE odometry", "ate_online": "ATE online", "ate_final": "ATE final",
          "cpu_s": "CPU"}


def out_dir():
    return os.environ.get("SUITE_OUT", os.path.join(REPO, "out", "suite"))


def cache_dir():
    return os.environ.get("SUITE_CACHE", os.path.join(out_dir(), "cache"))


def label_dir(label):
    if not re.fullmatch(r"[A-Za-z0-9._-]+", label):
        raise SystemExit(f"suite: label '{label}' must be letters, digits, '.', '_' or '-'")
    return os.path.join(out_dir(), "runs", label)


def load_rows(args):
    d = suite_rows.load_definition(args.suite)
    rows = suite_rows.tier_rows(d, args.tier, REPO)
    if getattr(args, "only", None):
        rows = [r for r in rows if re.search(args.only, r["id"])]
    if getattr(args, "duration", None):
        for r in rows:
            if r["duration_s"] is not None:
                r["duration_s"] = args.duration
    return d, rows


def frames_of(definition, row):
    d = suite_rows.planned_duration_s(definition, row)
    return None if d is None else int(d * row["fps"])


def generation_peak_bytes(definition, row):
    """Disk a row's generation needs at its peak (an upper bound for hybrid rows)."""
    d = suite_rows.planned_duration_s(definition, row) or HYBRID_DURATION_BOUND_S
    return d * row["fps"] * BYTES_PER_FRAME[row["layout"]] * GENERATION_PEAK_FACTOR[row["layout"]]


def cmd_plan(args):
    d, rows = load_rows(args)
    frames = sum(frames_of(d, r) or 0 for r in rows)
    cache_bytes = sum((frames_of(d, r) or 0) * BYTES_PER_FRAME[r["layout"]] for r in rows)
    by_cond = {}
    for r in rows:
        by_cond.setdefault(r["condition"], []).append(r)
    print(f"tier {args.tier}: {len(rows)} rows, {frames} frames of simulated profiles "
          f"(~{cache_bytes / 1e9:.1f} GB in the cache; hybrid rows: the "
          "recording's length)")
    for c, rs in by_cond.items():
        print(f"  {c}: {len(rs)} rows, seeds {', '.join(str(r['seed']) for r in rs)}")
    for r in rows[:1] + [r for r in rows if r["id"].startswith("hard_")][:1]:
        print(f"  example {r['id']}: [sim] {r['sim_keys']} speed preset {r['speed_preset']} "
              f"extra {r['extra_args']}")


def _pool(jobs, fn, items, stop=None):
    """fn over items, `jobs` at a time; on Ctrl-C (or SIGTERM) `stop` is set, so that no new item
    starts, the running ones are waited for, and KeyboardInterrupt goes on."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as ex:
        try:
            return list(ex.map(fn, items))
        except KeyboardInterrupt:
            if stop is not None:
                stop.set()
            print("suite: interrupted; waiting for the running rows to end (they are run again "
                  "on --resume)", file=sys.stderr, flush=True)
            raise


def cmd_run(args):
    if args.jobs not in (1, 2):
        raise SystemExit("suite: --jobs is 1 or 2 (a 2-core machine)")
    d, rows = load_rows(args)
    if not rows:
        raise SystemExit("suite: no row matches")
    sim_build = args.sim_build
    tools = {"sim": os.path.join(sim_build, "bin", "rgbdi-sim"),
             "convert": os.path.join(sim_build, "bin", "rawlog-convert"),
             "slam": os.path.join(args.build, "bin", "rgbdi-slam")}
    for name, path in tools.items():
        if not os.access(path, os.X_OK):
            raise SystemExit(f"suite: {path} not found (build it first)")
    out = label_dir(args.label)
    os.makedirs(out, exist_ok=True)
    extra_config = None
    if args.extra_config:
        with open(args.extra_config) as f:
            extra_config = f.read()
    t_start = time.monotonic()
    wanted = {}
    for r in rows:
        for k, v in r["sim_keys"].items():
            wanted.setdefault(k, v)
    accepted, refused = suite_cache.probe_sim_keys(tools["sim"], os.path.join(out, "probe"),
                                                   wanted)
    cache = suite_cache.SequenceCache(cache_dir(), tools["sim"], tools["convert"], accepted)
    has_recorded = suite_cache.sim_has_recorded_profile(tools["sim"])
    skipped, todo = [], []
    for r in rows:
        if r["recording"] and not has_recorded:
            skipped.append((r["id"], "this rgbdi-sim has no --profile recorded --recording"))
        elif r["recording"] and not os.path.isdir(r["recording"]):
            skipped.append((r["id"], f"recording {r['recording']} not found"))
        else:
            todo.append(r)
    setup = {"tier": args.tier, "only": args.only, "duration_override_s": args.duration,
             "extra_config": extra_config, "rgbdi_slam": os.path.abspath(tools["slam"]),
             "rgbdi_sim": os.path.abspath(tools["sim"]), "sim_version": cache.sim_version,
             "rows": [r["id"] for r in todo]}
    try:
        journal = suite_journal.Journal(out, setup, args.resume)
    except (suite_journal.JournalError, OSError) as e:
        raise SystemExit(f"suite: {e}")
    if journal.rows:
        print(f"suite: resuming {args.label}: {len(journal.rows)} of {len(todo)} rows done in "
              f"{len(journal.sessions)} earlier sessions", file=sys.stderr, flush=True)
    pending = [r for r in todo if r["id"] not in journal.rows]
    stop = threading.Event()  # Ctrl-C / SIGTERM: no new row starts, the running ones are dropped

    def generate(r):
        if stop.is_set():
            return r["id"], None, None, "interrupted"
        try:
            path, info = cache.ensure(r)
            if info:
                print(f"suite: generated {r['id']} in "
                      f"{sum(s['wall_s'] for s in info['steps'].values()):.0f} s",
                      file=sys.stderr, flush=True)
                journal.record_generation(r["id"], info["steps"])
            return r["id"], path, info, None
        except (RuntimeError, OSError, ValueError) as e:
            print(f"suite: {r['id']}: {e}", file=sys.stderr, flush=True)
            return r["id"], None, None, str(e)

    def run(r):
        path, _, err = gen[r["id"]]
        if stop.is_set():
            return None
        if err:
            res = {k: r[k] for k in ("id", "condition", "profile", "seed", "rate", "fps",
                                     "layout", "duration_s")}
            res["status"] = "sequence generation failed: " + err
        else:
            res = suite_run.run_slam(tools["slam"], r, path, out, extra_config=extra_config)
        if stop.is_set() or res.get("exit_status") in (130, -2, -15):
            return None  # stopped with the suite (Ctrl-C, SIGTERM): run again on --resume
        print(f"suite: {r['id']}: {res['status']}"
              + (f", ATE final {res['ate_final']:.4f} m" if res["status"] == "ok" else ""),
              file=sys.stderr, flush=True)
        journal.record_row(res)
        return res

    gen = {}
    cap_gb = os.environ.get("SUITE_CACHE_MAX_GB")
    pruned = []
    interrupted = False
    t_run = time.monotonic()
    gen_wall_now = None
    try:
        if cap_gb is None:
            # all sequences first, then the runs: the runs' wall time is not mixed with generation
            t_gen = time.monotonic()
            gen = {rid: (path, info, err)
                   for rid, path, info, err in _pool(args.jobs, generate, pending, stop)}
            gen_wall_now = time.monotonic() - t_gen
            t_run = time.monotonic()
            _pool(args.jobs, run, pending, stop)
        else:
            # a bounded cache: generate, run, then evict least recently used entries of other rows
            try:
                cap_bytes = float(cap_gb) * 1e9
            except ValueError:
                raise SystemExit(f"suite: SUITE_CACHE_MAX_GB '{cap_gb}' is not a number")
            in_use, lock = set(), threading.Lock()
            reserved = {}  # row id -> disk its generation may still need [bytes]

            def gen_and_run(r):
                if stop.is_set():
                    return None
                entry = cache.entry(r)
                with lock:
                    in_use.add(entry)
                    # room for what the generations under way will write, before they write it
                    reserved[r["id"]] = generation_peak_bytes(d, r)
                    keep = set(in_use)
                    room = cap_bytes - sum(reserved.values())
                pruned.extend(cache.prune(max(room, 0.0), keep))
                rid, path, info, err = generate(r)
                with lock:
                    reserved.pop(r["id"], None)
                gen[rid] = (path, info, err)
                res = run(r)
                with lock:
                    in_use.discard(entry)
                    keep = set(in_use)
                pruned.extend(cache.prune(cap_bytes, keep))
                return res

            _pool(args.jobs, gen_and_run, pending, stop)
    except KeyboardInterrupt:
        interrupted = True
    run_wall_now = time.monotonic() - t_run
    session_wall = time.monotonic() - t_start
    journal.record_session(session_wall, len(journal.rows))
    results = [journal.rows[r["id"]] for r in todo if r["id"] in journal.rows]
    steps = [s for rid, st in journal.generation.items() for s in st.values()]
    gen_cpu = sum(s["cpu_s"] for s in steps)
    if cap_gb is None and not journal.sessions[:-1] and gen_wall_now is not None:
        gen_wall, run_wall = gen_wall_now, run_wall_now
    else:
        # bounded cache or several sessions: generation wall = its summed wall / jobs, and the
        # runs' wall is every session's wall (which includes generation when bounded)
        gen_wall = sum(s["wall_s"] for s in steps) / args.jobs
        run_wall = sum(journal.sessions)
    generated = len(journal.generation)
    header = {
        "tier": args.tier, "label": args.label, "date_utc":
            datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M"),
        "rgbdi_slam": os.path.abspath(tools["slam"]), "rgbdi_sim": os.path.abspath(tools["sim"]),
        "sim_version": cache.sim_version, "rows": len(rows), "runs": len(results),
        "sim_keys_accepted": accepted, "sim_keys_refused": refused, "skipped": skipped,
        "generated": generated, "generation_wall_s": gen_wall, "generation_cpu_s": gen_cpu,
        "runs_wall_s": run_wall, "total_wall_s": sum(journal.sessions), "jobs": args.jobs,
        "only": args.only, "duration_override_s": args.duration, "cache_max_gb": cap_gb,
        "cache_entries_pruned": len(pruned), "extra_config": extra_config,
        "sessions": len(journal.sessions),
        "rows_not_run": [r["id"] for r in todo if r["id"] not in journal.rows]}
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump({"header": header, "results": results}, f, indent=1)
    suite_report.write_csv(results, os.path.join(out, "results.csv"),
                           ["id", "condition", "status"] + suite_run.METRICS +
                           ["wall_s", "frames", "data_s", "exit_status", "sequence"])
    text = report_text(header, results)
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write(text)
    print(text)
    if interrupted or header["rows_not_run"]:
        print(f"suite: {len(header['rows_not_run'])} rows not run; 'suite.sh run --resume' with the "
              "same options runs them", file=sys.stderr)
        return 130 if interrupted else 1
    return 0 if all(r["status"] == "ok" for r in results) else 1


def report_text(h, results):
    lines = [f"# Suite {h['tier']} tier, label {h['label']} ({h['date_utc']} UTC)", "",
             f"rgbdi-slam {h['rgbdi_slam']}; sequences by {h['rgbdi_sim']} ({h['sim_version']})."]
    if h.get("only"):
        lines.append(f"Subset: the rows whose id matches '{h['only']}'.")
    if h.get("duration_override_s"):
        lines.append(f"Every simulated row shortened to {h['duration_override_s']:g} s.")
    if h.get("extra_config"):
        lines.append("Every run's configuration had this appended: "
                     + " / ".join(l.strip() for l in h["extra_config"].splitlines() if l.strip())
                     + ".")
    if h["sim_keys_refused"]:
        lines.append("World/motion keys this rgbdi-sim does not accept, run WITHOUT them (rows "
                     "differ only by seed noise/textures and speed): "
                     + ", ".join(sorted(h["sim_keys_refused"])) + ".")
    lines.append("World/motion keys applied: " + (", ".join(h["sim_keys_accepted"]) or "none")
                 + ".")
    for rid, why in h["skipped"]:
        lines.append(f"Skipped {rid}: {why}.")
    if h.get("cache_max_gb") is not None:
        lines.append(f"Cache bounded to {h['cache_max_gb']} GB (SUITE_CACHE_MAX_GB): each sequence "
                     "generated just before its run, so the runs' wall time includes generation "
                     "(generation wall = its summed wall / jobs); "
                     f"{h['cache_entries_pruned']} entries evicted.")
    if h.get("sessions", 1) > 1:
        lines.append(f"Run in {h['sessions']} sessions (interrupted and resumed with --resume): "
                     "the walls below are the sessions' sums.")
    if h.get("rows_not_run"):
        lines.append(f"Not run yet ({len(h['rows_not_run'])} rows: interrupted): "
                     + ", ".join(h["rows_not_run"]) + ".")
    lines.append(f"{h['runs']} runs ({h['jobs']} at a time): wall {h['runs_wall_s'] / 60:.1f} min."
                 f" Generation of {h['generated']} sequences: wall "
                 f"{h['generation_wall_s'] / 60:.1f} min, CPU {h['generation_cpu_s'] / 60:.1f} "
                 f"min. Total wall {h['total_wall_s'] / 60:.1f} min.")
    lines += ["", "Per condition, median / 90th percentile / worst over the runs that did not "
              "fail:", "", suite_report.condition_table(results), "",
              suite_report.failure_list(results), ""]
    return "\n".join(lines)


def load_results(label):
    path = os.path.join(label_dir(label), "results.json")
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        raise SystemExit(f"suite: {path}: {e.strerror} (run the suite with --label {label})")
    except ValueError as e:
        raise SystemExit(f"suite: {path}: not a results file ({e})")


def cmd_report(args):
    r = load_results(args.label)
    print(report_text(r["header"], r["results"]))


def compare_text(old, new, rules):
    pairs, only_old, only_new = suite_stats.pair_runs(old["results"], new["results"],
                                                      COMPARE_METRICS)
    by_cond = {}
    for p in pairs:
        by_cond.setdefault(p["condition"], []).append(p)
    per_cond = {c: suite_stats.ratio_summary(ps, COMPARE_METRICS, rules["worse_ratio"],
                                             rules["much_worse_ratio"])
                for c, ps in by_cond.items()}
    overall = suite_stats.ratio_summary(pairs, COMPARE_METRICS, rules["worse_ratio"],
                                        rules["much_worse_ratio"])
    ho, hn = old["header"], new["header"]
    lines = [f"# Paired comparison: {hn['label']} / {ho['label']}", "",
             f"old: {ho['rgbdi_slam']} ({ho['tier']} tier, {ho['date_utc']} UTC)",
             f"new: {hn['rgbdi_slam']} ({hn['tier']} tier, {hn['date_utc']} UTC)",
             f"{len(pairs)} sequences in both."]
    if only_old or only_new:
        lines.append(f"Only in old: {', '.join(only_old) or 'none'}; only in new: "
                     f"{', '.join(only_new) or 'none'} (not compared).")
    lines += ["", suite_report.compare_tables(pairs, per_cond, overall, COMPARE_METRICS, TITLES),
              ""]
    if overall["new_failures"]:
        lines.append("Newly failing: " + ", ".join(overall["new_failures"]))
    if overall["fixed"]:
        lines.append("Fixed: " + ", ".join(overall["fixed"]))
    lines.append(suite_stats.verdict(overall, ACCURACY_METRICS, "cpu_s", rules))
    return "\n".join(lines) + "\n"


def cmd_compare(args):
    d = suite_rows.load_definition(args.suite)
    text = compare_text(load_results(args.old), load_results(args.new), d["compare"])
    path = os.path.join(out_dir(), "runs", f"compare_{args.old}_{args.new}.md")
    with open(path, "w") as f:
        f.write(text)
    print(text)


def main(argv):
    p = argparse.ArgumentParser(prog="suite", description=__doc__.splitlines()[0])
    p.add_argument("--suite", default=os.path.join(REPO, "bench", "suite", "suite.json"))
    sub = p.add_subparsers(dest="command", required=True)
    pl = sub.add_parser("plan", help="list the rows of a tier")
    pl.add_argument("--tier", default="quick")
    r = sub.add_parser("run", help="generate (cached) and run a tier")
    r.add_argument("--tier", default="quick")
    r.add_argument("--label", default="current")
    r.add_argument("--build", default=os.path.join(REPO, "build"),
                   help="build directory of the rgbdi-slam to measure")
    r.add_argument("--sim-build", default=os.path.join(REPO, "build"),
                   help="build directory of rgbdi-sim and rawlog-convert (default: this tree's "
                   "build, whatever --build is, so that two builds run on the same sequences)")
    r.add_argument("--jobs", type=int, default=2)
    r.add_argument("--extra-config", default=None,
                   help="INI text appended to every run's configuration (a candidate default)")
    r.add_argument("--only", default=None, help="only rows whose id matches this regex")
    r.add_argument("--duration", type=float, default=None,
                   help="override the rows' duration [s] (quick checks of the machinery)")
    r.add_argument("--resume", action="store_true",
                   help="run only the rows the label's journal does not hold (an interrupted "
                   "run with the same options)")
    rp = sub.add_parser("report", help="print the tables of a label again")
    rp.add_argument("label")
    c = sub.add_parser("compare", help="paired comparison of two labels")
    c.add_argument("old")
    c.add_argument("new")
    a = p.parse_args(argv)
    return {"plan": cmd_plan, "run": cmd_run, "report": cmd_report,
            "compare": cmd_compare}[a.command](a) or 0


def _sigterm(signum, frame):
    raise KeyboardInterrupt


if __name__ == "__main__":
    signal.signal(signal.SIGTERM, _sigterm)
    try:
        sys.exit(main(sys.argv[1:]))
    except ValueError as e:  # a bad suite file, named with the entry
        sys.exit(f"suite: {e}")
