"""A typed use of the package for mypy --strict (run_mypy.sh): every stub is exercised."""
from typing import Any, Dict

import numpy as np
import numpy.typing as npt

import plucker
from plucker import factors


def top_view(poses: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    return poses[:, :2, 3]


def main() -> None:
    dotted: Dict[str, Any] = {"features.min_range": 2.0}
    odometry = plucker.LidarOdometry(**dotted, registration={"use_edges": True})
    scan: npt.NDArray[np.float32] = plucker.read_kitti_bin("scan.bin")
    T_w_l: npt.NDArray[np.float64] = odometry.register(scan, timestamp=0.0)
    print(T_w_l, top_view(odometry.poses), odometry.local_map("planes").shape, odometry.last_frame)
    R = plucker.so3_exp(np.zeros(3))
    w = plucker.so3_log(R)
    T = plucker.se3_exp(np.zeros(6))
    T_ac, J_ab, J_bc = plucker.compose(T, T)
    L = plucker.line_from_points([0.0, 0.0, 1.0], [1.0, 0.0, 1.0])
    L_a, J_T, J_L = plucker.transform_line(T, L)
    p = plucker.line_to_orthonormal(L)
    L2, J = plucker.line_from_orthonormal(p)
    l, J_l = plucker.project_line([500.0, 500.0, 320.0, 240.0], L)
    f = factors.point_to_plane([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0])
    r, jacobians = f.evaluate([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    result = plucker.ate(odometry.poses, odometry.poses, align="se3")
    rmse: float = result["translation_m"]["rmse"]
    print(w, T_ac, J_ab, J_bc, L_a, J_T, J_L, L2, J, l, J_l, r, jacobians[0], rmse,
          plucker.lidar_options()["features.min_range"], plucker.format_kitti_poses(odometry.poses))
    euroc = plucker.read_euroc("euroc")
    vio = plucker.VisualInertialOdometry(euroc["camera"], euroc["camera"]["T_b_c"],
                                         euroc["imu_model"], window={"size": 8}, use_lines=False)
    vio.add_imu(euroc["imu"])
    vio.add_imu(10.0, [0.0, 0.0, 0.0], [0.0, 0.0, 9.81])
    image: npt.NDArray[np.uint8] = plucker.read_gray_image(euroc["images"][0])
    frame: Dict[str, Any] = vio.add_image(float(euroc["frame_times"][0]), image)
    vio.finish()
    refined = vio.refined_trajectory()
    plucker.write_tum("vio.tum", refined["times"], refined["T_w_b"], origin_ns=euroc["origin_ns"],
                      comments=["body frame"])
    print(frame["status"], vio.initialized, vio.initialization, vio.time_offset, vio.T_b_c)
    vo = plucker.MonocularOdometry([700.0, 700.0, 600.0, 180.0], defaults="features",
                                   window={"size": 8}, pixel_sigma=1.0)
    vo.add_frame(0.0, np.zeros((0, 3)), None)
    vo.add_image(0.1, image)
    vo.finish()
    print(vo.trajectory()["T_w_c"].shape, vo.summary["keyframes"])
    try:
        plucker.read_pcd("missing.pcd")
    except plucker.IoError as e:
        print(e)
