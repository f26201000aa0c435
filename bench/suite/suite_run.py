"""One rgbdi-slam run of a row on its cached sequence, and the figures the suite collects from it.

CPU = user + sys of the whole process from /usr/bin/time -v (as scripts/bench-cpu.sh); peak RSS
from the same. Accuracy from the summary.json that rgbdi-slam --gt writes: ATE RMSE of the
odometry, online and final trajectories (position + yaw alignment), the final trajectory's Sim(3)
scale; coverage of the final trajectory.
"""
import json
import os
import re
import shutil
import subprocess
import time

METRICS = ["ate_odometry", "ate_online", "ate_final", "scale_error", "coverage", "resets",
           "first_pose_s", "cpu_per_data_s", "x_real_time", "peak_rss_mb", "keyframes_per_frame",
           "loops_accepted", "cpu_s"]


def parse_time_v(text):
    """(CPU s = user + sys, wall s, peak RSS MB) from /usr/bin/time -v output."""
    def num(pat):
        m = re.search(pat, text)
        if not m:
            raise ValueError(f"/usr/bin/time output has no '{pat}'")
        return float(m.group(1))
    cpu = num(r"User time \(seconds\): ([0-9.]+)") + num(r"System time \(seconds\): ([0-9.]+)")
    w = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([0-9.]+)",
                  text)
    if not w:
        raise ValueError("/usr/bin/time output has no wall clock time")
    wall = int(w.group(1) or 0) * 3600 + int(w.group(2)) * 60 + float(w.group(3))
    rss_mb = num(r"Maximum resident set size \(kbytes\): (\d+)") / 1024.0
    return cpu, wall, rss_mb


def metrics_from_summary(s, cpu, wall, rss_mb):
    """The suite's figures of one run; status 'ok' or why the run counts as failed."""
    m = {"cpu_s": cpu, "wall_s": wall, "peak_rss_mb": rss_mb}
    frames = s.get("frames") or 0
    data_s = s.get("stream_duration_s") or 0.0
    m["frames"] = frames
    m["data_s"] = data_s
    m["cpu_per_data_s"] = cpu / data_s if data_s > 0 else None
    m["x_real_time"] = data_s / wall if wall > 0 else None
    m["resets"] = s.get("resets")
    m["first_pose_s"] = s.get("first_pose_time_s")
    m["keyframes_per_frame"] = s.get("keyframes", 0) / frames if frames else None
    m["loops_accepted"] = (s.get("loop") or {}).get("accepted", 0)
    ev = s.get("evaluation")
    if ev:
        m["ate_final"] = ev.get("ate_rmse")
        m["coverage"] = ev.get("coverage")
        m["ate_online"] = (s.get("evaluation_online") or {}).get("ate_rmse")
        m["ate_odometry"] = (s.get("evaluation_odometry") or {}).get("ate_rmse")
        scale = (s.get("evaluation_sim3") or {}).get("scale")
        m["scale_error"] = abs(scale - 1.0) if isinstance(scale, (int, float)) else None
    if s.get("interrupted"):
        m["status"] = "interrupted"
    elif s.get("read_error"):
        m["status"] = "read error: " + str(s["read_error"])
    elif m["first_pose_s"] is None:
        m["status"] = "never initialised"
    elif not ev or m.get("ate_final") is None:
        m["status"] = "no evaluation: " + str(s.get("evaluation_error", "no poses to evaluate"))
    else:
        m["status"] = "ok"
    return m


def run_slam(slam, row, entry, runs_dir, extra_args=(), extra_config=None):
    """Runs rgbdi-slam on the row's sequence into runs_dir/<id>/; returns the row's result.
    extra_config: INI text appended to the sequence's configuration (a candidate default judged
    without a rebuild); the run's configuration is then runs_dir/<id>.ini."""
    out = os.path.join(runs_dir, row["id"])
    shutil.rmtree(out, ignore_errors=True)
    config = os.path.join(entry, "slam.ini")
    if extra_config:
        with open(config) as f:
            text = f.read()
        config = out + ".ini"
        with open(config, "w") as f:
            f.write(text + "\n" + extra_config)
    cmd = [slam, "--input", os.path.join(entry, "sequence.rawlog"),
           "--config", config,
           "--gt", os.path.join(entry, "groundtruth.tum"), "--out", out, "--quiet",
           *extra_args]
    result = {k: row[k] for k in ("id", "condition", "profile", "seed", "rate", "fps", "layout",
                                  "duration_s")}
    result["sequence"] = entry
    t0 = time.monotonic()
    with open(out + ".log", "w") as log:
        rc = subprocess.run(["/usr/bin/time", "-v", "-o", out + ".time"] + cmd, stdout=log,
                            stderr=subprocess.STDOUT).returncode
    result["exit_status"] = rc
    try:
        cpu, wall, rss = parse_time_v(open(out + ".time").read())
    except (OSError, ValueError) as e:
        cpu, wall, rss = None, time.monotonic() - t0, None
        result["status"] = f"no timing ({e})"
    summary_path = os.path.join(out, "summary.json")
    if rc != 0:
        result["status"] = f"rgbdi-slam exit {rc}: see {out}.log"
    elif not os.path.isfile(summary_path):
        result["status"] = f"no summary.json: see {out}.log"
    elif cpu is not None:
        try:
            with open(summary_path) as f:
                result.update(metrics_from_summary(json.load(f), cpu, wall, rss))
        except ValueError as e:
            result["status"] = f"unreadable summary.json ({e})"
    result.setdefault("status", "failed")
    return result
