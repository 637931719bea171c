// Kalibr calibration files (and OpenVINS' variant of them), read into plucker's types.
//
//   camchain.yaml / camchain-imucam.yaml (Kalibr), kalibr_imucam_chain.yaml (OpenVINS): one map
//   per camera, keys cam0, cam1, ... (numbered from 0 without gaps), each with
//     camera_model       `pinhole` (omni, ds, eucm are refused by name)
//     intrinsics         [fu, fv, pu, pv]
//     distortion_model   `radtan`: distortion_coeffs [k1, k2, p1, p2]
//                        `equidistant`: distortion_coeffs [k1, k2, k3, k4] (Kannala-Brandt,
//                        geometry/equidistant.h); anything else is refused by name
//     resolution         [width, height]
//     T_cam_imu          optional 4x4 (4 rows of 4 numbers): IMU to camera, p_c = T_cam_imu p_imu,
//                        so T_b_c = T_cam_imu^-1 (the body frame b is the IMU's)
//     T_imu_cam          OpenVINS' key instead: camera to IMU, T_b_c itself
//     T_cn_cnm1          optional 4x4: the previous camera to this one (cam1: T_c1_c0)
//     timeshift_cam_imu  optional, s: t_imu = t_cam + timeshift_cam_imu
//     rostopic, cam_overlaps and other keys are ignored.
//   Every 4x4 must be rigid: last row exactly (0, 0, 0, 1), rotation block orthonormal within
//   1e-6 (max |R^T R - I|) with det > 0; it is then projected onto the nearest rotation (SVD), as
//   the EuRoC reader does, so the same numbers give the same SE3d.
//   imu.yaml (Kalibr; OpenVINS' kalibr_imu_chain.yaml has the same keys under imu0):
//     accelerometer_noise_density, accelerometer_random_walk, gyroscope_noise_density,
//     gyroscope_random_walk, update_rate: all > 0, into sensor::ImuModel.
// Errors: io::IoError naming the file, the key (e.g. "cam1.T_cn_cnm1") and the problem.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/io/io_error.h"
#include "plucker/sensor/camera.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace io {

struct KalibrCamera {
  std::string name;  // "cam0", "cam1", ...
  sensor::Camera camera;
  // Camera to body (IMU): T_cam_imu inverted, or T_imu_cam as read; empty when neither is given.
  std::optional<SE3d> T_b_c;
  std::optional<SE3d> T_cn_cnm1;   // previous camera to this one, as read (cam1: T_c1_c0)
  double timeshift_cam_imu = 0.0;  // s; t_imu = t_cam + timeshift_cam_imu (0 when absent)
};

struct KalibrCameraChain {
  std::string path;
  std::vector<KalibrCamera> cameras;  // cam0, cam1, ... in order, at least one

  // T_b_c of camera `index`, for visual-inertial use: IoError naming the file and the missing
  // key (cam0.T_cam_imu) when the chain has no IMU extrinsic for it (a camchain.yaml from a
  // camera-only calibration), or when there is no such camera.
  SE3d RequireT_b_c(std::size_t index = 0) const;
};

// Reads a camchain; `path` names the file in errors. Throws IoError.
KalibrCameraChain ReadKalibrCameraChain(const std::string& path);
KalibrCameraChain ParseKalibrCameraChain(const std::string& text, const std::string& path);

// Reads a Kalibr imu.yaml (or OpenVINS' kalibr_imu_chain.yaml). Throws IoError.
sensor::ImuModel ReadKalibrImu(const std::string& path);
sensor::ImuModel ParseKalibrImu(const std::string& text, const std::string& path);

}  // namespace io
}  // namespace plucker
