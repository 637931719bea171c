// The calibration of the image commands (`vo`, `vio`, `lines track`, `sfm`) from one set of
// flags, read by one function, with one undistortion rule (docs/cli.md, "Cameras and
// calibrations"):
//   --sensor sensor.yaml   EuRoC cam0 sensor.yaml: intrinsics, distortion, resolution, T_BS (T_b_c)
//   --calib FILE           a KITTI calib.txt (P0, rectified: a pinhole of the images' size) or a
//                          Kalibr camchain.yaml / camchain-imucam.yaml / OpenVINS
//                          kalibr_imucam_chain.yaml (cam0; told apart by the file's content: a
//                          `cam0:` key is Kalibr's); T_cam_imu inverted for T_b_c
//   --intrinsics K.txt     a Strecha K.txt (lines, sfm)
//   --imu-sensor FILE      EuRoC imu0 sensor.yaml (vio): the IMU noise model
//   --imu-calib imu.yaml   Kalibr imu.yaml (vio): the IMU noise model
// The undistortion rule (the same in every command): a camera with lens distortion (radial-
// tangential with coefficients, or equidistant: Kannala-Brandt, Kalibr `equidistant`) has its
// images undistorted as a whole into the pinhole of its own K and size before anything is
// detected (vision::Undistorter; for a fisheye that is the lens's central view, see
// vision/undistort.h); a pinhole camera (KITTI, Strecha, zero distortion) is used as it is.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/sensor/camera.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace app {

struct CameraFlags {
  std::string sensor, calib, intrinsics;  // one of them
  std::string imu_sensor, imu_calib;      // at most one (vio)
  bool offers_intrinsics = false;         // set by AddCameraFlags, for the messages
};

// Which flags a command offers.
struct CameraFlagSet {
  bool intrinsics = false;  // --intrinsics K.txt
  bool imu = false;         // --imu-sensor, --imu-calib
};

void AddCameraFlags(CLI::App* cmd, CameraFlags* flags, const CameraFlagSet& set);

struct CameraCalibration {
  sensor::Camera camera;                // the raw camera of the images
  std::string source;                   // the file it came from, for messages
  bool has_camera = false;              // a camera flag was given (see ReadCameraCalibration)
  bool kalibr = false;                  // --calib was a Kalibr camchain
  std::optional<SE3d> T_b_c;            // EuRoC T_BS, Kalibr T_cam_imu^-1 (or T_imu_cam)
  double timeshift_cam_imu = 0.0;       // Kalibr: t_imu = t_cam + timeshift_cam_imu
  std::optional<sensor::ImuModel> imu;  // --imu-sensor / --imu-calib
  std::string missing_T_b_c;            // why there is no T_b_c (the file and key named)
  // Names the missing key/file when the calibration has no T_b_c (for visual-inertial use).
  SE3d RequireT_b_c() const;
};

// True when a camera flag was given (exactly one is required by ReadCameraCalibration).
bool HasCameraFlag(const CameraFlags& flags);

// Reads the flags (camera_required false: no camera flag is fine, has_camera tells). width/height:
// the images' size (KITTI and Strecha files have none; the others are checked against it; 0: not
// known yet, not checked). Throws std::invalid_argument for a wrong combination of flags,
// io::IoError for a file that does not parse, a size that differs from the images'.
CameraCalibration ReadCameraCalibration(const CameraFlags& flags, int width = 0, int height = 0,
                                        bool camera_required = true);

// The undistortion rule: whether the images of `camera` are undistorted before detection.
// Throws io::IoError naming `source` for an invalid camera.
bool NeedsUndistortion(const sensor::Camera& camera, const std::string& source);

// The files the flags name (for RefuseOverwritingInputs).
std::vector<std::string> CameraFlagFiles(const CameraFlags& flags);

// std::runtime_error "OUT: refusing to overwrite an input file" when an output (empty: none) is
// one of the inputs (the same file by path or by identity).
void RefuseOverwritingInputs(const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outputs);

}  // namespace app
}  // namespace plucker
