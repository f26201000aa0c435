"""Markdown tables and CSV of the suite's results and of a paired comparison."""
import csv

from suite_stats import summarise

# (metric, column title, format) of the per-condition table
COLUMNS = [
    ("ate_odometry", "ATE odometry [m]", "{:.4f}"),
    ("ate_online", "ATE online [m]", "{:.4f}"),
    ("ate_final", "ATE final [m]", "{:.4f}"),
    ("scale_error", "scale error", "{:.5f}"),
    ("coverage", "coverage", "{:.3f}"),
    ("resets", "resets", "{:g}"),
    ("first_pose_s", "first pose [s]", "{:.2f}"),
    ("cpu_per_data_s", "CPU-s per s", "{:.3f}"),
    ("x_real_time", "x real time", "{:.2f}"),
    ("peak_rss_mb", "peak RSS [MB]", "{:.0f}"),
    ("keyframes_per_frame", "keyframes per frame", "{:.3f}"),
    ("loops_accepted", "loops", "{:g}"),
]


def _cell(sp, fmt):
    if sp is None:
        return "-"
    return " / ".join(fmt.format(sp[k]) for k in ("median", "p90", "worst"))


def condition_table(results):
    """One row per condition: runs, failures, and median / p90 / worst of each metric over the
    runs that did not fail."""
    s = summarise(results, [c[0] for c in COLUMNS])
    head = ["condition", "runs", "failed"] + [c[1] for c in COLUMNS]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for cond, c in s.items():
        cells = [cond, str(c["runs"]), str(len(c["failed"]))]
        cells += [_cell(c[m], fmt) for m, _, fmt in COLUMNS]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def failure_list(results):
    failed = [r for r in results if r["status"] != "ok"]
    if not failed:
        return "No run failed."
    return "\n".join([f"Failed runs ({len(failed)}):"] +
                     [f"- {r['id']}: {r['status']}" for r in failed])


def write_csv(results, path, fields):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in results:
            w.writerow({k: r.get(k) for k in fields})


def _ratio_cells(s, metrics):
    cells = []
    for m in metrics:
        x = s["metrics"].get(m)
        cells.append("-" if x is None else
                     f"{x['median']:.3f} / {x['worst']:.3f} / {x['worse']} / {x['much_worse']}")
    return cells


def compare_tables(pairs, per_condition, overall, metrics, titles):
    """Per-sequence ratios, then per condition and overall: median / worst ratio / sequences
    worse than the worse ratio / than the much-worse ratio."""
    out = ["| sequence | " + " | ".join(titles[m] + " new/old" for m in metrics) + " |",
           "|---|" + "---|" * len(metrics)]
    for p in pairs:
        if p["old_status"] != "ok" or p["new_status"] != "ok":
            cells = [f"old {p['old_status']}; new {p['new_status']}"] + ["-"] * (len(metrics) - 1)
        else:
            cells = ["-" if p["ratios"][m] is None else f"{p['ratios'][m]:.3f}" for m in metrics]
        out.append(f"| {p['id']} | " + " | ".join(cells) + " |")
    out += ["", "Per condition: median ratio / worst ratio / sequences worse than the 'worse' "
            "ratio / worse than the 'much worse' ratio (suite.json 'compare').", "",
            "| condition | sequences | newly failed | fixed | " +
            " | ".join(titles[m] for m in metrics) + " |",
            "|---|---|---|---|" + "---|" * len(metrics)]
    for cond, s in list(per_condition.items()) + [("**all**", overall)]:
        out.append(f"| {cond} | {s['sequences']} | {len(s['new_failures'])} | {len(s['fixed'])} | "
                   + " | ".join(_ratio_cells(s, metrics)) + " |")
    return "\n".join(out)
