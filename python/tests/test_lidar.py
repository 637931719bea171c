"""LidarOdometry from Python: the same poses as `plucker lidar --frame lidar` (byte-identical
text), two odometries in two threads, the options of `plucker config lidar`, and bad input."""
import subprocess

import numpy as np
import pytest

import plucker
from conftest import run_in_two_threads


def scans(sequence, count=None):
    files = sorted((sequence / "velodyne").glob("*.bin"))[:count]
    times = plucker.read_kitti_times(str(sequence / "times.txt"))
    return [(plucker.read_kitti_bin(str(f)), float(times[i])) for i, f in enumerate(files)]


def test_same_poses_as_the_command_line(kitti_sequence, plucker_cli, tmp_path):
    out = tmp_path / "cli.txt"
    subprocess.run([plucker_cli, "lidar", "--data", str(kitti_sequence), "--out", str(out),
                    "--frame", "lidar", "--quiet"], check=True)
    odometry = plucker.LidarOdometry()
    poses = [odometry.register(points, timestamp=t) for points, t in scans(kitti_sequence)]
    assert np.array_equal(np.stack(poses), odometry.poses)
    assert np.array_equal(poses[0], np.eye(4))
    assert np.linalg.norm(poses[-1][:3, 3]) > 5.0  # the car drove ~13 m
    assert plucker.format_kitti_poses(odometry.poses) == out.read_text()
    assert odometry.local_map().shape[1] == 3 and len(odometry.local_map("edges")) > 0


def test_two_odometries_in_two_threads_give_the_sequential_poses(kitti_sequence):
    data = scans(kitti_sequence, 4)
    sequential = plucker.LidarOdometry()
    for points, t in data:
        sequential.register(points, t)

    def run():
        o = plucker.LidarOdometry()
        for points, t in data:
            o.register(points, t)
        return o.poses

    for poses in run_in_two_threads(run):
        assert np.array_equal(poses, sequential.poses)


def test_options_are_the_command_lines(plucker_cli):
    text = subprocess.run([plucker_cli, "config", "lidar"], check=True, capture_output=True,
                          text=True).stdout
    assert plucker.lidar_config_yaml() == text
    o = plucker.LidarOdometry(**{"features.min_range": 2.5}, registration={"max_iterations": 6})
    assert "min_range: 2.5" in o.config_yaml() and "max_iterations: 6" in o.config_yaml()
    assert plucker.lidar_options()["features.min_range"] != "2.5"


@pytest.mark.parametrize("kwargs, text", [
    ({"features.min_rang": 1.0}, "unknown option 'features.min_rang'"),
    ({"features": {"min_range": "near"}}, "option 'features.min_range': expected a number"),
    ({"registration.max_iterations": 2.5}, "option 'registration.max_iterations'"),
    ({"sensor": "hdl65"}, "hdl65"),
])
def test_bad_options_raise_naming_the_key(kwargs, text):
    with pytest.raises((ValueError, RuntimeError)) as e:
        plucker.LidarOdometry(**kwargs)
    assert text in str(e.value)


@pytest.mark.parametrize("points, error, text", [
    (np.zeros((10, 3), dtype=np.int32), TypeError, "float32 or float64, got dtype int32"),
    (np.zeros((10, 2)), ValueError, "shape (N, 3) or (N, 4), got (10, 2)"),
    (np.zeros((10, 6))[:, ::2], ValueError, "C-contiguous"),
    (np.array([[1.0, 2.0, np.nan]]), ValueError, "point 0 is not finite"),
    (np.zeros((0, 3)), ValueError, "no points"),
])
def test_bad_scans_raise(points, error, text):
    with pytest.raises(error) as e:
        plucker.LidarOdometry().register(points)
    assert text in str(e.value)


def test_config_file_errors_name_the_file(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("features:\n  min_range: [1, 2]\n")
    with pytest.raises(RuntimeError, match="bad.yaml"):
        plucker.LidarOdometry(config=str(bad))
