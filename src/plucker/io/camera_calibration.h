// Camera calibration files of the datasets (formats: ../shared/data/README.md), each read into a
// sensor::Camera (sensor/camera.h says which model each dataset uses) and, where the format has
// it, a pose. Every reader validates what it reads and throws io::IoError naming the file and
// the problem: file missing, a key missing, a field not a number or not finite, a wrong number of
// values, a non-positive focal length, a non-zero skew, a 3x3 block that is not a rotation.
//
//   KITTI   calib.txt   `P0: ` + 12 numbers, the 3x4 projection P = K [I | t] row-major (the
//                       other keys P1.., Tr are read only when asked for). No image size in the
//                       file: pass it, e.g. from io/image_folder.h (the clip: 1226x370).
//   Strecha K.txt       the 3x3 K, row-major (whitespace-separated); no size in the file.
//           .camera     26 numbers: K (3x3), radial distortion (3, all zero in fountain-P11: the
//                       images are undistorted; read as k1 k2 k3), R (3x3), C (3), width height.
//                       Convention (checked on the real images by vision/strecha_pose_test.cc:
//                       the epipolar geometry of matched features fits it, and not R^T):
//                       R = R_w_c, the camera-to-world rotation (columns = camera axes in the
//                       world), C = the camera centre in the world. So T_w_c = [R | C] and the
//                       world-to-camera transform is R_c_w = R^T, t_c_w = -R^T C.
//   EuRoC   sensor.yaml camera_model pinhole, intrinsics [fu, fv, cu, cv], distortion_model
//                       radial-tangential with [k1, k2, p1, p2] (a fifth value is k3),
//                       resolution [width, height], T_BS {rows: 4, cols: 4, data: 16 numbers
//                       row-major} = T_b_c (camera to body = IMU frame), rate_hz. OpenCV's
//                       `%YAML:1.0` first line is accepted.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/io/io_error.h"
#include "plucker/sensor/camera.h"

namespace plucker {
namespace io {

struct KittiCalibration {
  sensor::Camera camera;          // K from P, zero distortion, the size passed in
  Eigen::Matrix<double, 3, 4> P;  // the projection matrix as read
};

// Reads the projection `key` (default P0, the left grayscale camera) of a KITTI calib.txt.
// width/height: the image size (from the images; the file has none). Throws IoError.
KittiCalibration ReadKittiCalibration(const std::string& path, int width, int height,
                                      const std::string& key = "P0");

// Reads a Strecha K.txt (3x3 intrinsics) into an undistorted pinhole of the given size.
// Throws IoError.
sensor::Camera ReadStrechaIntrinsics(const std::string& path, int width, int height);

struct StrechaCamera {
  sensor::Camera camera;
  SE3d T_w_c;  // camera to world: rotation R of the file, translation = camera centre C
};

// Reads one Strecha `<image>.camera` file. Throws IoError.
StrechaCamera ReadStrechaCamera(const std::string& path);

// The `*.camera` files of a folder in name order (Strecha's `cameras/`), or IoError when the
// folder is missing or has none.
std::vector<std::string> ListStrechaCameraFiles(const std::string& dir);

struct EurocCamera {
  sensor::Camera camera;
  SE3d T_b_c;            // T_BS: camera (sensor) frame to body (IMU) frame, p_b = T_b_c p_c
  double rate_hz = 0.0;  // 0 when absent
};

// Reads an EuRoC camera `sensor.yaml` (mav0/cam0/sensor.yaml). Throws IoError.
EurocCamera ReadEurocCamera(const std::string& path);

}  // namespace io
}  // namespace plucker
