#!/usr/bin/env python3
"""How far the camera rotation of a `plucker vo` run drifts from the EuRoC ground truth's.

    scripts/rotation_vs_gt.py EUROC_DIR VO_POSES.txt GT.tum [STEP_FRAMES]

VO_POSES.txt: the `--out` of `plucker vo --images EUROC_DIR/mav0/cam0/data` (one 3x4 T_w_c per
image, KITTI layout, in the order of cam0/data.csv); GT.tum: `plucker convert euroc-gt`. For every
STEP_FRAMES-th frame k (default 20) it prints the angle of R_gt_rel^T R_vo_rel (deg), where both
are the camera's rotation from frame 0 to frame k (the ground truth's through cam0's T_BS), next
to the rotation angle itself. No alignment is needed (a relative rotation is gauge-free): a growth
while the body turns is a disagreement between the images and the ground truth's attitude (the
extrinsic, or the ground truth's orientation), which a VIO run on an IMU synthesised from that
attitude must absorb. Pure Python (no numpy).
"""
import math
import os
import sys


def mm(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def tr(a):
    return [list(r) for r in zip(*a)]


def q2r(x, y, z, w):
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def angle_deg(r):
    return math.degrees(math.acos(max(-1.0, min(1.0, (r[0][0] + r[1][1] + r[2][2] - 1) / 2))))


def t_bs_rotation(path):
    text = open(path).read()
    data = text[text.index("data:", text.index("T_BS")):]
    nums = [float(v) for v in data[data.index("[") + 1:data.index("]")].replace("\n", " ").split(",")]
    return [nums[0:3], nums[4:7], nums[8:11]]


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    root, vo_path, gt_path = sys.argv[1:4]
    step = int(sys.argv[4]) if len(sys.argv) == 5 else 20
    cam = os.path.join(root, "mav0", "cam0")
    stamps = [int(l.split(",")[0]) * 1e-9 for l in open(os.path.join(cam, "data.csv"))
              if l.strip() and not l.startswith("#")]
    gt = {}
    for line in open(gt_path):
        if line.startswith("#") or not line.strip():
            continue
        v = [float(a) for a in line.split()]
        gt[round(v[0], 3)] = q2r(*v[4:8])
    vo = []
    for line in open(vo_path):
        v = [float(a) for a in line.split()]
        vo.append([v[0:3], v[4:7], v[8:11]])
    if len(vo) != len(stamps):
        sys.exit(f"{vo_path}: {len(vo)} poses for {len(stamps)} images")
    r_b_c = t_bs_rotation(os.path.join(cam, "sensor.yaml"))
    t0 = round(stamps[0], 3)
    if t0 not in gt:
        sys.exit(f"{gt_path}: no pose at the first image's time {stamps[0]:.3f}")
    print("| s | disagreement [deg] | rotation since frame 0 [deg] |\n|---|---|---|")
    for k in range(0, len(vo), step):
        t = round(stamps[k], 3)
        if t not in gt:
            continue
        r_gt = mm(mm(tr(r_b_c), mm(tr(gt[t0]), gt[t])), r_b_c)
        r_vo = mm(tr(vo[0]), vo[k])
        print(f"| {stamps[k] - stamps[0]:.1f} | {angle_deg(mm(tr(r_gt), r_vo)):.2f} | "
              f"{angle_deg(r_gt):.1f} |")


if __name__ == "__main__":
    main()
