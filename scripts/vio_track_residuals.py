#!/usr/bin/env python3
"""The front end's point and line tracks on real images against ground-truth camera poses.

    scripts/vio_track_residuals.py TRACKS_DIR GT.tum CAM_SENSOR_YAML [MIN_VIEWS] [MIN_ANGLE_DEG]

TRACKS_DIR: `plucker vio --euroc DIR --tracks TRACKS_DIR` (undistorted pixels of the pipeline's
pinhole, frames.txt with the frame times on the dataset's clock); GT.tum: `plucker convert
euroc-gt` (T_w_b); CAM_SENSOR_YAML: the camera's sensor.yaml (T_BS = T_b_c). The ground-truth
camera of each frame is T_w_b(t) T_b_c (T_w_b interpolated). Every track seen by MIN_VIEWS (3)
frames or more whose back-projected rays (points) or planes (lines) span MIN_ANGLE_DEG (2) or
more is triangulated from those cameras (linear, then Gauss-Newton on the pixel residuals) and
its residuals there are the front end's noise plus the ground truth's pose error, which points
and lines share: a point's two pixel coordinates, a segment's two endpoint distances to the
reprojected line (the window's line residual). Prints per kind the sigma of one residual (RMS
corrected for the parameters fitted: 3 for a point, 4 for a line), the robust sigma (1.4826 x the
median absolute residual), the share of tracks with a residual over 4 robust sigmas, and the
lines' robust sigma by segment length and by the track's depth. numpy only.
"""
import re
import sys

import numpy as np

sys.path.insert(0, __import__('os').path.dirname(__import__('os').path.abspath(__file__)))
from ate_orientation_offset import rotation  # noqa: E402  (quaternion x y z w -> matrix)


def rows(path):
    with open(path) as f:
        return [[float(v) for v in r.split()] for r in f if r.strip() and not r.startswith('#')]


def t_b_c(path):
    text = open(path).read()
    m = re.search(r'T_BS:.*?data:\s*\[([^\]]*)\]', text, re.S)
    if not m:
        sys.exit(f'{path}: no T_BS data')
    return np.array([float(v) for v in m.group(1).split(',')]).reshape(4, 4)


def slerp(q0, q1, a):
    if np.dot(q0, q1) < 0:
        q1 = -q1
    q = (1 - a) * q0 + a * q1  # nlerp: the ground truth is at 200 Hz
    return q / np.linalg.norm(q)


def gt_cameras(gt_path, frames, T_bc):
    gt = np.array(rows(gt_path))
    cams = {}
    for f, t in frames.items():
        k = np.searchsorted(gt[:, 0], t)
        if k == 0 or k >= len(gt):
            continue
        a = (t - gt[k - 1, 0]) / (gt[k, 0] - gt[k - 1, 0])
        p = (1 - a) * gt[k - 1, 1:4] + a * gt[k, 1:4]
        q = slerp(gt[k - 1, 4:8], gt[k, 4:8], a)
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = rotation(*q), p
        T = T @ T_bc
        cams[f] = (T[:3, :3].T, -T[:3, :3].T @ T[:3, 3])  # R_c_w, t_c_w
    return cams


def project(K, R, t, X):
    x = R @ X + t
    return np.array([K[0] * x[0] / x[2] + K[2], K[1] * x[1] / x[2] + K[3]]), x[2]


def gauss_newton(residual, x, iterations=15):
    """Levenberg-Marquardt with numeric Jacobians (steps that raise the cost are refused)."""
    r = residual(x)
    lam = 1e-3
    for _ in range(iterations):
        J = np.empty((len(r), len(x)))
        for j in range(len(x)):
            d = np.zeros(len(x))
            d[j] = 1e-6 * max(1.0, abs(x[j]))
            J[:, j] = (residual(x + d) - residual(x - d)) / (2 * d[j])
        H = J.T @ J
        step = np.linalg.solve(H + lam * np.diag(np.diag(H) + 1e-12), -J.T @ r)
        r_new = residual(x + step)
        if r_new @ r_new < r @ r:
            x, r, lam = x + step, r_new, lam * 0.3
        else:
            lam *= 10.0
        if np.linalg.norm(step) < 1e-10 * (1 + np.linalg.norm(x)):
            break
    return x, r


def point_track(K, cams, obs):
    A, rays = [], []
    for f, uv in obs:
        R, t = cams[f]
        P = np.hstack([R, t[:, None]])
        xn = np.array([(uv[0] - K[2]) / K[0], (uv[1] - K[3]) / K[1]])
        A += [xn[0] * P[2] - P[0], xn[1] * P[2] - P[1]]
        rays.append(R.T @ np.array([xn[0], xn[1], 1.0]))
    rays = [r / np.linalg.norm(r) for r in rays]
    angle = max(np.degrees(np.arccos(np.clip(a @ b, -1, 1))) for a in rays for b in rays)
    X = np.linalg.svd(np.array(A))[2][-1]
    if abs(X[3]) < 1e-12:
        return None
    X = X[:3] / X[3]

    def residual(X):
        return np.concatenate([project(K, *cams[f], X)[0] - uv for f, uv in obs])
    X, r = gauss_newton(residual, X)
    depths = [project(K, *cams[f], X)[1] for f, _ in obs]
    return angle, r, min(depths)


def line_residual(K, cams, obs, X1, X2):
    r = []
    for f, s, e in obs:
        a, _ = project(K, *cams[f], X1)
        b, _ = project(K, *cams[f], X2)
        l = np.cross(np.append(a, 1.0), np.append(b, 1.0))
        l /= np.hypot(l[0], l[1])
        r += [l @ np.append(s, 1.0), l @ np.append(e, 1.0)]
    return np.array(r)


def ray_line_point(K, cam, uv, p, d):
    """The point of the line (p, d) nearest to the ray of pixel uv from camera cam."""
    R, t = cam
    c = -R.T @ t
    r = R.T @ np.array([(uv[0] - K[2]) / K[0], (uv[1] - K[3]) / K[1], 1.0])
    # minimise |p + a d - c - b r| over a, b
    M = np.array([[d @ d, -(d @ r)], [d @ r, -(r @ r)]])
    a, _ = np.linalg.lstsq(M, np.array([d @ (c - p), r @ (c - p)]), rcond=None)[0]
    return p + a * d


def line_track(K, cams, obs):
    planes, normals = [], []
    for f, s, e in obs:
        R, t = cams[f]
        l = np.cross(np.append(s, 1.0), np.append(e, 1.0))
        n_c = np.array([K[0] * l[0], K[1] * l[1], K[2] * l[0] + K[3] * l[1] + l[2]])  # K^T l
        n_c /= np.linalg.norm(n_c)
        n_w = R.T @ n_c
        planes.append(np.append(n_w, n_c @ t))  # n_c . (R X + t) = 0
        normals.append(n_w)
    angle = max(np.degrees(np.arccos(np.clip(abs(a @ b), 0, 1))) for a in normals for b in normals)
    V = np.linalg.svd(np.array(planes))[2]
    A, B = V[-1], V[-2]  # the line is their span: Plücker direction and moment
    d = A[3] * B[:3] - B[3] * A[:3]
    moment = np.cross(A[:3], B[:3])
    p0 = np.cross(d, moment) / (d @ d)  # its point nearest to the origin
    d /= np.linalg.norm(d)
    f0, s0, e0 = obs[len(obs) // 2]
    X1, X2 = (ray_line_point(K, cams[f0], uv, p0, d) for uv in (s0, e0))  # the segment's ends

    def residual(x):
        return line_residual(K, cams, obs, x[:3], x[3:])
    x, r = gauss_newton(residual, np.concatenate([X1, X2]))
    depth = np.median([project(K, *cams[f], x[:3])[1] for f, _, _ in obs])
    length = np.median([np.linalg.norm(e - s) for _, s, e in obs])
    return angle, r, depth, length


def summary(name, tracks, params):
    if not tracks:
        print(f'{name}: no tracks')
        return None
    r = np.concatenate([t[1] for t in tracks])
    dof = sum(len(t[1]) - params for t in tracks)
    sigma = np.sqrt(np.sum(r * r) / dof)
    robust = 1.4826 * np.median(np.abs(r))
    bad = sum(np.max(np.abs(t[1])) > 4 * robust for t in tracks)
    print(f'{name}: {len(tracks)} tracks, {len(r)} residuals; sigma {sigma:.3f} px (dof-corrected '
          f'RMS), robust sigma {robust:.3f} px, tracks over 4 robust sigmas {bad} '
          f'({100.0 * bad / len(tracks):.1f} %); |r| p50/p90/p99 '
          + '/'.join(f'{np.percentile(np.abs(r), q):.2f}' for q in (50, 90, 99)))
    return robust


def main(argv):
    if len(argv) < 4:
        sys.exit(__doc__)
    d, gt_path, yaml = argv[1:4]
    min_views = int(argv[4]) if len(argv) > 4 else 3
    min_angle = float(argv[5]) if len(argv) > 5 else 2.0
    fr = rows(d + '/frames.txt')
    frames = {int(r[0]): r[1] for r in fr}
    K = fr[0][2:6]
    cams = gt_cameras(gt_path, frames, t_b_c(yaml))
    pts, segs = {}, {}
    for r in rows(d + '/points.txt'):
        if int(r[0]) in cams and r[1] >= 0:
            pts.setdefault(int(r[1]), []).append((int(r[0]), np.array(r[2:4])))
    for r in rows(d + '/segments.txt'):
        if int(r[0]) in cams and r[1] >= 0:
            segs.setdefault(int(r[1]), []).append((int(r[0]), np.array(r[2:4]), np.array(r[4:6])))
    points = [t for t in (point_track(K, cams, o) for o in pts.values() if len(o) >= min_views)
              if t and t[0] >= min_angle and t[2] > 0]
    lines = [t for t in (line_track(K, cams, o) for o in segs.values() if len(o) >= min_views)
             if t[0] >= min_angle and t[2] > 0]
    print(f'{len(cams)} frames with a ground-truth camera; tracks of >= {min_views} views '
          f'spanning >= {min_angle} deg')
    p = summary('points', points, 3)
    q = summary('lines', lines, 4)
    if p and q:
        print(f'line / point robust sigma: {q / p:.2f}')
    for name, key, edges in (('length px', 3, (0, 40, 80, 160, 1e9)),
                             ('depth m', 2, (0, 2, 4, 8, 1e9))):
        for lo, hi in zip(edges[:-1], edges[1:]):
            sel = [t for t in lines if lo <= t[key] < hi]
            if sel:
                r = np.concatenate([t[1] for t in sel])
                print(f'  lines, {name} [{lo:g}, {hi:g}): {len(sel)} tracks, robust sigma '
                      f'{1.4826 * np.median(np.abs(r)):.3f} px')


if __name__ == '__main__':
    main(sys.argv)
