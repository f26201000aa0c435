"""Statistics of the suite: per-condition summaries and the paired comparison of two labels.

Pure functions on plain lists and dicts (no I/O), so that tests/bench can check them with known
answers. A metric's "worst" is its maximum, or its minimum for metrics where more is better
(coverage, x real time).
"""
import math

# Metrics where a larger value is better: their worst is the minimum.
HIGHER_IS_BETTER = {"coverage", "x_real_time"}


def median(values):
    """Median of a non-empty list (mean of the two middle values for an even count)."""
    if not values:
        raise ValueError("median of no values")
    s = sorted(values)
    n = len(s)
    mid = n // 2
    return s[mid] if n % 2 else 0.5 * (s[mid - 1] + s[mid])


def percentile(values, q):
    """q-th percentile (0-100) with linear interpolation between order statistics, the
    definition numpy.percentile uses by default: position (n - 1) q / 100 in the sorted list."""
    if not values:
        raise ValueError("percentile of no values")
    if not 0.0 <= q <= 100.0:
        raise ValueError(f"percentile {q} outside 0-100")
    s = sorted(values)
    pos = (len(s) - 1) * q / 100.0
    lo = math.floor(pos)
    hi = min(lo + 1, len(s) - 1)
    return s[lo] + (s[hi] - s[lo]) * (pos - lo)


def worst(values, metric):
    return min(values) if metric in HIGHER_IS_BETTER else max(values)


def spread(values, metric):
    """median, 90th percentile "towards worse" and worst of the values that are numbers;
    None when there are none. For higher-is-better metrics the 90th percentile towards worse is
    the 10th percentile."""
    v = [x for x in values if isinstance(x, (int, float)) and math.isfinite(x)]
    if not v:
        return None
    q = 10.0 if metric in HIGHER_IS_BETTER else 90.0
    return {"median": median(v), "p90": percentile(v, q), "worst": worst(v, metric), "n": len(v)}


def summarise(results, metrics):
    """results: list of per-run dicts with 'condition', 'status' ('ok' or a failure reason) and
    the metrics. Returns {condition: {'runs', 'failed' [ids], metric: spread of the runs that
    did not fail}} in the order conditions first appear."""
    out = {}
    for r in results:
        c = out.setdefault(r["condition"], {"runs": 0, "failed": [], "_ok": []})
        c["runs"] += 1
        if r["status"] == "ok":
            c["_ok"].append(r)
        else:
            c["failed"].append(r["id"])
    for c in out.values():
        ok = c.pop("_ok")
        for m in metrics:
            c[m] = spread([r.get(m) for r in ok], m)
    return out


def ratio(new, old):
    """new / old, None when either is missing or old is not positive."""
    if not isinstance(new, (int, float)) or not isinstance(old, (int, float)):
        return None
    if not old > 0.0 or not math.isfinite(new) or not math.isfinite(old):
        return None
    return new / old


def pair_runs(old_results, new_results, metrics):
    """One row per sequence id present in both: status of each and new/old ratio per metric
    (None when a run failed). Ids in only one label are returned separately."""
    old = {r["id"]: r for r in old_results}
    new = {r["id"]: r for r in new_results}
    pairs = []
    for rid in [r["id"] for r in old_results if r["id"] in new]:
        o, n = old[rid], new[rid]
        both_ok = o["status"] == "ok" and n["status"] == "ok"
        pairs.append({"id": rid, "condition": o["condition"], "old_status": o["status"],
                      "new_status": n["status"],
                      "ratios": {m: ratio(n.get(m), o.get(m)) if both_ok else None
                                 for m in metrics}})
    only_old = [rid for rid in old if rid not in new]
    only_new = [rid for rid in new if rid not in old]
    return pairs, only_old, only_new


def ratio_summary(pairs, metrics, worse_ratio, much_worse_ratio):
    """Over the pairs: per metric the median and worst (largest) ratio and how many sequences
    got worse by more than worse_ratio and much_worse_ratio; and how many runs newly failed or
    were fixed."""
    s = {"sequences": len(pairs),
         "new_failures": [p["id"] for p in pairs
                          if p["old_status"] == "ok" and p["new_status"] != "ok"],
         "fixed": [p["id"] for p in pairs if p["old_status"] != "ok" and p["new_status"] == "ok"],
         "metrics": {}}
    for m in metrics:
        v = [p["ratios"][m] for p in pairs if p["ratios"].get(m) is not None]
        s["metrics"][m] = None if not v else {
            "n": len(v), "median": median(v), "worst": max(v),
            "worse": sum(1 for x in v if x > worse_ratio),
            "much_worse": sum(1 for x in v if x > much_worse_ratio)}
    return s


def verdict(summary, accuracy_metrics, cpu_metric, rules):
    """One line: 'worse', 'better' or 'no clear change' in accuracy, with the reason, and the
    CPU change. rules: median_tolerance, much_worse_ratio, max_much_worse_fraction.

    worse:  more runs newly fail than are fixed, or the median ratio of an accuracy metric is
            above 1 + median_tolerance, or more than max_much_worse_fraction of the sequences got
            worse than much_worse_ratio in an accuracy metric;
    better: not worse, and more runs fixed than newly failing or the median ratio of an accuracy
            metric is below 1 - median_tolerance;
    otherwise no clear change."""
    tol = rules["median_tolerance"]
    reasons_worse, reasons_better = [], []
    nf, fx = len(summary["new_failures"]), len(summary["fixed"])
    if nf > fx:
        reasons_worse.append(f"{nf} runs newly fail, {fx} fixed")
    elif fx > nf:
        reasons_better.append(f"{fx} runs fixed, {nf} newly fail")
    for m in accuracy_metrics:
        s = summary["metrics"].get(m)
        if s is None:
            continue
        if s["median"] > 1.0 + tol:
            reasons_worse.append(f"{m} median ratio {s['median']:.3f} > {1.0 + tol:.2f}")
        elif s["median"] < 1.0 - tol:
            reasons_better.append(f"{m} median ratio {s['median']:.3f} < {1.0 - tol:.2f}")
        limit = rules["max_much_worse_fraction"] * s["n"]
        if s["much_worse"] > limit:
            reasons_worse.append(f"{m}: {s['much_worse']} of {s['n']} sequences worse than "
                                 f"x{rules['much_worse_ratio']:.2f} (allowed {limit:.1f})")
    if reasons_worse:
        word, why = "worse", reasons_worse
    elif reasons_better:
        word, why = "better", reasons_better
    else:
        word, why = "no clear change", [f"accuracy median ratios within 1 +- {tol:.2f}"]
    c = summary["metrics"].get(cpu_metric)
    cpu = "CPU: no pairs" if c is None else f"CPU median ratio {c['median']:.3f}"
    return f"verdict: {word} ({'; '.join(why)}); {cpu}"
