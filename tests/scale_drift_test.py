#!/usr/bin/env python3
"""scripts/scale_drift.py on synthetic trajectories (ctest scale_drift_script_test): a known
scale ramp is recovered with a zero standard error; a trajectory whose scale is constant but for
one segment has a standard error as large as its figure, and the left-out range crosses zero;
--chord equals the path sum on a straight line. Fast, deterministic."""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import scale_drift  # noqa: E402


def straight(n, step=1.0):
    return [(step * k, 0.0, 0.0) for k in range(n)]


def scaled(gt, scale_of_step):
    est = [gt[0]]
    for k in range(1, len(gt)):
        s = scale_of_step(k)
        est.append(tuple(e + s * (b - a) for e, a, b in zip(est[-1], gt[k - 1], gt[k])))
    return est


def check(cond, what):
    if not cond:
        sys.exit(f"FAIL: {what}")


def main():
    gt = straight(201)  # 200 m
    # Step scale 1 + 0.1 * s / 100 m: +10 % per 100 m, relative to the mean ratio (~1.1).
    ramp = scaled(gt, lambda k: 1.0 + 0.1 * (k - 0.5) / 100.0)
    d = scale_drift.scale_drift(ramp, gt, 10, 0.05)
    check(d is not None and d["segments"] == 20, "20 segments")
    check(abs(d["drift_percent_per_100m"] - 100.0 * 0.1 / 1.1) < 0.2, f"ramp {d}")
    check(d["stderr_percent_per_100m"] < 1e-6, "a straight ramp fits exactly")
    # Constant scale but for one segment 20 % low at the start: the fit sees a slope, the
    # standard error and the left-out range say it is one segment.
    jump = scaled(gt, lambda k: 0.8 if k <= 10 else 1.0)
    d = scale_drift.scale_drift(jump, gt, 10, 0.05)
    check(d["drift_percent_per_100m"] > 1.0, f"the jump tilts the fit {d}")
    check(d["stderr_percent_per_100m"] > 0.3 * d["drift_percent_per_100m"], "jump: large error")
    check(abs(d["left_out_min"]) < 1e-6, f"without the low segment no slope {d['left_out_min']}")
    # Chord and path sum agree on a straight line; jitter inflates the path sum only.
    c = scale_drift.scale_drift(ramp, gt, 10, 0.05, chord=True)
    check(abs(c["drift_percent_per_100m"] - 100.0 * 0.1 / 1.1) < 0.2, "chord ramp")
    jitter = [(x, 0.2 * math.sin(7.0 * k), 0.0) for k, (x, _, _) in enumerate(gt)]
    p = scale_drift.scale_drift(jitter, gt, 10, 0.05)
    c = scale_drift.scale_drift(jitter, gt, 10, 0.05, chord=True)
    check(p["mean_ratio"] > 1.004 and abs(c["mean_ratio"] - 1.0) < 0.005, "jitter")
    # Too few segments: no figure.
    check(scale_drift.scale_drift(gt[:25], gt[:25], 10, 0.05) is None, "2 segments: None")
    print("scale_drift_test: ok")


if __name__ == "__main__":
    main()
