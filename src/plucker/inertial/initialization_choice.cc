#include "plucker/inertial/initialization_choice.h"

#include <cmath>
#include <cstdio>

namespace plucker {
namespace inertial {

const char* ToString(InitializationMethod method) {
  switch (method) {
    case InitializationMethod::kWait:
      return "wait";
    case InitializationMethod::kStatic:
      return "static";
    case InitializationMethod::kDynamic:
      return "dynamic";
  }
  return "unknown";
}

double ImuExcitation(const std::vector<ImuPreintegration>& pre) {
  if (pre.empty()) return 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const ImuPreintegration& p : pre) mean += p.DeltaV() / p.Dt();
  mean /= static_cast<double>(pre.size());
  double sum = 0.0;
  for (const ImuPreintegration& p : pre) sum += (p.DeltaV() / p.Dt() - mean).squaredNorm();
  return std::sqrt(sum / static_cast<double>(pre.size()));
}

InitializationChoice ChooseInitialization(const StaticInitResult& still, int num_keyframes,
                                          double excitation, const InitializationChoiceOptions& o) {
  char buf[160];
  if (still.success()) {
    std::snprintf(buf, sizeof(buf), "still for %.2f s at the start",
                  still.still_end - still.still_begin);
    return {InitializationMethod::kStatic, buf};
  }
  if (num_keyframes < o.min_keyframes) {
    std::snprintf(buf, sizeof(buf), "not still (%s); %d of %d keyframes", ToString(still.status),
                  num_keyframes, o.min_keyframes);
    return {InitializationMethod::kWait, buf};
  }
  if (!(excitation >= o.min_excitation)) {
    std::snprintf(buf, sizeof(buf), "not still (%s); IMU excitation %.3f m/s^2 below %.3f",
                  ToString(still.status), excitation, o.min_excitation);
    return {InitializationMethod::kWait, buf};
  }
  std::snprintf(buf, sizeof(buf), "not still; %d keyframes, IMU excitation %.3f m/s^2",
                num_keyframes, excitation);
  return {InitializationMethod::kDynamic, buf};
}

}  // namespace inertial
}  // namespace plucker
