"""add_frame against `plucker vio --features` and `plucker vo --features`: a simulated features
folder read with read_features and fed frame by frame gives the command line's poses bit for
bit (refined and online), lines included; read_features' errors."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import plucker
from test_online import poses_lines, same_as_file


def cli_usable(cli: str) -> bool:
    return bool(cli) and os.access(cli, os.X_OK)

FRAMES = 40  # a simulated room: the dynamic start at frame ~31, then tracking


@pytest.fixture(scope="module")
def features(tmp_path_factory) -> pathlib.Path:
    plucker_cli = os.environ.get("PLUCKER_CLI", "")
    if not cli_usable(plucker_cli):
        pytest.skip("PLUCKER_CLI (the plucker program) is not set")
    folder = tmp_path_factory.mktemp("features") / "room"
    subprocess.run([plucker_cli, "sim", "camera", "--out", str(folder), "--scene", "room",
                    "--frames", str(FRAMES), "--seed", "3"], check=True, capture_output=True)
    return folder


def run_vio_frames(data: dict):
    vio = plucker.VisualInertialOdometry(data["camera"], data["camera"]["T_b_c_tq"],
                                         data["imu_model"],
                                         gravity_magnitude=data["gravity_magnitude"],
                                         pixel_sigma=data["pixel_sigma"])
    imu, fed, online = data["imu"], 0, []
    for t, points, segments in zip(data["frame_times"], data["points"], data["segments"]):
        end = min(int(np.searchsorted(imu[:, 0], t, side="left")) + 1, len(imu))
        if end > fed:
            vio.add_imu(imu[fed:end])
            fed = end
        online.append(vio.add_frame(float(t), points, segments))
    vio.add_imu(imu[fed:])
    vio.finish()
    return vio, online


def test_vio_add_frame_same_as_the_command_line(features, plucker_cli, tmp_path):
    out, out_online = tmp_path / "cli.tum", tmp_path / "cli-online.tum"
    subprocess.run([plucker_cli, "vio", "--features", str(features), "--out", str(out),
                    "--out-online", str(out_online), "--quiet"], check=True)
    data = plucker.read_features(str(features))
    assert len(data["frame_times"]) == FRAMES and data["warnings"] == []
    assert data["ground_truth_T_w_b"].shape == (FRAMES, 4, 4)
    assert any(len(s) > 0 for s in data["segments"])  # lines are fed too
    vio, online = run_vio_frames(data)
    assert vio.initialized
    with_pose = [r for r in online if r["T_w_b"] is not None]
    assert len(with_pose) >= 5
    same_as_file([r["time"] for r in with_pose], [r["T_w_b_tq"] for r in with_pose], out_online,
                 None, tmp_path)
    refined = vio.refined_trajectory()
    same_as_file(refined["times"], refined["T_w_b_tq"], out, None, tmp_path)
    assert len(poses_lines(out)) == FRAMES


def test_vo_add_frame_same_as_the_command_line(features, plucker_cli, tmp_path):
    out = tmp_path / "cli.txt"
    subprocess.run([plucker_cli, "vo", "--features", str(features), "--out", str(out),
                    "--quiet"], check=True)
    data = plucker.read_features(str(features))
    vo = plucker.MonocularOdometry(data["camera"]["K"], defaults="features",
                                   pixel_sigma=data["pixel_sigma"])
    for t, points, segments in zip(data["frame_times"], data["points"], data["segments"]):
        vo.add_frame(float(t), points, segments)
    vo.finish()
    assert plucker.format_kitti_poses(vo.trajectory()["T_w_c"]) == out.read_text()


def test_read_features_stride_and_errors(features, tmp_path):
    every = plucker.read_features(str(features))
    half = plucker.read_features(str(features), point_stride=2)
    for a, b in zip(every["points"], half["points"]):
        assert np.array_equal(a[a[:, 0] % 2 == 0], b)
    with pytest.raises(ValueError, match="point_stride must be >= 1"):
        plucker.read_features(str(features), point_stride=0)
    with pytest.raises(plucker.IoError, match="rig.txt"):
        plucker.read_features(str(tmp_path / "nothing"))
