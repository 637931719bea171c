#!/usr/bin/env python3
"""LiDAR odometry on a KITTI odometry sequence from Python, with a top view of the trajectory.

    PYTHONPATH=<prefix>/lib/python3/dist-packages python3 examples/python/lidar_kitti.py \\
        ../shared/data/kitti-odometry-00/sequences/00 --plot top_view.png

Writes the poses as `plucker lidar --frame lidar` writes them (--out), prints the ATE against
the ground truth when the sequence has one (poses/NN.txt, cam0 frame), and draws the top view
when matplotlib is installed (Debian python3-matplotlib); without it the plot is skipped.
"""
import argparse
import pathlib
import sys

import numpy as np

import plucker


def ground_truth(sequence: pathlib.Path) -> "np.ndarray | None":
    gt = sequence.parent.parent / "poses" / f"{sequence.name}.txt"
    return plucker.read_trajectory(str(gt))["poses"] if gt.is_file() else None


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sequence", type=pathlib.Path, help="folder with velodyne/ and times.txt")
    parser.add_argument("--out", type=pathlib.Path, help="KITTI poses (LiDAR frame)")
    parser.add_argument("--plot", type=pathlib.Path, help="top-view image (PNG)")
    args = parser.parse_args()

    scans = sorted((args.sequence / "velodyne").glob("*.bin"))
    if not scans:
        print(f"{args.sequence}/velodyne: no .bin scans", file=sys.stderr)
        return 1
    times_file = args.sequence / "times.txt"
    times = plucker.read_kitti_times(str(times_file)) if times_file.is_file() else None
    odometry = plucker.LidarOdometry()
    for i, path in enumerate(scans):
        stamp = float(times[i]) if times is not None and i < len(times) else None
        T_w_l = odometry.register(plucker.read_kitti_bin(str(path)), timestamp=stamp)
        print(f"\rscan {i + 1}/{len(scans)}: x {T_w_l[0, 3]:8.2f} y {T_w_l[1, 3]:8.2f} m",
              end="", file=sys.stderr)
    print(file=sys.stderr)
    poses = odometry.poses  # T_w_l, (N, 4, 4)
    if args.out:
        args.out.write_text(plucker.format_kitti_poses(poses))

    gt = ground_truth(args.sequence)
    calib = args.sequence / "calib.txt"
    Tr = plucker.read_kitti_calib_tr(str(calib)) if calib.is_file() else None
    if gt is not None and Tr is not None and len(gt) >= len(poses):
        cam0 = np.stack([Tr @ T @ np.linalg.inv(Tr) for T in poses])  # T_cam0(0)_cam0(i)
        ate = plucker.ate(gt[:len(poses)], cam0, align="se3")
        print(f"ATE (SE(3)-aligned, cam0 frame): rmse {ate['translation_m']['rmse']:.3f} m over "
              f"{len(poses)} poses")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (apt-get install python3-matplotlib)")
        return 0
    fig, ax = plt.subplots(figsize=(6, 6))
    ax.plot(poses[:, 0, 3], poses[:, 1, 3], "-o", ms=2, label="plucker (LiDAR frame)")
    ax.set_xlabel("x [m] (forward)")
    ax.set_ylabel("y [m] (left)")
    ax.set_aspect("equal")
    ax.legend()
    out = args.plot or pathlib.Path("lidar_top_view.png")
    fig.savefig(out, dpi=120)
    print(f"top view -> {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
