#include "vio_checks.h"

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace plucker {
namespace app {

VioStartCheck CheckStart(const VioReport& report, const VioStartBounds& bounds) {
  VioStartCheck c;
  if (report.keyframe_chi2.empty()) return c;
  c.solved = true;
  c.keyframe = report.keyframe_chi2.front();
  const VioReport::KeyframeChi2& k = c.keyframe;
  c.culled_share = k.residuals > 0 ? static_cast<double>(k.culled) / k.residuals : 0.0;
  c.chi2_over = bounds.max_imu_chi2 > 0.0 && !(k.chi2 <= bounds.max_imu_chi2);
  c.culled_over = bounds.max_culled_share > 0.0 && k.culled >= kMinStartCulled &&
                  !(c.culled_share <= bounds.max_culled_share);
  return c;
}

nlohmann::json StartCheckJson(const VioStartCheck& check, const VioStartBounds& bounds) {
  nlohmann::json j = {{"solved", check.solved},
                      {"failed", check.failed()},
                      {"max_start_imu_chi2", bounds.max_imu_chi2},
                      {"max_start_culled_share", bounds.max_culled_share}};
  if (!check.solved) return j;
  j["frame"] = check.keyframe.frame;
  j["time"] = check.keyframe.time;
  j["imu_chi2"] = check.keyframe.chi2;
  j["culled"] = check.keyframe.culled;
  j["residuals"] = check.keyframe.residuals;
  j["culled_share"] = check.culled_share;
  return j;
}

int WarnStart(const VioStartCheck& check, const VioStartBounds& bounds) {
  if (!check.failed()) return 0;
  const VioReport::KeyframeChi2& k = check.keyframe;
  std::ostringstream w;
  w << std::fixed << std::setprecision(2)
    << "plucker vio: warning: the start disagrees with the IMU: the window's first solve after "
       "it (keyframe frame "
    << k.frame << ", " << k.time << " s) left its IMU factor chi2 " << std::setprecision(1)
    << k.chi2;
  if (check.chi2_over) w << " (over max_start_imu_chi2 " << bounds.max_imu_chi2 << ")";
  w << " and culled " << k.culled << " observations as outliers (a share " << std::setprecision(4)
    << check.culled_share << " of its " << k.residuals << " residual blocks";
  if (check.culled_over) w << ", over max_start_culled_share " << bounds.max_culled_share;
  w << "): a start on a wrong scale; the trajectory is not trustworthy (exit code " << kExitImuOnly
    << ")";
  std::cerr << w.str() << "\n";
  return kExitImuOnly;
}

nlohmann::json KeyframeChi2StatsJson(const VioReport& report) {
  constexpr double kChi2Dof15Q99 = 30.58;
  std::vector<double> c;
  for (const VioReport::KeyframeChi2& k : report.keyframe_chi2) c.push_back(k.chi2);
  std::sort(c.begin(), c.end());
  const auto at = [&c](double q) {
    return c.empty() ? 0.0 : c[std::min(c.size() - 1, static_cast<std::size_t>(q * c.size()))];
  };
  const double over = static_cast<double>(
      std::count_if(c.begin(), c.end(), [](double x) { return x > kChi2Dof15Q99; }));
  return {{"keyframes", c.size()},
          {"median", at(0.5)},
          {"p95", at(0.95)},
          {"largest", c.empty() ? 0.0 : c.back()},
          {"share_over_q99", c.empty() ? 0.0 : over / c.size()}};
}

}  // namespace app
}  // namespace plucker
