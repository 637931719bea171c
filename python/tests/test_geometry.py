"""Geometry bindings: values against numpy formulas, Jacobians against central differences."""
import numpy as np
import pytest

import plucker
from conftest import random_pose


def numeric_jacobian(f, x, h=1e-6):
    x = np.asarray(x, dtype=float)
    cols = []
    for i in range(x.size):
        d = np.zeros_like(x)
        d[i] = h
        cols.append((f(x + d) - f(x - d)) / (2 * h))
    return np.stack(cols, axis=1)


def test_so3_exp_log_round_trip_and_rodrigues():
    rng = np.random.default_rng(1)
    for _ in range(50):
        w = rng.uniform(-3.0, 3.0, 3)
        if np.linalg.norm(w) >= np.pi:
            continue
        R = plucker.so3_exp(w)
        theta = np.linalg.norm(w)
        K = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]) / theta
        expected = np.eye(3) + np.sin(theta) * K + (1 - np.cos(theta)) * K @ K
        np.testing.assert_allclose(R, expected, atol=1e-12)
        np.testing.assert_allclose(plucker.so3_log(R), w, atol=1e-10)


def test_se3_chart_and_compose_jacobians():
    rng = np.random.default_rng(2)
    A, B = random_pose(rng), random_pose(rng)
    np.testing.assert_allclose(plucker.se3_exp(plucker.se3_log(A)), A, atol=1e-12)
    T, J_a, J_b = plucker.compose(A, B)
    np.testing.assert_allclose(T, A @ B, atol=1e-12)
    J_a_num = numeric_jacobian(lambda d: plucker.se3_minus(plucker.se3_plus(A, d) @ B, T), np.zeros(6))
    J_b_num = numeric_jacobian(lambda d: plucker.se3_minus(A @ plucker.se3_plus(B, d), T), np.zeros(6))
    np.testing.assert_allclose(J_a, J_a_num, atol=1e-6)
    np.testing.assert_allclose(J_b, J_b_num, atol=1e-6)
    p, J_pose, J_p = plucker.transform_point(A, [1.0, 2.0, 3.0])
    np.testing.assert_allclose(p, A[:3, :3] @ [1.0, 2.0, 3.0] + A[:3, 3], atol=1e-12)
    np.testing.assert_allclose(J_p, A[:3, :3], atol=1e-12)


def test_lines_orthonormal_transform_and_projection():
    rng = np.random.default_rng(3)
    p1, p2 = rng.uniform(-5, 5, 3), rng.uniform(-5, 5, 3)
    L = plucker.line_from_points(p1, p2)
    np.testing.assert_allclose(L, np.concatenate([np.cross(p1, p2), p2 - p1]))
    o = plucker.line_to_orthonormal(L)
    L_unit, J = plucker.line_from_orthonormal(o)
    np.testing.assert_allclose(L_unit, L / np.linalg.norm(L), atol=1e-12)
    assert J.shape == (6, 4)
    T = random_pose(rng)
    L_a, J_T, J_L = plucker.transform_line(T, L)
    q1, q2 = T[:3, :3] @ p1 + T[:3, 3], T[:3, :3] @ p2 + T[:3, 3]
    np.testing.assert_allclose(L_a, plucker.line_from_points(q1, q2), atol=1e-9)
    K = [500.0, 510.0, 320.0, 240.0]
    l, J_l = plucker.project_line(K, L_a)
    np.testing.assert_allclose(l, plucker.line_intrinsics(K) @ L_a[:3], atol=1e-9)
    # Both projected endpoints lie on the image line (points in front of the camera or not).
    for q in (q1, q2):
        uv = np.array([K[0] * q[0] / q[2] + K[2], K[1] * q[1] / q[2] + K[3], 1.0])
        assert abs(l @ uv) / np.linalg.norm(l[:2]) < 1e-6


def test_triangulation_of_a_point_and_a_line():
    K = np.array([500.0, 500.0, 320.0, 240.0])
    poses = np.stack([plucker.se3_exp([0, 0, 0, x, 0, 0]) for x in (-1.0, 0.0, 1.0)])
    p_w = np.array([0.3, -0.2, 6.0])
    a_w, b_w = np.array([0.2, -1.0, 5.0]), np.array([0.4, 1.0, 6.0])

    def pixel(T, x):
        c = np.linalg.inv(T) @ np.append(x, 1.0)
        return np.array([K[0] * c[0] / c[2] + K[2], K[1] * c[1] / c[2] + K[3]])

    r = plucker.triangulate_point(K, poses, np.stack([pixel(T, p_w) for T in poses]))
    assert r["ok"], r["message"]
    np.testing.assert_allclose(r["p_w"], p_w, atol=1e-6)
    segments = np.stack([np.concatenate([pixel(T, a_w), pixel(T, b_w)]) for T in poses])
    r = plucker.triangulate_line(K, poses, segments)
    assert r["ok"], r["message"]
    for x in (a_w, b_w):
        L = r["L_w"]
        assert np.linalg.norm(np.cross(x, L[3:]) - L[:3]) / np.linalg.norm(L[3:]) < 1e-6


@pytest.mark.parametrize("call, error, text", [
    (lambda: plucker.so3_exp([1.0, 2.0]), ValueError, "w: expected shape (3,), got (2,)"),
    (lambda: plucker.so3_exp([np.nan, 0, 0]), ValueError, "w: contains NaN"),
    (lambda: plucker.so3_exp(np.array(["a", "b", "c"])), TypeError, "w: expected a real"),
    (lambda: plucker.so3_log(np.ones((3, 3))), ValueError, "R: not a rotation"),
    (lambda: plucker.compose(np.eye(4) * 2, np.eye(4)), ValueError, "T_a_b: the top-left"),
    (lambda: plucker.line_to_orthonormal([1, 0, 0, 1, 0, 0]), ValueError, "L: not a Plücker line"),
    (lambda: plucker.line_intrinsics([0, 1, 0, 0]), ValueError, "K: expected (fx, fy, cx, cy)"),
    (lambda: plucker.triangulate_point([1, 1, 0, 0], np.zeros((2, 4)), np.zeros((2, 2))), ValueError,
     "T_w_c: expected shape (N, 4, 4)"),
])
def test_bad_input_raises_with_the_argument_named(call, error, text):
    with pytest.raises(error) as e:
        call()
    assert text in str(e.value)


def test_strided_views_are_read_correctly():
    w = np.zeros((3, 2))
    w[:, 0] = [0.1, -0.2, 0.3]
    np.testing.assert_allclose(plucker.so3_exp(w[:, 0]), plucker.so3_exp([0.1, -0.2, 0.3]))
