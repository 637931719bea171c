#include "pipeline_json.h"

namespace plucker {
namespace app {
nlohmann::json Vec3Json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json InertialStateJson(const sensor::BodyState& s) {
  return {{"v_w", Vec3Json(s.v_w)},
          {"gyro_bias", Vec3Json(s.bias.gyro)},
          {"accel_bias", Vec3Json(s.bias.accel)}};
}

nlohmann::json WindowFrameJson(const window::WindowFrameResult& r, bool inertial) {
  nlohmann::json j = {{"keyframe", r.keyframe},
                      {"tracked_points", r.tracked_points},
                      {"tracked_lines", r.tracked_lines},
                      {"pnp_fallback", r.pnp_fallback},
                      {"new_points", r.new_points},
                      {"new_lines", r.new_lines},
                      {"window_points", r.window_points},
                      {"window_lines", r.window_lines},
                      {"window_keyframes", r.window_keyframes},
                      {"parallax_px", r.parallax_px},
                      {"tracking_iterations", r.tracking_iterations},
                      {"window_iterations", r.window_iterations},
                      {"initial_cost", r.initial_cost},
                      {"final_cost", r.final_cost},
                      {"residuals", r.residuals},
                      {"culled_observations", r.culled_observations},
                      {"line_residuals", r.line_residuals},
                      {"culled_line_observations", r.culled_line_observations},
                      {"line_rms_sigmas", r.line_rms_sigmas},
                      {"point_rms_sigmas", r.point_rms_sigmas},
                      {"line_candidates", r.line_candidates},
                      {"line_small_parallax", r.line_small_parallax},
                      {"line_ill_conditioned", r.line_ill_conditioned},
                      {"line_other_rejections", r.line_other_rejections},
                      {"marginalized_keyframes", r.marginalized_keyframes},
                      {"marginalized_landmarks", r.marginalized_landmarks},
                      {"dropped_point_observations", r.dropped_point_observations},
                      {"dropped_line_observations", r.dropped_line_observations},
                      {"held_line_observations", r.held_line_observations},
                      {"dropped_retained_line_observations", r.dropped_retained_line_observations},
                      {"retained_poses", r.retained_poses},
                      {"prior_lines", r.prior_lines},
                      {"prior_rank", r.prior_rank},
                      {"marginalization_failed", r.marginalization_failed}};
  if (inertial) {
    j["imu_chi2"] = r.imu_chi2;
    j["state"] = InertialStateJson(r.state);
  }
  return j;
}

}  // namespace app
}  // namespace plucker
