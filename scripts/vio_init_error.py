#!/usr/bin/env python3
"""The error of a `plucker vio --euroc` run right after its start, against the EuRoC ground truth.

    scripts/vio_init_error.py EUROC_DIR EST.tum EST.json [BIN_SECONDS]

EUROC_DIR holds mav0/state_groundtruth_estimate0/data.csv (pose, world velocity, biases);
EST.tum and EST.json are the `--out` and `--json` files of the run. For each time bin after the
window's start (the last initialisation frame) it prints medians of:
  scale    the local scale: estimated over true distance travelled in the next 1 s (TUM poses);
  speed    |v_w| estimated over true (the JSON's per-frame states, frames faster than 0.2 m/s);
  dvz      the vertical velocity error (m/s; both worlds are gravity-aligned, so no alignment);
  tilt     the angle between the estimated and true gravity directions in the body (deg);
  dba      |b_a| error (m/s^2), and dbg |b_g| error (mrad/s).
No alignment is needed for any of them (all are invariant to the unobservable position and yaw).
Pure Python (no numpy).
"""
import bisect
import csv
import json
import math
import os
import sys


def rot(qx, qy, qz, qw):
    x, y, z, w = qx, qy, qz, qw
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def up_in_body(R):  # R_w_b^T e_z
    return [R[2][0], R[2][1], R[2][2]]


def angle_deg(a, b):
    d = sum(x * y for x, y in zip(a, b)) / (norm(a) * norm(b))
    return math.degrees(math.acos(max(-1.0, min(1.0, d))))


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def median(v):
    v = sorted(v)
    if not v:
        return float("nan")
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def load_gt(path):
    t, rows = [], []
    with open(path) as f:
        for r in csv.reader(f):
            if not r or r[0].startswith("#"):
                continue
            v = [float(x) for x in r]
            t.append(v[0] * 1e-9)
            rows.append({"p": v[1:4], "R": rot(v[5], v[6], v[7], v[4]), "v": v[8:11],
                         "bg": v[11:14], "ba": v[14:17]})
    return t, rows


def nearest(ts, t):
    i = bisect.bisect_left(ts, t)
    best = min((j for j in (i - 1, i) if 0 <= j < len(ts)), key=lambda j: abs(ts[j] - t))
    return best if abs(ts[best] - t) < 0.003 else None


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    root, tum, js = sys.argv[1:4]
    bin_s = float(sys.argv[4]) if len(sys.argv) == 5 else 2.5
    gt_t, gt = load_gt(os.path.join(root, "mav0/state_groundtruth_estimate0/data.csv"))
    est = []
    with open(tum) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(a) for a in line.split()]
            est.append((v[0], v[1:4], rot(*v[4:8])))
    report = json.load(open(js))
    frames = report["frames"]
    # The JSON's and the TUM's clocks: the dataset's, or seconds from the first IMU sample.
    with open(os.path.join(root, "mav0/imu0/data.csv")) as f:
        first = next(r for r in csv.reader(f) if r and not r[0].startswith("#"))
    t_imu0 = float(first[0]) * 1e-9
    shift = t_imu0 if est and est[0][0] < 1e8 else 0.0
    js_shift = t_imu0 if frames and frames[0]["time"] < 1e8 else 0.0
    init = report["initialization"]
    t_start = frames[init["frames"][1]]["time"] + js_shift
    est_t = [e[0] + shift for e in est]
    rows = []  # (t - t_start, metric name, value)
    for k, (t, p, R) in enumerate(zip(est_t, (e[1] for e in est), (e[2] for e in est))):
        g = nearest(gt_t, t)
        j = bisect.bisect_left(est_t, t + 1.0 - 1e-6)
        if g is None:
            continue
        rows.append((t - t_start, "tilt", angle_deg(up_in_body(R), up_in_body(gt[g]["R"]))))
        if j < len(est_t) and abs(est_t[j] - t - 1.0) < 0.01:
            g1 = nearest(gt_t, est_t[j])
            true_d = norm(sub(gt[g1]["p"], gt[g]["p"])) if g1 is not None else 0.0
            if true_d > 0.2:
                rows.append((t - t_start, "scale", norm(sub(est[j][1], p)) / true_d))
    for f in frames:
        s = f.get("state")
        if not s:
            continue
        t = f["time"] + js_shift
        g = nearest(gt_t, t)
        if g is None:
            continue
        truth = gt[g]
        if norm(truth["v"]) > 0.2:
            rows.append((t - t_start, "speed", norm(s["v_w"]) / norm(truth["v"])))
        rows.append((t - t_start, "dvz", s["v_w"][2] - truth["v"][2]))
        rows.append((t - t_start, "dba", norm(sub(s["accel_bias"], truth["ba"]))))
        rows.append((t - t_start, "dbg", 1e3 * norm(sub(s["gyro_bias"], truth["bg"]))))
    g0 = nearest(gt_t, frames[init["frames"][0]]["time"] + js_shift)
    s0 = init.get("state_first", {})
    print(f"start: frames {init['frames']} ({init['method']}), window from t = {t_start:.3f} s")
    events = [e for e in init.get("events", []) if e.get("event") == "alignment"]
    if events:
        print(f"alignment scale {events[-1].get('scale')}, keyframes {events[-1].get('keyframes')}")
    if g0 is not None and s0:
        print(f"first state: v_w {[round(x, 3) for x in s0['v_w']]} "
              f"(truth {[round(x, 3) for x in gt[g0]['v']]}), "
              f"b_a {[round(x, 3) for x in s0['accel_bias']]} "
              f"(truth {[round(x, 3) for x in gt[g0]['ba']]})")
    names = ["scale", "speed", "dvz", "tilt", "dba", "dbg"]
    print("| seconds after the start | " + " | ".join(names) + " |")
    print("|---" * (len(names) + 1) + "|")
    lo = min(r[0] for r in rows)
    b = math.floor(lo / bin_s) * bin_s
    hi = max(r[0] for r in rows)
    while b <= hi:
        sel = [r for r in rows if b <= r[0] < b + bin_s]
        cells = [median([r[2] for r in sel if r[1] == n]) for n in names]
        print(f"| {b:+.1f} .. {b + bin_s:+.1f} | " +
              " | ".join("-" if math.isnan(c) else f"{c:.3f}" for c in cells) + " |")
        b += bin_s


if __name__ == "__main__":
    main()
