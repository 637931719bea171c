#!/usr/bin/env python3
"""The segment observations of a simulated sequence against the truth.

    scripts/fisheye_segment_residuals.py SIM_DIR

SIM_DIR: a `plucker sim camera --out` folder (pinhole, or a fisheye whose segments are in its
undistorted view: rig.txt `view`). For every inlier segment, the signed distances of its two
observed endpoints to the projection of the true 3D line at the true camera pose (the window's
line residual at the truth, in pixels), and whether its true endpoints lie in the image (an
endpoint outside: the observation was clipped by the image border). Prints the residual RMS
(the pixel sigma it was drawn with, if the model is right) overall, by clipped endpoints, and
the share of observations by angle off the optical axis. numpy only.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ate_orientation_offset import rotation  # noqa: E402  (quaternion x y z w -> matrix)


def rows(path):
    with open(path) as f:
        return [line.split() for line in f if line.strip() and not line.startswith('#')]


def main(d):
    rig = {r[0]: r[1:] for r in rows(d + '/rig.txt')}
    if 'view' in rig:
        fx, fy, cx, cy, w, h = map(float, rig['view'][:6])
    else:
        fx, fy, cx, cy = map(float, rig['intrinsics'])
        w, h = map(float, rig['image'])
    min_depth = float(rig['depth_range'][0])
    seg_w = {int(r[1]): (np.array(r[2:5], float), np.array(r[5:8], float))
             for r in rows(d + '/scene.txt') if r[0] == 'segment'}
    poses = [(rotation(*map(float, r[4:8])), np.array(r[1:4], float))
             for r in rows(d + '/trajectory.txt')]

    def in_image(p):
        if p[2] < min_depth:
            return False
        u, v = fx * p[0] / p[2] + cx, fy * p[1] / p[2] + cy
        return 0 <= u <= w - 1 and 0 <= v <= h - 1

    def angle_deg(uv):
        ray = np.array([(uv[0] - cx) / fx, (uv[1] - cy) / fy, 1.0])
        return np.degrees(np.arccos(1.0 / np.linalg.norm(ray)))

    res, clipped, max_angle, length = [], [], [], []
    for r in rows(d + '/segments.txt'):
        frame, line_id = int(r[0]), int(r[1])
        if line_id < 0:
            continue
        s, e = np.array(r[2:4], float), np.array(r[4:6], float)
        R_w_c, t_w_c = poses[frame]
        a_c, b_c = R_w_c.T @ (seg_w[line_id][0] - t_w_c), R_w_c.T @ (seg_w[line_id][1] - t_w_c)
        n = np.cross(a_c, b_c)  # the line's moment: its image line in normalized coordinates
        l = np.array([fy * n[0], fx * n[1], -fy * cx * n[0] - fx * cy * n[1] + fx * fy * n[2]])
        rho = np.hypot(l[0], l[1])
        res.append([(s @ l[:2] + l[2]) / rho, (e @ l[:2] + l[2]) / rho])
        clipped.append((not in_image(a_c)) + (not in_image(b_c)))
        max_angle.append(max(angle_deg(s), angle_deg(e)))
        length.append(np.linalg.norm(e - s))
    res, clipped = np.array(res), np.array(clipped)
    max_angle, length = np.array(max_angle), np.array(length)
    print('%s: %d inlier segments, endpoint-to-true-line RMS %.3f px, mean length %.0f px' %
          (d, len(res), np.sqrt(np.mean(res ** 2)), length.mean()))
    for c in (0, 1, 2):
        m = clipped == c
        if m.any():
            print('  %d endpoint(s) clipped: %.2f of them, RMS %.3f px, mean length %.0f px' %
                  (c, m.mean(), np.sqrt(np.mean(res[m] ** 2)), length[m].mean()))
    for lo, hi in ((0, 30), (30, 45), (45, 50), (50, 90)):
        m = (max_angle >= lo) & (max_angle < hi)
        if m.any():
            print('  farthest endpoint %2d-%2d deg off the axis: %.2f of them, RMS %.3f px' %
                  (lo, hi, m.mean(), np.sqrt(np.mean(res[m] ** 2))))


if __name__ == '__main__':
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
