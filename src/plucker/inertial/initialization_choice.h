// Which initialisation to run (docs/math/vi-initialisation.md, "Choosing"):
//   1. a still period at the start of the log (InitializeStatic succeeds): static;
//   2. else, once at least min_keyframes keyframes with visual poses exist and the IMU between
//      them is excited (ImuExcitation >= min_excitation): dynamic (AlignVisualInertial), which
//      may still fail and is then retried with later keyframes;
//   3. else wait for more data.
// Static comes first because it needs no visual structure and gives the accelerometer bias along
// gravity; the dynamic alignment cannot run while the body stands still (no parallax, no scale).
#pragma once

#include <string>
#include <vector>

#include "plucker/factors/imu_preintegration.h"
#include "plucker/inertial/static_initializer.h"

namespace plucker {
namespace inertial {

enum class InitializationMethod { kWait, kStatic, kDynamic };
const char* ToString(InitializationMethod method);

struct InitializationChoiceOptions {
  int min_keyframes = 10;
  double min_excitation = 0.25;  // m/s^2, ImuExcitation below this: wait for more motion
};

struct InitializationChoice {
  InitializationMethod method = InitializationMethod::kWait;
  std::string reason;
};

// The spread of the mean specific force of the keyframe intervals, sqrt(mean_k |a_k - a_mean|^2)
// with a_k = Dv_k / Dt_k (body frame of each interval's start): zero for a body at rest or in
// uniform motion without rotation. 0 for an empty list.
double ImuExcitation(const std::vector<ImuPreintegration>& preintegrations);

// `still` is the static initialiser's result on the log so far; num_keyframes the keyframes with
// visual poses; excitation ImuExcitation of the preintegrations between them.
InitializationChoice ChooseInitialization(const StaticInitResult& still, int num_keyframes,
                                          double excitation,
                                          const InitializationChoiceOptions& options = {});

}  // namespace inertial
}  // namespace plucker
