// The inertial part of a EuRoC ASL folder (../shared/data/README.md, EuRoC MAV datasets):
//   mav0/imu0/data.csv        timestamp [ns], w_x, w_y, w_z [rad/s], a_x, a_y, a_z [m/s^2]
//   mav0/imu0/sensor.yaml     rate_hz and the noise figures (gyroscope_noise_density,
//                             gyroscope_random_walk, accelerometer_noise_density,
//                             accelerometer_random_walk), T_BS (must be the identity: the body
//                             frame B is the IMU frame)
//   mav0/state_groundtruth_estimate0/data.csv (optional)
//                             time [ns], p (3), q (w, x, y, z), v (3), b_w (3), b_a (3): the body
//                             pose in the world, world-frame velocity, gyro and accel biases
// Times are returned in seconds since `origin_ns` (the first IMU timestamp by default), so that
// double precision keeps nanoseconds over hours.
//
// Errors: IoError naming the file (and line) and the problem: a missing file, a row with the
// wrong number of fields, a non-numeric or non-finite value, timestamps that do not increase, a
// zero quaternion, a noise figure that is missing or not positive, a T_BS that is not the
// identity, an empty file.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "plucker/geometry/se3.h"
#include "plucker/sensor/body_state.h"
#include "plucker/sensor/imu.h"

namespace plucker {
namespace io {

struct EurocImuRecording {
  std::int64_t origin_ns = 0;  // the first IMU timestamp
  sensor::ImuModel imu_model;
  std::vector<sensor::ImuSample> imu;
  std::vector<sensor::BodyState> ground_truth;  // empty when the folder has none
};

// `dir` is the dataset folder (with mav0/) or mav0 itself.
EurocImuRecording ReadEurocImuRecording(const std::string& dir);

// A ground-truth csv alone (state_groundtruth_estimate0/data.csv or a file of its layout), its
// times in seconds since its own first row, `origin_ns`. Throws IoError.
struct EurocGroundTruth {
  std::int64_t origin_ns = 0;
  std::vector<sensor::BodyState> states;
};
EurocGroundTruth ReadEurocGroundTruthCsv(const std::string& path);

// The single readers, for tests and other layouts. `name` is used in error messages.
std::vector<sensor::ImuSample> ParseEurocImuCsv(const std::string& text, const std::string& name,
                                                std::int64_t origin_ns);
std::vector<sensor::BodyState> ParseEurocGroundTruthCsv(const std::string& text,
                                                        const std::string& name,
                                                        std::int64_t origin_ns);
sensor::ImuModel ParseEurocImuYaml(const std::string& text, const std::string& name);
// A timestamp field: integer nanoseconds >= 0 (blanks after it allowed). `where` is used in the
// error message.
std::int64_t ParseEurocNanoseconds(const std::string& field, const std::string& where);

}  // namespace io
}  // namespace plucker
