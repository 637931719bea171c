#!/usr/bin/env python3
"""How far the body has turned since a start frame, from a TUM ground truth (T_w_b):

    scripts/gt_turn.py GT.tum CAM0_DATA.csv FIRST_FRAME [STEP]

GT.tum from `plucker convert euroc-gt`; CAM0_DATA.csv the EuRoC mav0/cam0/data.csv (frame
times in ns). For every STEP-th frame (default 10) from FIRST_FRAME it prints the angle of
R_b0_bk, its yaw part (about the world's vertical) and the tilt change (the angle between the
gravity directions in the two bodies): what the start's bundle adjustment has to separate the
gravity tilt from the accelerometer bias (docs/results/vio.md). Needs numpy.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ate_orientation_offset import rotation  # noqa: E402  (quaternion x y z w -> matrix)


def yaw_deg(R):
    return np.degrees(np.arctan2(R[1, 0], R[0, 0]))


def main():
    gt = np.loadtxt(sys.argv[1], comments='#')
    frames = np.loadtxt(sys.argv[2], delimiter=',', comments='#', usecols=0) / 1e9
    first = int(sys.argv[3])
    step = int(sys.argv[4]) if len(sys.argv) > 4 else 10

    def at(t):
        return rotation(*gt[np.argmin(np.abs(gt[:, 0] - t)), 4:8])

    R0 = at(frames[first])
    up0 = R0.T @ np.array([0.0, 0.0, 1.0])
    print('| frame | s from frame 0 | turned [deg] | yaw [deg] | tilt change [deg] |')
    print('|---|---|---|---|---|')
    for f in range(first, len(frames), step):
        R = at(frames[f])
        c = np.clip((np.trace(R0.T @ R) - 1.0) / 2.0, -1.0, 1.0)
        dyaw = (yaw_deg(R) - yaw_deg(R0) + 180.0) % 360.0 - 180.0
        tilt = np.degrees(np.arccos(np.clip(up0 @ (R.T @ np.array([0.0, 0.0, 1.0])), -1.0, 1.0)))
        print('| %d | %.2f | %.1f | %.1f | %.1f |' %
              (f, frames[f] - frames[0], np.degrees(np.arccos(c)), dyaw, tilt))


if __name__ == '__main__':
    main()
