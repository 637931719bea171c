// The start's test of `plucker vio` (CheckStart, vio_checks.h): the window's first solve after the
// start against the bounds of checks.max_start_imu_chi2 and checks.max_start_culled_share.
#include <gtest/gtest.h>

#include "vio_checks.h"

namespace plucker {
namespace app {
namespace {

VioReport ReportWithFirstKeyframe(double chi2, int culled, int residuals) {
  VioReport r;
  r.keyframe_chi2.push_back({121, 4.03, chi2, culled, residuals});
  r.keyframe_chi2.push_back({128, 4.27, 1e4, 4000, 5000});  // later keyframes do not count
  return r;
}

const VioStartBounds kDefaults{25.0, 0.01};

TEST(VioStartCheck, AHealthyStartPasses) {
  // A healthy fast corridor start (session 22): chi2 0.87, nothing culled.
  const VioStartCheck c = CheckStart(ReportWithFirstKeyframe(0.87, 0, 3238), kDefaults);
  EXPECT_TRUE(c.solved);
  EXPECT_FALSE(c.failed());
  EXPECT_EQ(c.keyframe.frame, 121);
  EXPECT_EQ(WarnStart(c, kDefaults), 0);
}

TEST(VioStartCheck, AWrongScaleStartFails) {
  // Aggressive corridor seed 210 with the previous start: 2.2 m of ATE.
  const VioStartCheck c = CheckStart(ReportWithFirstKeyframe(262.3, 160, 5184), kDefaults);
  EXPECT_TRUE(c.chi2_over);
  EXPECT_TRUE(c.culled_over);
  EXPECT_NEAR(c.culled_share, 160.0 / 5184.0, 1e-12);
  EXPECT_EQ(WarnStart(c, kDefaults), kExitImuOnly);
  const nlohmann::json j = StartCheckJson(c, kDefaults);
  EXPECT_TRUE(j["failed"].get<bool>());
  EXPECT_EQ(j["frame"].get<int>(), 121);
}

TEST(VioStartCheck, EitherBoundAloneFailsAndZeroIsOff) {
  // Many outliers, a small chi2 (aggressive corridor seed 215 points only: 3.2 m).
  EXPECT_TRUE(CheckStart(ReportWithFirstKeyframe(14.6, 140, 4968), kDefaults).culled_over);
  EXPECT_FALSE(CheckStart(ReportWithFirstKeyframe(14.6, 140, 4968), kDefaults).chi2_over);
  EXPECT_TRUE(CheckStart(ReportWithFirstKeyframe(30.4, 0, 4776), kDefaults).chi2_over);
  EXPECT_FALSE(CheckStart(ReportWithFirstKeyframe(262.3, 160, 5184), {0.0, 0.0}).failed());
}

TEST(VioStartCheck, AFewCulledObservationsAreNoShare) {
  // 1 of 88 is over 0.01 but below kMinStartCulled.
  EXPECT_FALSE(CheckStart(ReportWithFirstKeyframe(0.01, 1, 88), kDefaults).failed());
  EXPECT_TRUE(CheckStart(ReportWithFirstKeyframe(0.01, kMinStartCulled, 500), kDefaults).failed());
}

TEST(VioStartCheck, NoKeyframeIsNotSolved) {
  const VioStartCheck c = CheckStart(VioReport(), kDefaults);
  EXPECT_FALSE(c.solved);
  EXPECT_FALSE(c.failed());
  EXPECT_FALSE(StartCheckJson(c, kDefaults).contains("frame"));
}

TEST(VioStartCheck, KeyframeChi2Distribution) {
  VioReport r;
  for (int k = 0; k < 20; ++k) r.keyframe_chi2.push_back({k, 0.1 * k, k < 18 ? 1.0 : 100.0});
  const nlohmann::json j = KeyframeChi2StatsJson(r);
  EXPECT_EQ(j["median"].get<double>(), 1.0);
  EXPECT_EQ(j["p95"].get<double>(), 100.0);
  EXPECT_NEAR(j["share_over_q99"].get<double>(), 0.1, 1e-12);
  EXPECT_EQ(KeyframeChi2StatsJson(VioReport())["largest"].get<double>(), 0.0);
}

}  // namespace
}  // namespace app
}  // namespace plucker
