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

Is the figure signal or noise? Also printed: the slope's standard error (from the fit's
residuals, as if the segments were independent) and the figure with each segment left out in
turn (its range: one segment that moves the figure by more than the figure itself is a
jump, not a drift). --series prints every segment (frames, true and estimated length, r/mean);
--chord measures a segment by the distance between its end centres instead of the sum of its
steps (jitter of the estimate inflates a sum of short steps, a hovering drone's most of all).
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


def chord_length(c, a, b):
    if c[a] is None or c[b] is None:
        return None
    return math.dist(c[a], c[b])


def fit_slope(s, r):
    """Least-squares slope of r/mean(r) against s, and its standard error (None: no fit)."""
    mean_r = sum(r) / len(r)
    q = [x / mean_r for x in r]
    ms, mq = sum(s) / len(s), sum(q) / len(q)
    sxx = sum((x - ms) ** 2 for x in s)
    if sxx <= 0.0:
        return None, None
    slope = sum((x - ms) * (y - mq) for x, y in zip(s, q)) / sxx
    if len(s) < 3:
        return slope, None
    rss = sum((y - mq - slope * (x - ms)) ** 2 for x, y in zip(s, q))
    return slope, math.sqrt(rss / (len(s) - 2) / sxx)


def scale_drift(est, gt, segment, min_length, chord=False):
    n = min(len(est), len(gt))
    length = chord_length if chord else path_length
    s, r, rows = [], [], []
    travelled = 0.0
    for a in range(0, n - segment, segment):
        b = a + segment
        lg = path_length(gt, a, b)
        if lg is None:
            continue
        cg, le = length(gt, a, b), length(est, a, b)
        if le is not None and cg is not None and lg >= min_length and cg > 0.0 and le > 0.0:
            s.append(travelled + 0.5 * lg)
            r.append(le / cg)
            rows.append((a, b, cg, le))
        travelled += lg
    if len(r) < 3:
        return None
    mean_r = sum(r) / len(r)
    q = [x / mean_r for x in r]
    slope, stderr = fit_slope(s, r)
    if slope is None:
        return None
    left_out = []
    for i in range(len(r)):
        si, ri = s[:i] + s[i + 1:], r[:i] + r[i + 1:]
        b, _ = fit_slope(si, ri)
        if b is not None:
            left_out.append(1e4 * b)
    k = max(1, len(r) // 4)
    first, last = sum(r[:k]) / k, sum(r[-k:]) / k
    return {
        "series": [(a, b, x, cg, le, y) for (a, b, cg, le), x, y in zip(rows, s, q)],
        "stderr_percent_per_100m": None if stderr is None else 1e4 * stderr,
        "left_out_min": min(left_out) if left_out else None,
        "left_out_max": max(left_out) if left_out else None,
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
    p.add_argument("--chord", action="store_true",
                   help="a segment's length is the distance between its end centres (default: "
                        "the sum of its steps)")
    p.add_argument("--series", action="store_true", help="print every segment")
    a = p.parse_args()
    if a.segment < 1:
        sys.exit("--segment must be at least 1")
    est, gt = read_poses(a.est), read_poses(a.gt)
    if len(est) != len(gt):
        print(f"warning: {a.est} has {len(est)} poses, {a.gt} {len(gt)}: the first "
              f"{min(len(est), len(gt))} compared", file=sys.stderr)
    d = scale_drift(est, gt, a.segment, a.min_length, a.chord)
    if d is None:
        sys.exit(f"{a.est}: fewer than 3 segments of {a.segment} frames with a pose and a true "
                 f"length >= {a.min_length} m: no scale drift")
    print(f"segments {d['segments']} of {a.segment} frames, {d['distance_m']:.2f} m travelled")
    if a.series:
        print("# frames  s [m]  true [m]  est  r/mean")
        for fa, fb, x, cg, le, y in d["series"]:
            print(f"{fa}-{fb}  {x:.2f}  {cg:.3f}  {le:.4g}  {y:.3f}")
    err = d["stderr_percent_per_100m"]
    print(f"scale drift [% per 100 m]  {d['drift_percent_per_100m']:+.1f}"
          + ("" if err is None else f"  (standard error {err:.1f}; one segment left out: "
             f"{d['left_out_min']:+.1f} .. {d['left_out_max']:+.1f})"))
    print(f"ratio change, first to last quarter [%]  {d['first_to_last_quarter_percent']:+.1f}")
    print(f"ratio / mean  min {d['ratio_min']:.3f}  max {d['ratio_max']:.3f}  "
          f"(mean ratio {d['mean_ratio']:.4g})")


if __name__ == "__main__":
    main()
