"""Readers, writers and the trajectory metrics."""
import numpy as np
import pytest

import plucker
from conftest import random_pose


def test_kitti_bin_round_trip_and_errors(tmp_path):
    records = np.arange(40, dtype=np.float32).reshape(10, 4)
    records[3, 1] = np.nan  # dropped, as plucker lidar drops it
    path = tmp_path / "000000.bin"
    records.tofile(path)
    scan = plucker.read_kitti_bin(str(path))
    assert scan.dtype == np.float32 and scan.shape == (9, 4)
    np.testing.assert_array_equal(scan, np.delete(records, 3, axis=0))
    path.write_bytes(records.tobytes()[:-3])
    with pytest.raises(plucker.IoError, match="000000.bin"):
        plucker.read_kitti_bin(str(path))
    with pytest.raises(OSError, match="missing.bin"):
        plucker.read_kitti_bin(str(tmp_path / "missing.bin"))


def test_pcd_reader(tmp_path):
    path = tmp_path / "scan.pcd"
    path.write_text("VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
                    "COUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3 4\n5 6 7 8\n")
    scan = plucker.read_pcd(str(path))
    np.testing.assert_array_equal(scan["points"], [[1, 2, 3], [5, 6, 7]])
    np.testing.assert_array_equal(scan["intensity"], [4, 8])
    assert scan["ring"].size == 0 and scan["time"].size == 0
    path.write_text("VERSION 0.7\nFIELDS a b\n")
    with pytest.raises(plucker.IoError, match="scan.pcd"):
        plucker.read_pcd(str(path))


def test_trajectories_read_back_exactly(tmp_path):
    rng = np.random.default_rng(5)
    poses = np.stack([random_pose(rng) for _ in range(5)])
    kitti = tmp_path / "poses.txt"
    kitti.write_text(plucker.format_kitti_poses(poses))
    back = plucker.read_trajectory(str(kitti))
    np.testing.assert_allclose(back["poses"], poses, atol=1e-12)
    tum = tmp_path / "poses.tum"
    plucker.write_tum(str(tum), np.arange(5) * 0.1, poses)
    back = plucker.read_trajectory(str(tum))
    np.testing.assert_array_equal(back["times"], np.arange(5) * 0.1)
    np.testing.assert_allclose(back["poses"], poses, atol=1e-12)


def test_euroc_folder(euroc_folder):
    d = plucker.read_euroc(str(euroc_folder))
    assert len(d["images"]) == len(d["frame_times"]) > 50
    assert d["imu"].shape[1] == 7 and d["imu"].shape[0] > 1000
    assert d["camera"]["K"][0] > 100 and d["camera"]["T_b_c"].shape == (4, 4)


def test_metrics():
    rng = np.random.default_rng(6)
    gt = np.stack([plucker.se3_exp([0, 0, 0.01 * i, i, 0.1 * i, 0]) for i in range(30)])
    offset = random_pose(rng)
    est = np.stack([offset @ T for T in gt])  # the same trajectory in another frame
    r = plucker.ate(gt, est, align="se3")
    assert r["translation_m"]["rmse"] < 1e-9 and r["translation_m"]["count"] == 30
    assert plucker.ate(gt, est, align="none")["translation_m"]["rmse"] > 1e-3
    r = plucker.rpe(gt, est, delta=1)
    assert r["translation_m"]["max"] < 1e-9 and len(r["first"]) == 29
    k = plucker.kitti_metric(gt, gt)
    assert k["segment_count"] == 0 and k["translation_error_percent"] is None
    with pytest.raises(ValueError, match="align"):
        plucker.ate(gt, est, align="sim4")
    with pytest.raises(ValueError):
        plucker.ate(gt, est[:5])
