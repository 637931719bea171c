// What `plucker vo` and `plucker vio` write alike, defined once: the names of the timed stages
// (the JSON keys of "ms", "mean_stage_ms", "frontend_mean_ms", in the order of the library's
// stage enums) and the window's per-frame statistics. The LiDAR stage names are in
// stage_clock.h (the LiDAR commands do not load the image code).
#pragma once

#include <array>
#include <nlohmann/json.hpp>

#include "plucker/vision/image_frontend.h"
#include "plucker/window/sliding_window_estimator.h"

namespace plucker {
namespace app {

inline constexpr std::array<const char*, vision::kNumFrontendStages> kFrontendStageNames = {
    "points", "detection", "lines"};
inline constexpr std::array<const char*, window::kNumWindowStages> kWindowStageNames = {
    "tracking", "triangulation", "solve", "marginalization"};
inline constexpr const char* kReadStageName = "read";    // reading (and decoding) the input
inline constexpr const char* kOtherStageName = "other";  // the rest of a call

// The window's statistics of one frame (window::WindowFrameResult), every field, the same keys in
// both pipelines; inertial: with the IMU terms (imu_chi2 and the state: velocity, biases).
nlohmann::json WindowFrameJson(const window::WindowFrameResult& r, bool inertial);

// [x, y, z]
nlohmann::json Vec3Json(const Eigen::Vector3d& v);

// {"v_w": [x, y, z], "gyro_bias": [...], "accel_bias": [...]}
nlohmann::json InertialStateJson(const sensor::BodyState& s);

}  // namespace app
}  // namespace plucker
