#include "camera_input.h"

#include <filesystem>
#include <stdexcept>

#include "plucker/io/camera_calibration.h"
#include "plucker/io/euroc_imu.h"
#include "plucker/io/io_error.h"
#include "plucker/io/kalibr_calibration.h"
#include "plucker/io/kitti_lidar.h"

namespace plucker {
namespace app {
namespace {

// A Kalibr camchain has a top-level `cam0:` key; a KITTI calib.txt has `P0:` rows.
bool IsKalibrCameraChain(const std::string& path) {
  const std::string text = io::ReadFileToString(path);
  return text.rfind("cam0:", 0) == 0 || text.find("\ncam0:") != std::string::npos;
}

void CheckSize(const sensor::Camera& camera, const std::string& path, int width, int height) {
  if (width <= 0 || height <= 0) return;
  if (camera.width == width && camera.height == height) return;
  throw io::IoError(path, "resolution " + std::to_string(camera.width) + "x" +
                              std::to_string(camera.height) + " differs from the images' " +
                              std::to_string(width) + "x" + std::to_string(height));
}

void ReadImuFlags(const CameraFlags& f, CameraCalibration* c) {
  if (!f.imu_sensor.empty() && !f.imu_calib.empty())
    throw std::invalid_argument(
        "give at most one of --imu-sensor sensor.yaml, --imu-calib imu.yaml");
  if (!f.imu_sensor.empty())
    c->imu = io::ParseEurocImuYaml(io::ReadFileToString(f.imu_sensor), f.imu_sensor);
  if (!f.imu_calib.empty()) c->imu = io::ReadKalibrImu(f.imu_calib);
}

}  // namespace

void AddCameraFlags(CLI::App* cmd, CameraFlags* flags, const CameraFlagSet& set) {
  cmd->add_option("--sensor", flags->sensor,
                  "EuRoC cam0 sensor.yaml (intrinsics, radial-tangential distortion: the images "
                  "are undistorted first; T_BS)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--calib", flags->calib,
                  "KITTI calib.txt (P0, rectified images) or Kalibr camchain.yaml / "
                  "camchain-imucam.yaml (cam0; T_cam_imu, timeshift_cam_imu)")
      ->check(CLI::ExistingFile);
  flags->offers_intrinsics = set.intrinsics;
  if (set.intrinsics) {
    cmd->add_option("--intrinsics", flags->intrinsics, "Strecha K.txt (undistorted images)")
        ->check(CLI::ExistingFile);
  }
  if (set.imu) {
    cmd->add_option("--imu-sensor", flags->imu_sensor,
                    "EuRoC imu0 sensor.yaml: the IMU noise model")
        ->check(CLI::ExistingFile);
    cmd->add_option("--imu-calib", flags->imu_calib, "Kalibr imu.yaml: the IMU noise model")
        ->check(CLI::ExistingFile);
  }
}

bool HasCameraFlag(const CameraFlags& f) {
  return !f.sensor.empty() || !f.calib.empty() || !f.intrinsics.empty();
}

SE3d CameraCalibration::RequireT_b_c() const {
  if (T_b_c) return *T_b_c;
  throw std::runtime_error(missing_T_b_c);
}

CameraCalibration ReadCameraCalibration(const CameraFlags& f, int width, int height,
                                        bool camera_required) {
  const int given = !f.sensor.empty() + !f.calib.empty() + !f.intrinsics.empty();
  CameraCalibration c;
  if (given == 0 && !camera_required) {
    ReadImuFlags(f, &c);
    return c;
  }
  if (given != 1) {
    throw std::invalid_argument(std::string("give exactly one of ") +
                                (f.offers_intrinsics ? "--intrinsics K.txt, " : "") +
                                "--calib calib.txt|camchain.yaml or --sensor sensor.yaml" +
                                (given > 1 ? " (several given)" : ""));
  }
  c.has_camera = true;
  if (!f.sensor.empty()) {
    const io::EurocCamera e = io::ReadEurocCamera(f.sensor);
    c.source = f.sensor, c.camera = e.camera, c.T_b_c = e.T_b_c;
    CheckSize(c.camera, c.source, width, height);
  } else if (!f.intrinsics.empty()) {
    c.source = f.intrinsics;
    c.camera = io::ReadStrechaIntrinsics(f.intrinsics, std::max(width, 1), std::max(height, 1));
    c.missing_T_b_c = f.intrinsics + ": a K.txt has no camera-IMU extrinsic";
  } else if (IsKalibrCameraChain(f.calib)) {
    const io::KalibrCameraChain chain = io::ReadKalibrCameraChain(f.calib);
    const io::KalibrCamera& cam0 = chain.cameras[0];
    c.source = f.calib, c.kalibr = true, c.camera = cam0.camera, c.T_b_c = cam0.T_b_c;
    c.timeshift_cam_imu = cam0.timeshift_cam_imu;
    try {
      chain.RequireT_b_c(0);
    } catch (const io::IoError& e) {
      c.missing_T_b_c = std::string(e.what()) + ": needed for visual-inertial use";
    }
    CheckSize(c.camera, c.source, width, height);
  } else {
    c.source = f.calib;
    c.camera = io::ReadKittiCalibration(f.calib, std::max(width, 1), std::max(height, 1)).camera;
    c.missing_T_b_c = f.calib +
                      ": a KITTI calib.txt has no camera-IMU extrinsic (give --sensor "
                      "sensor.yaml or a Kalibr camchain-imucam.yaml)";
  }
  ReadImuFlags(f, &c);
  return c;
}

std::vector<std::string> CameraFlagFiles(const CameraFlags& f) {
  std::vector<std::string> files;
  for (const std::string* s : {&f.sensor, &f.calib, &f.intrinsics, &f.imu_sensor, &f.imu_calib})
    if (!s->empty()) files.push_back(*s);
  return files;
}

void RefuseOverwritingInputs(const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outputs) {
  namespace fs = std::filesystem;
  for (const std::string& out : outputs) {
    if (out.empty()) continue;
    for (const std::string& in : inputs) {
      std::error_code ec;
      if (in.empty()) continue;
      if (fs::weakly_canonical(out, ec) == fs::weakly_canonical(in, ec) ||
          (fs::exists(out, ec) && fs::equivalent(out, in, ec)))
        throw std::runtime_error(out + ": refusing to overwrite an input file");
    }
  }
}

bool NeedsUndistortion(const sensor::Camera& camera, const std::string& source) {
  const std::string problem = camera.Problem();
  if (!problem.empty()) throw io::IoError(source, problem);
  return !camera.IsPinhole();  // radtan with coefficients, or equidistant (always)
}

}  // namespace app
}  // namespace plucker
