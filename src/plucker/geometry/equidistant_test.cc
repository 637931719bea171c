#include "plucker/geometry/equidistant.h"

#include <gtest/gtest.h>

#include <limits>

#include "plucker/verify/checks.h"

namespace plucker {
namespace {

// TUM-VI cam0 (Kalibr pinhole-equi, 512x512, 195 deg lens).
EquidistantDistortion TumVi() {
  return {0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202,
          0.00020293673591811182};
}

Eigen::Vector3d Bearing(double theta, double phi) {
  return Eigen::Vector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         std::cos(theta));
}

TEST(Equidistant, MatchesTheKalibrFormula) {
  const EquidistantDistortion D = TumVi();
  const double theta = M_PI / 4;
  const double t2 = theta * theta;
  const double theta_d =
      theta * (1 + D.k1 * t2 + D.k2 * t2 * t2 + D.k3 * t2 * t2 * t2 + D.k4 * t2 * t2 * t2 * t2);
  EXPECT_NEAR(D.ThetaD(theta), theta_d, 1e-15);
  // (1, 0, 1): theta = 45 deg, xd = (theta_d, 0). (0, -2, 2): the same angle along -y.
  const auto xd = EquidistantProject(D, Eigen::Vector3d(1, 0, 1));
  ASSERT_TRUE(xd.has_value());
  EXPECT_NEAR(xd->x(), theta_d, 1e-15);
  EXPECT_EQ(xd->y(), 0.0);
  EXPECT_NEAR(
      (*EquidistantProject(D, Eigen::Vector3d(0, -2, 2)) - Eigen::Vector2d(0, -theta_d)).norm(),
      0.0, 1e-15);
  // The optical axis maps to the principal point exactly.
  EXPECT_EQ(*EquidistantProject(D, Eigen::Vector3d(0, 0, 5)), Eigen::Vector2d::Zero());
}

// Bearings on a grid of angles of incidence up to the valid field of view and all azimuths go to
// distorted coordinates and back to 1e-9 (measured: ~1e-15).
TEST(Equidistant, RoundTripUpToTheValidFieldOfView) {
  struct Case {
    EquidistantDistortion D;
    EquidistantOptions options;
  };
  EquidistantOptions wide;
  wide.max_theta = 97.5 * M_PI / 180;  // TUM-VI's 195 deg lens, bearing use
  const std::vector<Case> cases = {{TumVi(), {}},
                                   {TumVi(), wide},
                                   {EquidistantDistortion{}, {}},
                                   {EquidistantDistortion{-0.2, 0.0, 0.0, 0.0}, {}},
                                   {EquidistantDistortion{0.3, -0.1, 0.02, -0.002}, {}}};
  for (const Case& c : cases) {
    const double theta_valid = EquidistantValidTheta(c.D, c.options);
    ASSERT_GT(theta_valid, 1.0);
    double worst = 0;
    int n = 0;
    for (int i = 0; i <= 200; ++i) {
      const double theta = theta_valid * i / 200.0;
      for (int j = 0; j < 24; ++j) {
        const Eigen::Vector3d b = Bearing(theta, j * M_PI / 12 - M_PI);
        const auto xd = EquidistantProject(c.D, 3.0 * b, nullptr, c.options);
        ASSERT_TRUE(xd.has_value()) << theta;
        const auto back = EquidistantUnprojectBearing(c.D, *xd, c.options);
        ASSERT_TRUE(back.has_value()) << theta;
        worst = std::max(worst, (*back - b).norm());
        if (theta < M_PI / 2 - 1e-3) {  // normalized coordinates exist
          const auto xn = EquidistantUndistort(c.D, *xd, c.options);
          ASSERT_TRUE(xn.has_value()) << theta;
          const auto again =
              EquidistantProject(c.D, Eigen::Vector3d(xn->x(), xn->y(), 1.0), nullptr, c.options);
          ASSERT_TRUE(again.has_value());
          worst = std::max(worst, (*again - *xd).norm());
        }
        ++n;
      }
    }
    EXPECT_EQ(n, 201 * 24);
    EXPECT_LT(worst, 1e-9);
  }
}

TEST(Equidistant, RefusesBeyondTheValidFieldOfView) {
  const EquidistantDistortion D = TumVi();
  EXPECT_EQ(EquidistantValidTheta(D), M_PI / 2);
  // Behind the 180 deg field of view (z < 0) by default; accepted when max_theta allows it.
  const Eigen::Vector3d behind = Bearing(M_PI / 2 + 0.1, 0.3);
  EXPECT_FALSE(EquidistantProject(D, behind).has_value());
  EquidistantOptions wide;
  wide.max_theta = M_PI / 2 + 0.2;
  EXPECT_TRUE(EquidistantProject(D, behind, nullptr, wide).has_value());
  // Distorted radius beyond theta_d(theta_valid): no bearing.
  const double edge = D.ThetaD(M_PI / 2);
  EXPECT_TRUE(EquidistantUnprojectBearing(D, Eigen::Vector2d(edge - 1e-9, 0)).has_value());
  EXPECT_FALSE(EquidistantUnprojectBearing(D, Eigen::Vector2d(edge + 1e-9, 0)).has_value());
  EXPECT_FALSE(EquidistantUnprojectBearing(D, Eigen::Vector2d(0, -3.0)).has_value());
  // A lens whose theta_d stops increasing: k1 = -0.2 gives d theta_d / d theta = 1 - 0.6 theta^2,
  // which reaches min_derivative (1e-3) at theta = sqrt(0.999 / 0.6).
  const EquidistantDistortion folding{-0.2, 0.0, 0.0, 0.0};
  const double theta_valid = EquidistantValidTheta(folding);
  EXPECT_NEAR(theta_valid, std::sqrt(0.999 / 0.6), 1e-9);
  EXPECT_TRUE(EquidistantProject(folding, Bearing(theta_valid - 1e-6, 1.0)).has_value());
  EXPECT_FALSE(EquidistantProject(folding, Bearing(theta_valid + 1e-6, 1.0)).has_value());
  const double peak = folding.ThetaD(theta_valid);
  EXPECT_FALSE(EquidistantUnprojectBearing(folding, Eigen::Vector2d(0, peak + 1e-9)));
  // Points that have no projection, non-finite input and coefficients.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(EquidistantProject(D, Eigen::Vector3d::Zero()).has_value());
  EXPECT_FALSE(EquidistantProject(D, Eigen::Vector3d(0, 0, -1), nullptr, wide).has_value());
  EXPECT_FALSE(EquidistantProject(D, Eigen::Vector3d(nan, 0, 1)).has_value());
  EXPECT_FALSE(EquidistantUnprojectBearing(D, Eigen::Vector2d(nan, 0)).has_value());
  EquidistantDistortion bad = D;
  bad.k3 = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(EquidistantProject(bad, Eigen::Vector3d(0.1, 0, 1)).has_value());
  EXPECT_EQ(EquidistantValidTheta(bad), 0.0);
  // No normalized coordinates at or beyond 90 deg, even when the bearing exists.
  EquidistantOptions wider;
  wider.max_theta = M_PI;
  const auto xd = EquidistantProject(D, behind, nullptr, wider);
  ASSERT_TRUE(xd.has_value());
  EXPECT_TRUE(EquidistantUnprojectBearing(D, *xd, wider).has_value());
  EXPECT_FALSE(EquidistantUndistort(D, *xd, wider).has_value());
}

TEST(Equidistant, JacobianChecksPass) {
  verify::JacobianCheckOptions options;
  options.samples = 1000;
  const verify::JacobianCheckRun run =
      verify::RunJacobianChecks(verify::CameraJacobianChecks(), "camera.", 3, options);
  EXPECT_TRUE(run.ok()) << run.error;
  for (const verify::JacobianCheckStats& s : run.stats) EXPECT_EQ(s.skipped, 0) << s.name;
}

}  // namespace
}  // namespace plucker
