#!/usr/bin/env python3
"""Scale drift of a monocular trajectory against its ground truth (docs/evaluation.md).

Both files are KITTI poses (12 numbers a row) or TUM (8, times ignored), frame by frame: row k of the estimate is the
same image as row k of the ground truth (`plucker vo --out`, and `plucker convert euroc-gt
--camera-poses` or a KITTI poses.txt). Rows with a nan are skipped.

The path is cut into segments of --segment frames (non-overlapping). For each segment whose true
length is at least --min-length m:  r = (estimated length) / (true length), lengths of the
camera centres' steps summed. r is divided by its mean over the run (the global scale a Sim(3)
alignment removes), and a straight line r/mean(r) = a + b * s is fitted by least squares against
s, the true distance travelled at the segment's middle. The scale drift is 100 * b * 100 m:
percent change of the step-length ratio per 100 m travelled. Also printed: the change of r from
the first to the last quarter of the segments (percent), which is what the clip shows directly.

On a clip shorter than 100 m the per-100 m figure is an extrapolation of the fitted slope: on
a 14 m clip a 1 % change of r reads as about 7 % per 100 m.
"""
import argparse
import math
import sys


def read_poses(path):
    centres = []
    try:
        with open(path) as f:
            for n, line in enumerate(f, 1):
                fields = line.split()
                if not fields or fields[0].startswith("#"):
                    continue
                if len(fields) not in (8, 12):
                    sys.exit(f"{path}:{n}: expected 12 numbers (KITTI) or 8 (TUM), got "
                             f"{len(fields)}")
                try:
                    v = [float(x) for x in fields]
                except ValueError:
                    sys.exit(f"{path}:{n}: not a number")
                c = (v[3], v[7], v[11]) if len(v) == 12 else (v[1], v[2], v[3])
                centres.append(c if all(math.isfinite(x) for x in c) else None)
    except OSError as e:
        sys.exit(f"{path}: cannot open: {e.strerror}")
    return centres


def path_length(c, a, b):
    total = 0.0
    for k in range(a, b):
        if c[k] is None or c[k + 1] is None:
            return None
        total += math.dist(c[k], c[k + 1])
    return total


def scale_drift(est, gt, segment, min_length):
    n = min(len(est), len(gt))
    s, r = [], []
    travelled = 0.0
    for a in range(0, n - segment, segment):
        b = a + segment
        lg, le = path_length(gt, a, b), path_length(est, a, b)
        if lg is None:
            continue
        if le is not None and lg >= min_length and le > 0.0:
            s.append(travelled + 0.5 * lg)
            r.append(le / lg)
        travelled += lg
    if len(r) < 3:
        return None
    mean_r = sum(r) / len(r)
    q = [x / mean_r for x in r]
    ms, mq = sum(s) / len(s), sum(q) / len(q)
    sxx = sum((x - ms) ** 2 for x in s)
    if sxx <= 0.0:
        return None
    slope = sum((x - ms) * (y - mq) for x, y in zip(s, q)) / sxx
    k = max(1, len(r) // 4)
    first, last = sum(r[:k]) / k, sum(r[-k:]) / k
    return {
        "segments": len(r),
        "distance_m": travelled,
        "mean_ratio": mean_r,
        "drift_percent_per_100m": 100.0 * slope * 100.0,
        "first_to_last_quarter_percent": 100.0 * (last / first - 1.0),
        "ratio_min": min(q),
        "ratio_max": max(q),
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--gt", required=True, help="ground truth, KITTI poses")
    p.add_argument("--est", required=True, help="estimate, KITTI poses, same frames")
    p.add_argument("--segment", type=int, default=10, help="frames per segment (default 10)")
    p.add_argument("--min-length", type=float, default=0.05,
                   help="segments whose true length is shorter are left out (m, default 0.05)")
    a = p.parse_args()
    if a.segment < 1:
        sys.exit("--segment must be at least 1")
    est, gt = read_poses(a.est), read_poses(a.gt)
    if len(est) != len(gt):
        print(f"warning: {a.est} has {len(est)} poses, {a.gt} {len(gt)}: the first "
              f"{min(len(est), len(gt))} compared", file=sys.stderr)
    d = scale_drift(est, gt, a.segment, a.min_length)
    if d is None:
        sys.exit(f"{a.est}: fewer than 3 segments of {a.segment} frames with a pose and a true "
                 f"length >= {a.min_length} m: no scale drift")
    print(f"segments {d['segments']} of {a.segment} frames, {d['distance_m']:.2f} m travelled")
    print(f"scale drift [% per 100 m]  {d['drift_percent_per_100m']:+.1f}")
    print(f"ratio change, first to last quarter [%]  {d['first_to_last_quarter_percent']:+.1f}")
    print(f"ratio / mean  min {d['ratio_min']:.3f}  max {d['ratio_max']:.3f}  "
          f"(mean ratio {d['mean_ratio']:.4g})")


if __name__ == "__main__":
    main()
