"""The online camera pipelines from Python: VisualInertialOdometry fed the shared EuRoC head (and
the MH_05 clip's first frames) in time order gives the poses of `plucker vio --euroc` (--out and
--out-online) bit for bit,
MonocularOdometry fed the first KITTI clip images those of `plucker vo --images`; bad input."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import plucker
from conftest import _shared_data, run_in_two_threads

KITTI_CLIP_FRAMES = 15  # enough for the start and a few tracked frames, small under ASan
MH05_PREFIX_FRAMES = 135  # the online start is at frame 112 on the whole clip (it waits for a 60 deg turn)


def poses_lines(path: pathlib.Path):
    return [line for line in path.read_text().splitlines() if not line.startswith("#")]


def run_vio(euroc: dict, **options):
    """The loop of `plucker vio`: the IMU up to each image's time, then the image."""
    # T_b_c_tq: the extrinsic's own numbers (a 4x4's quaternion rounds in the last bit)
    vio = plucker.VisualInertialOdometry(euroc["camera"], euroc["camera"]["T_b_c_tq"],
                                         euroc["imu_model"], **options)
    imu = euroc["imu"]
    fed, online = 0, []
    for t, path in zip(euroc["frame_times"], euroc["images"]):
        # every sample before t and the first one at or after it
        end = min(int(np.searchsorted(imu[:, 0], t, side="left")) + 1, len(imu))
        if end > fed:
            vio.add_imu(imu[fed:end])
            fed = end
        result = vio.add_image(float(t), plucker.read_gray_image(path))
        assert result["frame"] == len(online) and result["status"] != "failed"
        online.append(result)
    vio.add_imu(imu[fed:])
    end = vio.finish()
    return vio, online, end


def tum_rows(path: pathlib.Path):
    """The stamps (text) and the poses tx ty tz qx qy qz qw (shortest exact text: the doubles)."""
    rows = [line.split() for line in poses_lines(path)]
    return [r[0] for r in rows], np.array([[float(v) for v in r[1:]] for r in rows]).reshape(-1, 7)


def same_as_file(times, poses_tq, path: pathlib.Path, origin_ns: int, tmp_path: pathlib.Path):
    """The poses are the file's numbers bit for bit; their stamps are its text on the clock."""
    stamps, cli = tum_rows(path)
    ours = tmp_path / "stamps.tum"
    plucker.write_tum(str(ours), times, np.tile(np.eye(4), (len(times), 1, 1)),
                      origin_ns=origin_ns)
    assert tum_rows(ours)[0] == stamps
    assert np.array_equal(np.asarray(poses_tq).reshape(-1, 7), cli)


def vio_against_the_command_line(folder, plucker_cli, tmp_path):
    out, out_online = tmp_path / "cli.tum", tmp_path / "cli-online.tum"
    subprocess.run([plucker_cli, "vio", "--euroc", str(folder), "--out", str(out),
                    "--out-online", str(out_online), "--quiet"], check=True)
    euroc = plucker.read_euroc(str(folder))
    vio, online, end = run_vio(euroc)
    assert vio.initialized and vio.initialization["done"]
    with_pose = [r for r in online if r["T_w_b"] is not None]
    same_as_file([r["time"] for r in with_pose], [r["T_w_b_tq"] for r in with_pose], out_online,
                 euroc["origin_ns"], tmp_path)
    refined = vio.refined_trajectory()
    assert refined["frames_given"] == len(online)
    same_as_file(refined["times"], refined["T_w_b_tq"], out, euroc["origin_ns"], tmp_path)
    assert len(poses_lines(out)) == len(refined["times"]) == len(online)
    settled = [s["frame"] for r in online + [end] for s in r["settled"]]
    assert settled == list(range(len(online)))  # each frame settles once, in order
    return vio, online, end


def test_vio_euroc_head_same_trajectories_as_the_command_line(euroc_folder, plucker_cli,
                                                              tmp_path):
    # The drone stands still throughout: the static start decides at finish(), so every pose is
    # a refined one (the online trajectory is empty, in both).
    vio, online, end = vio_against_the_command_line(euroc_folder, plucker_cli, tmp_path)
    assert vio.initialization["method"] == "static"
    assert all(r["status"] == "initializing" and r["T_w_b"] is None for r in online)
    assert len(end["settled"]) == len(online) and end["settled"][-1]["T_w_b"].shape == (4, 4)


@pytest.fixture
def euroc_mh05_prefix(tmp_path) -> pathlib.Path:
    """The first MH05_PREFIX_FRAMES images of the MH_05 clip (the dynamic start and ~20 tracked
    frames), the rest of the folder linked."""
    if os.environ.get("PLUCKER_ASAN_RUNTIME"):
        pytest.skip("the MH_05 prefix (~8 s CPU in Release) runs in the Release tests only")
    clip = _shared_data() / "euroc-mh05-clip" / "mav0"
    if not (clip / "cam0").is_dir():
        pytest.skip(f"shared EuRoC MH_05 clip not found at {clip}")
    mav0 = tmp_path / "mh05" / "mav0"
    (mav0 / "cam0").mkdir(parents=True)
    for entry in clip.iterdir():
        if entry.name != "cam0":
            (mav0 / entry.name).symlink_to(entry)
    for entry in ("data", "sensor.yaml"):
        (mav0 / "cam0" / entry).symlink_to(clip / "cam0" / entry)
    rows = (clip / "cam0" / "data.csv").read_text().splitlines(keepends=True)
    (mav0 / "cam0" / "data.csv").write_text("".join(rows[:1 + MH05_PREFIX_FRAMES]))
    return mav0.parent


def test_vio_euroc_mh05_online_poses_same_as_the_command_line(euroc_mh05_prefix, plucker_cli,
                                                              tmp_path):
    vio, online, _ = vio_against_the_command_line(euroc_mh05_prefix, plucker_cli, tmp_path)
    assert vio.initialization["method"] == "dynamic"
    tracked = [r for r in online if r["T_w_b"] is not None]
    assert len(tracked) >= 10, [r["status"] for r in online]
    r = tracked[-1]
    assert r["T_w_b"].shape == (4, 4) and r["v_w"].shape == (3,) and r["gyro_bias"].shape == (3,)
    assert np.linalg.norm(r["v_w"]) > 0.1  # the drone has taken off
    assert isinstance(r["window"]["tracked_points"], int) and r["observed_points"] > 0


def kitti_clip(tmp_path: pathlib.Path, data: pathlib.Path):
    images = sorted((data / "image_0").glob("*.png"))[:KITTI_CLIP_FRAMES]
    folder = tmp_path / "clip"
    folder.mkdir()
    for f in images:
        (folder / f.name).symlink_to(f)
    P0 = next(line for line in (data / "calib.txt").read_text().splitlines()
              if line.startswith("P0:"))
    P = [float(v) for v in P0.split()[1:]]
    first = plucker.read_gray_image(str(images[0]))
    camera = {"K": [P[0], P[5], P[2], P[6]], "width": first.shape[1], "height": first.shape[0]}
    return folder, camera, [str(f) for f in images]


@pytest.fixture
def kitti_mono_clip() -> pathlib.Path:
    folder = _shared_data() / "kitti-mono-clip"
    if not (folder / "image_0").is_dir():
        pytest.skip(f"shared KITTI mono clip not found at {folder}")
    return folder


def nan_where_missing(results):
    nan = np.full((4, 4), np.nan)
    return np.stack([r["T_w_c"] if r["has_pose"] else nan for r in results])


def run_vo(camera, images, rate_hz=10.0):
    vo = plucker.MonocularOdometry(camera)
    results = [vo.add_image(i / rate_hz, plucker.read_gray_image(f)) for i, f in enumerate(images)]
    vo.finish()
    return vo, results


def test_vo_same_trajectories_as_the_command_line(kitti_mono_clip, plucker_cli, tmp_path):
    folder, camera, images = kitti_clip(tmp_path, kitti_mono_clip)
    out, out_online = tmp_path / "cli.txt", tmp_path / "cli-online.txt"
    subprocess.run([plucker_cli, "vo", "--images", str(folder), "--calib",
                    str(kitti_mono_clip / "calib.txt"), "--out", str(out), "--out-online",
                    str(out_online), "--quiet"], check=True)
    vo, results = run_vo(camera, images)
    trajectory = vo.trajectory()
    assert trajectory["T_w_c"].shape == (len(images), 4, 4)
    assert vo.summary["maps"] >= 1 and any(r["has_pose"] for r in results)
    assert plucker.format_kitti_poses(trajectory["T_w_c"]) == out.read_text()
    assert plucker.format_kitti_poses(nan_where_missing(results)) == out_online.read_text()


def test_two_vo_in_two_threads_give_the_sequential_poses(kitti_mono_clip, tmp_path):
    _, camera, images = kitti_clip(tmp_path, kitti_mono_clip)
    images = images[:8]
    sequential = run_vo(camera, images)[0].trajectory()["T_w_c"]
    for poses in run_in_two_threads(lambda: run_vo(camera, images)[0].trajectory()["T_w_c"]):
        assert np.array_equal(poses, sequential)


CAMERA = {"K": [450.0, 450.0, 320.0, 240.0], "width": 640, "height": 480}
IMU = {"gyro_noise_density": 1.7e-4, "accel_noise_density": 2e-3}


def test_vio_options_are_the_config_keys():
    plucker.VisualInertialOdometry(CAMERA, np.eye(4), IMU, window={"size": 8}, use_lines=False,
                                   time_offset={"estimate": True, "initial_s": 0.002})
    with pytest.raises(ValueError, match="unknown key 'windw.size'"):
        plucker.VisualInertialOdometry(CAMERA, np.eye(4), IMU, windw={"size": 8})
    with pytest.raises(ValueError, match="key 'window.size': expected"):
        plucker.VisualInertialOdometry(CAMERA, np.eye(4), IMU, window={"size": "many"})
    with pytest.raises(ValueError, match="window.size"):
        plucker.VisualInertialOdometry(CAMERA, np.eye(4), IMU, **{"window.size": 1})
    # A features-folder reader option: refused, add_frame is given the points to use.
    with pytest.raises(ValueError, match="point_stride selects the tracks"):
        plucker.VisualInertialOdometry(CAMERA, np.eye(4), IMU, point_stride=2)
    with pytest.raises(ValueError, match="point_stride selects the tracks"):
        plucker.VisualInertialOdometry(CAMERA, np.eye(4), IMU, input={"point_stride": 2})
    numpy_ints = dict(CAMERA, width=np.int64(640), height=np.int32(480))
    plucker.VisualInertialOdometry(numpy_ints, np.eye(4), IMU)
    with pytest.raises(TypeError, match=r"camera\['width'\]: expected an integer"):
        plucker.VisualInertialOdometry(dict(CAMERA, width=640.0), np.eye(4), IMU)
    with pytest.raises(ValueError, match="camera needs 'width'"):
        plucker.VisualInertialOdometry({"K": [1.0, 1.0, 0.0, 0.0]}, np.eye(4), IMU)
    with pytest.raises(ValueError, match="unknown imu_model key 'gyro_noise'"):
        plucker.VisualInertialOdometry(CAMERA, np.eye(4), {"gyro_noise": 1.0})
    with pytest.raises(ValueError, match="T_b_c"):
        plucker.VisualInertialOdometry(CAMERA, np.ones((4, 4)), IMU)


def test_vio_bad_input_raises_with_the_message():
    vio = plucker.VisualInertialOdometry(CAMERA, np.eye(4), IMU)
    vio.add_imu(0.0, [0, 0, 0], [0, 0, 9.81])
    with pytest.raises(ValueError, match="sample 1 .*times must increase"):
        vio.add_imu(np.array([[0.1, 0, 0, 0, 0, 0, 9.81], [0.05, 0, 0, 0, 0, 0, 9.81]]))
    vio.add_imu(0.1, [0, 0, 0], [0, 0, 9.81])  # nothing of the bad batch was added
    with pytest.raises(ValueError, match="row 0 contains NaN"):
        vio.add_imu(np.array([[0.2, np.nan, 0, 0, 0, 0, 9.81]]))
    with pytest.raises(ValueError, match=r"shape \(N, 7\)"):
        vio.add_imu(np.zeros((3, 6)))
    with pytest.raises(TypeError, match="uint8"):
        vio.add_image(0.1, np.zeros((480, 640), np.float32))
    with pytest.raises(ValueError, match=r"shape \(H, W\)"):
        vio.add_image(0.1, np.zeros((480, 640, 3), np.uint8))
    with pytest.raises(ValueError, match="contiguous"):
        vio.add_image(0.1, np.zeros((480, 1280), np.uint8)[:, ::2])
    with pytest.raises(ValueError, match="t is not finite"):
        vio.add_image(float("nan"), np.zeros((480, 640), np.uint8))
    with pytest.raises(ValueError):  # the C++ message: another size than the calibration
        vio.add_image(0.1, np.zeros((240, 320), np.uint8))
    with pytest.raises(ValueError, match=r"points: expected shape \(N, 3\)"):
        vio.add_frame(0.1, np.zeros((4, 2)))
    result = vio.add_frame(0.1, np.array([[0, 100.0, 100.0]]), np.zeros((0, 5)))
    assert result["status"] == "initializing" and result["T_w_b"] is None


def test_vo_options_and_bad_input():
    plucker.MonocularOdometry(CAMERA, window={"size": 8}, **{"points.max_tracks": 150})
    plucker.MonocularOdometry([450.0, 450.0, 320.0, 240.0], defaults="features", pixel_sigma=1.0)
    with pytest.raises(ValueError, match="unknown key 'window.sise'"):
        plucker.MonocularOdometry(CAMERA, window={"sise": 8})
    with pytest.raises(ValueError, match="window.size.*out of range"):
        plucker.MonocularOdometry(CAMERA, **{"window.size": 1})
    with pytest.raises(ValueError, match="defaults"):
        plucker.MonocularOdometry(CAMERA, defaults="video")
    vo = plucker.MonocularOdometry(CAMERA)
    with pytest.raises(ValueError, match="the image is 320x240, the camera 640x480"):
        vo.add_image(0.0, np.zeros((240, 320), np.uint8))
    with pytest.raises(ValueError, match=r"segments: row 0 contains NaN"):
        vo.add_frame(0.0, None, np.array([[0, 1, 2, np.nan, 4]]))
    assert vo.add_image(0.0, np.zeros((480, 640), np.uint8))["status"] == "initializing"


def test_read_gray_image_errors(tmp_path):
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"not an image")
    with pytest.raises(plucker.IoError, match="bad.png"):
        plucker.read_gray_image(str(bad))
