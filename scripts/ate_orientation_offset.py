#!/usr/bin/env python3
"""Where the orientation error of a TUM trajectory against a TUM ground truth sits.

    scripts/ate_orientation_offset.py GT.tum EST.tum

Pairs the poses with equal stamps (to 0.1 ms), aligns the positions by SE(3) (Umeyama, no scale),
then reports the mean and spread of the rotation offset on the world side (R_align R_est R_gt^T:
a tilt here is a gravity direction the estimate holds apart from its positions) and on the body
side (R_gt^T R_align R_est: a constant one is an extrinsic or body-frame offset). numpy only.
"""
import sys

import numpy as np


def rotation(qx, qy, qz, qw):
    x, y, z, w = qx, qy, qz, qw
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def load(path):
    poses = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(a) for a in line.split()]
            if len(v) != 8:
                sys.exit(f"{path}: a TUM line has 8 numbers: {line.strip()}")
            poses[round(v[0], 4)] = (np.array(v[1:4]), rotation(*v[4:8]))
    return poses


def log_deg(m):
    a = np.arccos(np.clip((np.trace(m) - 1) / 2, -1, 1))
    if a < 1e-12:
        return np.zeros(3)
    w = np.array([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]])
    return np.degrees(a / (2 * np.sin(a)) * w)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    gt, est = load(sys.argv[1]), load(sys.argv[2])
    keys = [k for k in sorted(est) if k in gt]
    if len(keys) < 3:
        sys.exit(f"{sys.argv[2]}: fewer than 3 stamps in common with {sys.argv[1]}")
    p = np.array([est[k][0] for k in keys])
    q = np.array([gt[k][0] for k in keys])
    u, _, vt = np.linalg.svd((q - q.mean(0)).T @ (p - p.mean(0)))
    r = u @ np.diag([1, 1, np.sign(np.linalg.det(u @ vt))]) @ vt
    world = np.array([log_deg(r @ est[k][1] @ gt[k][1].T) for k in keys])
    body = np.array([log_deg(gt[k][1].T @ r @ est[k][1]) for k in keys])
    print(f"{len(keys)} pairs")
    for name, v in (("world side", world), ("body side", body)):
        print(f"{name}: mean {np.round(v.mean(0), 2)} deg (|mean| {np.linalg.norm(v.mean(0)):.2f}),"
              f" std {np.round(v.std(0), 2)} deg")


if __name__ == "__main__":
    main()
