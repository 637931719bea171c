#!/usr/bin/env python3
"""Candidate failure statistics of `plucker vio` runs (issue 26 part 2b, docs/results/vio.md).

Usage: scripts/vio_failure_stats.py OUT_DIR [OUT_DIR ...]  (the folders of
`VIO_KEEP_JSON=1 scripts/vio_robustness.sh`: runs.tsv and json/*.json.gz), or
       scripts/vio_failure_stats.py --json RUN.json [RUN.json ...]  (single runs, no ATE).

Per run: statistics of its --json that need no ground truth; then, per statistic, the healthy
runs' (ATE < 0.2 m) largest against the failed runs' (ATE > 0.5 m) smallest.
"""
import csv
import gzip
import json
import math
import os
import statistics
import sys

CHI2_15_P99 = 30.58  # the 0.99 quantile of chi2 with 15 degrees of freedom


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def quantile(xs, q):
    if not xs:
        return 0.0
    s = sorted(xs)
    return s[min(len(s) - 1, int(q * len(s)))]


def run_stats(j):
    frames = [f for f in j["frames"] if "state" in f]
    kf = [f for f in frames if f.get("keyframe")]
    out = {}
    if not kf:
        return out
    ba = [f["state"]["accel_bias"] for f in kf]
    bg = [f["state"]["gyro_bias"] for f in kf]
    t = [f["time"] for f in kf]
    last_ba, last_bg = ba[-1], bg[-1]
    out["ba_max_norm"] = max(norm(b) for b in ba)
    out["ba_from_final"] = max(norm(sub(b, last_ba)) for b in ba)
    out["ba_from_first"] = max(norm(sub(b, ba[0])) for b in ba)
    out["bg_from_final"] = max(norm(sub(b, last_bg)) for b in bg)
    out["bg_max_norm"] = max(norm(b) for b in bg)
    # The largest change of b_a over any keyframe pair 1 s or more apart, per second.
    rate = 0.0
    for i in range(len(kf)):
        for k in range(i + 1, len(kf)):
            if t[k] - t[i] >= 1.0:
                rate = max(rate, norm(sub(ba[k], ba[i])) / (t[k] - t[i]))
                break
    out["ba_rate_1s"] = rate
    chi2 = [f.get("imu_chi2", 0.0) for f in kf]
    out["chi2_max"] = max(chi2)
    out["chi2_median"] = statistics.median(chi2)
    out["chi2_p95"] = quantile(chi2, 0.95)
    out["chi2_share_p99"] = sum(c > CHI2_15_P99 for c in chi2) / len(chi2)
    prms = [f.get("point_rms_sigmas", 0.0) for f in kf]
    out["point_rms_median"] = statistics.median(prms)
    out["point_rms_max"] = max(prms)
    res = sum(f.get("residuals", 0) for f in kf)
    cul = sum(f.get("culled_observations", 0) for f in kf)
    out["culled_share"] = cul / res if res else 0.0
    out["min_window_points"] = min(f.get("window_points", 0) for f in kf)
    out["speed_max"] = max(norm(f["state"]["v_w"]) for f in frames)
    # The window's first solve: the start's state against the window's keyframes.
    first = kf[0]
    seen = [f for f in kf if f.get("residuals", 0) > 0]
    n = max(1, first.get("residuals", 0))
    out["first_initial_cost_per"] = first.get("initial_cost", 0.0) / n
    out["first_final_cost_per"] = first.get("final_cost", 0.0) / n
    out["first_cost_drop"] = first.get("initial_cost", 0.0) / max(1e-9, first.get("final_cost", 0.0))
    out["first_visual_culled_share"] = (seen[0]["culled_observations"] / seen[0]["residuals"]
                                        if seen else 0.0)
    out["first_visual_chi2"] = seen[0].get("imu_chi2", 0.0) if seen else 0.0
    out["first_chi2"] = first.get("imu_chi2", 0.0)
    out["first_point_rms"] = first.get("point_rms_sigmas", 0.0)
    out["first_culled"] = first.get("culled_observations", 0)
    out["first_culled_share"] = first.get("culled_observations", 0) / max(1, first.get("residuals", 0))
    later = [f.get("point_rms_sigmas", 0.0) for f in kf[1:]]
    out["first_rms_over_median"] = out["first_point_rms"] / max(1e-9, statistics.median(later) if later else 1.0)
    s = j.get("summary", {})
    out["imu_only_share"] = s.get("imu_only_share", 0.0)
    return out


def load(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        return json.load(f)


def main(argv):
    rows = []
    if argv and argv[0] == "--json":
        for p in argv[1:]:
            rows.append((os.path.basename(p), float("nan"), run_stats(load(p))))
    else:
        for d in argv:
            if not os.path.exists(os.path.join(d, "runs.tsv")):
                continue
            for r in csv.DictReader(open(os.path.join(d, "runs.tsv")), delimiter="\t"):
                name = "-".join(r[k] for k in ("scene", "rate", "start", "motion", "seed", "lines"))
                p = os.path.join(d, "json", name + ".json.gz")
                if not os.path.exists(p):
                    continue
                ate = float(r["ate_m"]) if r["ate_m"] != "nan" else math.inf
                rows.append((name, ate, run_stats(load(p))))
    keys = sorted({k for _, _, s in rows for k in s})
    print("run\tate_m\t" + "\t".join(keys))
    for name, ate, s in rows:
        print("%s\t%.4f\t%s" % (name, ate, "\t".join("%.4g" % s.get(k, float("nan")) for k in keys)))
    # The start check of `plucker vio` at its defaults (checks.max_start_imu_chi2 25,
    # checks.max_start_culled_share 0.01 from 10 culled observations on).
    def flagged(s):
        culled = s.get("first_culled", 0)
        return s.get("first_chi2", 0) > 25.0 or (culled >= 10 and s.get("first_culled_share", 0) > 0.01)
    for label, lo, hi in (("healthy (< 0.2 m)", -1, 0.2), ("0.2-0.5 m", 0.2, 0.5),
                          ("failed (> 0.5 m)", 0.5, math.inf), ("no ATE", math.nan, math.nan)):
        g = [(n, s) for n, a, s in rows if (lo <= a < hi if lo == lo else a != a)]
        if g:
            f = [n for n, s in g if flagged(s)]
            print("start check: %s: %d of %d flagged %s" % (label, len(f), len(g), " ".join(f)))
    healthy = [s for _, a, s in rows if a < 0.2]
    failed = [s for _, a, s in rows if a > 0.5]
    print("\n%d healthy (< 0.2 m), %d failed (> 0.5 m)" % (len(healthy), len(failed)))
    print("statistic\thealthy max\thealthy p95\tfailed min\tfailed median\tfailed over healthy max")
    for k in keys:
        h = [s[k] for s in healthy if k in s]
        f = [s[k] for s in failed if k in s]
        if not h or not f:
            continue
        print("%s\t%.4g\t%.4g\t%.4g\t%.4g\t%d/%d" % (k, max(h), quantile(h, 0.95), min(f),
                                                   statistics.median(f), sum(x > max(h) for x in f),
                                                   len(f)))


if __name__ == "__main__":
    main(sys.argv[1:])
