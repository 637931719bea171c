#include "plucker/geometry/line_triangulation.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <random>

#include "plucker/geometry/geometry_test_utils.h"
#include "plucker/geometry/orthonormal_line.h"
#include "plucker/geometry/point_projection.h"

namespace plucker {
namespace {

using testing_utils::LookAt;
using testing_utils::TestK;

LineObservation Observe(const SE3d& T_w_c, const Eigen::Vector3d& P, const Eigen::Vector3d& Q,
                        std::mt19937_64* rng = nullptr, double sigma_px = 0.0) {
  LineObservation o;
  o.T_w_c = T_w_c;
  const auto s = ProjectPoint(TestK(), T_w_c, P), e = ProjectPoint(TestK(), T_w_c, Q);
  EXPECT_TRUE(s && e);
  o.start = *s;
  o.end = *e;
  if (rng) {
    std::normal_distribution<double> noise(0.0, sigma_px);
    o.start += Eigen::Vector2d(noise(*rng), noise(*rng));
    o.end += Eigen::Vector2d(noise(*rng), noise(*rng));
  }
  return o;
}

// n cameras on an arc around the segment midpoint, ~6 m away.
std::vector<LineObservation> ObserveFromArc(const Eigen::Vector3d& P, const Eigen::Vector3d& Q,
                                            int n, std::mt19937_64* rng = nullptr,
                                            double sigma_px = 0.0) {
  const Eigen::Vector3d mid = 0.5 * (P + Q);
  std::vector<LineObservation> obs;
  for (int i = 0; i < n; ++i) {
    const double a = -0.6 + 1.2 * i / std::max(1, n - 1);
    const Eigen::Vector3d c =
        mid + Eigen::Vector3d(6 * std::sin(a), 0.7 * i - 1.0, -6 * std::cos(a));
    obs.push_back(Observe(LookAt(c, mid, 0.2 * i), P, Q, rng, sigma_px));
  }
  return obs;
}

Line6d TrueLine(const Eigen::Vector3d& P, const Eigen::Vector3d& Q) {
  return LineFromPoints<double>(P, Q) / (Q - P).norm();
}

void ExpectExact(const LineTriangulationResult& r, const Eigen::Vector3d& P,
                 const Eigen::Vector3d& Q, double tol = 1e-9) {
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT((r.L_w - TrueLine(P, Q)).norm(), tol) << r.L_w.transpose();
  EXPECT_NEAR(r.L_w.tail<3>().norm(), 1.0, 1e-12);
  EXPECT_LT(std::abs(r.L_w.head<3>().dot(r.L_w.tail<3>())), 1e-9);
  EXPECT_LT((r.start_w - P).norm(), tol * 10);
  EXPECT_LT((r.end_w - Q).norm(), tol * 10);
}

TEST(LineTriangulation, ExactRecoveryNoiseFree) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d P(u(rng), u(rng), u(rng)), Q(u(rng), u(rng), u(rng));
    if ((P - Q).norm() < 0.5) continue;
    const auto obs = ObserveFromArc(P, Q, 5);
    ExpectExact(TriangulateLineTwoView(TestK(), obs[0], obs[4]), P, Q);
    ExpectExact(TriangulateLine(TestK(), obs), P, Q);
    ExpectExact(TriangulateLine(TestK(), {obs[1], obs[3]}), P, Q);
    std::pair<int, int> pair;
    const auto best = TriangulateLineBestPair(TestK(), obs, {}, &pair);
    ExpectExact(best, P, Q);
    const auto r = TriangulateLine(TestK(), obs);
    EXPECT_LT(r.sigma_ratio, 1e-6);
    EXPECT_GE(r.max_parallax_rad, r.min_parallax_rad);
    EXPECT_NEAR(best.max_parallax_rad, r.max_parallax_rad, 1e-12);
  }
}

TEST(LineTriangulation, NoisyErrorBound) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  int n = 0;
  double sum_angle = 0.0, sum_dist = 0.0, sum_end = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d P(u(rng), u(rng), u(rng)), Q(u(rng), u(rng), u(rng));
    if ((P - Q).norm() < 1.5) continue;
    const auto obs = ObserveFromArc(P, Q, 6, &rng, 1.0);
    const auto r = TriangulateLine(TestK(), obs);
    ASSERT_TRUE(r.ok()) << r.message;
    // Lines nearly in the plane of the camera arc are poorly constrained (errors of several
    // degrees at 3-8 deg of plane angle): the bound is for well-observed lines.
    if (r.max_parallax_rad < 10.0 * M_PI / 180.0) continue;
    const Eigen::Vector3d d = r.L_w.tail<3>();
    const double angle = std::acos(std::min(1.0, d.dot((Q - P).normalized())));
    const Eigen::Vector3d mid = 0.5 * (P + Q);
    const double dist = (mid.cross(d) - r.L_w.head<3>()).norm();  // |x x d - n|, |d| = 1
    EXPECT_LT(angle, 2.5 * M_PI / 180.0);
    EXPECT_LT(dist, 0.1);
    EXPECT_LT(r.sigma_ratio, 0.1);
    // Endpoints: across the line as accurate as the line; along it weaker where a view's
    // endpoint ray is nearly parallel to the line, and the union of the views' extents is biased
    // outwards by the noise.
    for (const auto& [est, gt] : {std::make_pair(r.start_w, P), std::make_pair(r.end_w, Q)}) {
      const Eigen::Vector3d err = est - gt;
      EXPECT_LT((err - d * d.dot(err)).norm(), 0.15);
      EXPECT_LT(std::abs(d.dot(err)), 0.8);
      sum_end += err.norm();
    }
    sum_angle += angle;
    sum_dist += dist;
    ++n;
  }
  ASSERT_GT(n, 30);
  EXPECT_LT(sum_angle / n, 0.6 * M_PI / 180.0);
  EXPECT_LT(sum_dist / n, 0.03);
  EXPECT_LT(sum_end / (2 * n), 0.15);
}

// The notes: a reference implementation picked the view pair (and decided degeneracy) from the
// signed cos of the plane normals; swapping a segment's endpoints flips its normal and broke it.
TEST(LineTriangulation, SwappedEndpointsDoNotMatter) {
  const Eigen::Vector3d P(-1, 0.3, 0.5), Q(1.2, -0.4, 0.2);
  auto obs = ObserveFromArc(P, Q, 4);
  std::pair<int, int> pair_before, pair_after;
  const auto before = TriangulateLineBestPair(TestK(), obs, {}, &pair_before);
  const auto nview_before = TriangulateLine(TestK(), obs);
  std::swap(obs[2].start, obs[2].end);
  std::swap(obs[3].start, obs[3].end);
  const auto after = TriangulateLineBestPair(TestK(), obs, {}, &pair_after);
  const auto nview_after = TriangulateLine(TestK(), obs);
  EXPECT_EQ(pair_before, pair_after);
  ExpectExact(before, P, Q);
  ExpectExact(after, P, Q);
  ExpectExact(nview_after, P, Q);
  EXPECT_NEAR(before.max_parallax_rad, after.max_parallax_rad, 1e-12);
  EXPECT_NEAR(nview_before.min_parallax_rad, nview_after.min_parallax_rad, 1e-12);

  // Two nearly coplanar planes (angle ~0.5 deg): rejected whatever the endpoint order. With the
  // signed cos a swapped pair would look like a ~179.5 deg angle and be accepted.
  const Eigen::Vector3d mid = 0.5 * (P + Q), dir = (Q - P).normalized();
  const Eigen::Vector3d side = dir.cross(Eigen::Vector3d::UnitY()).normalized();
  const Eigen::Vector3d c0 = mid + 6 * side, c1 = mid + 6 * side + 2 * dir + 0.05 * dir.cross(side);
  LineObservation a = Observe(LookAt(c0, mid), P, Q), b = Observe(LookAt(c1, mid), P, Q);
  const auto r1 = TriangulateLineTwoView(TestK(), a, b);
  std::swap(b.start, b.end);
  const auto r2 = TriangulateLineTwoView(TestK(), a, b);
  EXPECT_EQ(r1.status, LineTriangulationStatus::kSmallParallax) << r1.message;
  EXPECT_EQ(r2.status, LineTriangulationStatus::kSmallParallax) << r2.message;
  EXPECT_NEAR(r1.max_parallax_rad, r2.max_parallax_rad, 1e-12);
  EXPECT_LT(r1.max_parallax_rad, 2.0 * M_PI / 180.0);
}

TEST(LineTriangulation, LineThroughTheOrigin) {
  const Eigen::Vector3d v = Eigen::Vector3d(0.3, -0.8, 0.5).normalized();
  const Eigen::Vector3d P = -1.5 * v, Q = 2.0 * v;
  const auto obs = ObserveFromArc(P, Q, 4);
  for (const auto& r :
       {TriangulateLine(TestK(), obs), TriangulateLineTwoView(TestK(), obs[0], obs[3])}) {
    ExpectExact(r, P, Q);
    EXPECT_LT(r.L_w.head<3>().norm(), 1e-9);
  }
}

TEST(LineTriangulation, LineParallelToAnOpticalAxis) {
  // Camera 0 looks along the line (offset 1 m sideways): its image of the line runs towards the
  // principal point (the vanishing point).
  const SE3d T0 = LookAt(Eigen::Vector3d(1, 0, -5), Eigen::Vector3d(1, 0, 0));
  const Eigen::Vector3d P(0, 0, 0), Q(0, 0, 4);  // direction = camera 0's optical axis
  std::vector<LineObservation> obs = {Observe(T0, P, Q)};
  obs.push_back(Observe(LookAt(Eigen::Vector3d(5, 1, 2), Eigen::Vector3d(0, 0, 2)), P, Q));
  obs.push_back(Observe(LookAt(Eigen::Vector3d(-4, -1, 1), Eigen::Vector3d(0, 0, 2)), P, Q));
  ExpectExact(TriangulateLine(TestK(), obs), P, Q);
  ExpectExact(TriangulateLineTwoView(TestK(), obs[0], obs[1]), P, Q);
  ExpectExact(TriangulateLineTwoView(TestK(), obs[1], obs[2]), P, Q);
}

TEST(LineTriangulation, TooFewViews) {
  const auto obs = ObserveFromArc(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), 1);
  EXPECT_EQ(TriangulateLine(TestK(), obs).status, LineTriangulationStatus::kTooFewViews);
  EXPECT_EQ(TriangulateLine(TestK(), {}).status, LineTriangulationStatus::kTooFewViews);
  EXPECT_EQ(TriangulateLineBestPair(TestK(), obs).status, LineTriangulationStatus::kTooFewViews);
}

TEST(LineTriangulation, InvalidInput) {
  const Eigen::Vector3d P(0, 0, 0), Q(1, 0.2, 0);
  const auto good = ObserveFromArc(P, Q, 3);
  auto obs = good;
  obs[1].end.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(TriangulateLine(TestK(), obs).status, LineTriangulationStatus::kInvalidInput);
  EXPECT_EQ(TriangulateLineTwoView(TestK(), obs[0], obs[1]).status,
            LineTriangulationStatus::kInvalidInput);
  obs = good;
  obs[2].end = obs[2].start;  // zero-length segment
  const auto r = TriangulateLine(TestK(), obs);
  EXPECT_EQ(r.status, LineTriangulationStatus::kInvalidInput);
  EXPECT_FALSE(r.message.empty());
  obs = good;
  obs[2].end = obs[2].start + Eigen::Vector2d(0.5, 0.0);  // shorter than 1 px
  EXPECT_EQ(TriangulateLine(TestK(), obs).status, LineTriangulationStatus::kInvalidInput);
  PinholeIntrinsics badK = TestK();
  badK.fx = std::numeric_limits<double>::infinity();
  EXPECT_EQ(TriangulateLine(badK, good).status, LineTriangulationStatus::kInvalidInput);
  EXPECT_FALSE(BackProjectSegment(badK, good[0].T_w_c, good[0].start, good[0].end).has_value());
  EXPECT_FALSE(SegmentEndpointsOnLine(TestK(), good[0], Line6d::Zero()).has_value());
}

TEST(LineTriangulation, SmallParallaxWhenBaselineInThePlaneOfTheLine) {
  // Both camera centres and the line lie in the plane z = 0: both back-projected planes are z = 0.
  const Eigen::Vector3d P(-1, 0, 0), Q(1, 0, 0);
  const Eigen::Vector3d target(0, 0, 0);
  std::vector<LineObservation> obs = {Observe(LookAt(Eigen::Vector3d(0.5, 5, 0), target), P, Q),
                                      Observe(LookAt(Eigen::Vector3d(-2, 6, 0), target), P, Q)};
  obs[0].T_w_c = LookAt(Eigen::Vector3d(0.5, 5, 0), target, 0.4);
  obs[0] = Observe(obs[0].T_w_c, P, Q);
  for (const auto& r :
       {TriangulateLine(TestK(), obs), TriangulateLineTwoView(TestK(), obs[0], obs[1])}) {
    EXPECT_EQ(r.status, LineTriangulationStatus::kSmallParallax) << r.message;
    EXPECT_LT(r.max_parallax_rad, 1e-6);
  }
  // The threshold is configurable.
  LineTriangulationOptions o;
  o.min_plane_angle_deg = 0.0;
  obs[1] = Observe(LookAt(Eigen::Vector3d(-2, 6, 0.2), target), P, Q);  // 2 deg out of the plane
  EXPECT_TRUE(TriangulateLineTwoView(TestK(), obs[0], obs[1], o).ok());
  // Exactly coplanar views stay rejected (floor of 1e-8 rad), with finite outputs.
  obs[1] = Observe(LookAt(Eigen::Vector3d(-2, 6, 0), target), P, Q);
  const auto two = TriangulateLineTwoView(TestK(), obs[0], obs[1], o);
  EXPECT_EQ(two.status, LineTriangulationStatus::kSmallParallax);
  EXPECT_TRUE(two.L_w.allFinite());
  obs.push_back(Observe(LookAt(Eigen::Vector3d(3, 7, 0), target), P, Q));
  const auto nview = TriangulateLine(TestK(), obs, o);
  EXPECT_FALSE(nview.ok());
  EXPECT_TRUE(std::isfinite(nview.sigma_ratio));
  EXPECT_TRUE(nview.L_w.allFinite());
}

TEST(LineTriangulation, IllConditionedWhenViewsDisagree) {
  // Three views of three different lines: no common line (sigma3 ~ sigma2).
  std::vector<LineObservation> obs =
      ObserveFromArc(Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(1, 0, 0), 3);
  obs[1] = Observe(obs[1].T_w_c, Eigen::Vector3d(0, -1, 0.5), Eigen::Vector3d(0, 1, -0.5));
  obs[2] = Observe(obs[2].T_w_c, Eigen::Vector3d(-1, 1, 1), Eigen::Vector3d(1, -1, 1));
  const auto r = TriangulateLine(TestK(), obs);
  EXPECT_EQ(r.status, LineTriangulationStatus::kIllConditioned) << r.message;
  EXPECT_GT(r.sigma_ratio, 0.5);
}

TEST(LineTriangulation, BehindCamera) {
  const Eigen::Vector3d P(-1, 0.2, 0), Q(1, -0.3, 0.4);
  auto obs = ObserveFromArc(P, Q, 3);
  // Turn camera 2 around (pi about its y axis) and observe the segment "through the back": the
  // pixels of the mirrored points keep the back-projected plane but put the line behind it.
  const SE3d T = obs[2].T_w_c;
  const SE3d T_flip(
      T.rotation() * Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY())),
      T.translation());
  const Eigen::Vector3d ps = T_flip.Inverse() * P, pe = T_flip.Inverse() * Q;
  ASSERT_LT(ps.z(), 0);
  obs[2].T_w_c = T_flip;
  obs[2].start = TestK().ToPixel<double>(Eigen::Vector2d(ps.head<2>() / ps.z()));
  obs[2].end = TestK().ToPixel<double>(Eigen::Vector2d(pe.head<2>() / pe.z()));
  const auto r = TriangulateLine(TestK(), obs);
  EXPECT_EQ(r.status, LineTriangulationStatus::kBehindCamera) << r.message;
  EXPECT_EQ(TriangulateLineTwoView(TestK(), obs[0], obs[2]).status,
            LineTriangulationStatus::kBehindCamera);
  EXPECT_TRUE(TriangulateLineTwoView(TestK(), obs[0], obs[1]).ok());
}

TEST(LineTriangulation, DegenerateEndpointAtTheVanishingPoint) {
  // Camera 0 looks along the line; its segment starts at the vanishing point (principal point),
  // whose ray is parallel to the line: no closest point.
  const SE3d T0 = LookAt(Eigen::Vector3d(1, 0, -5), Eigen::Vector3d(1, 0, 0));
  const Eigen::Vector3d P(0, 0, 0), Q(0, 0, 4);
  LineObservation o0 = Observe(T0, P, Q);
  o0.start = Eigen::Vector2d(TestK().cx, TestK().cy);
  const LineObservation o1 =
      Observe(LookAt(Eigen::Vector3d(5, 1, 2), Eigen::Vector3d(0, 0, 2)), P, Q);
  const auto r = TriangulateLineTwoView(TestK(), o0, o1);
  EXPECT_EQ(r.status, LineTriangulationStatus::kDegenerateEndpoint) << r.message;
}

TEST(LineTriangulation, SegmentEndpointsOnLineGivesDepths) {
  const Eigen::Vector3d P(-1, 0.2, 0), Q(1, -0.3, 0.4);
  const auto obs = ObserveFromArc(P, Q, 2);
  const auto ends = SegmentEndpointsOnLine(TestK(), obs[0], TrueLine(P, Q) * -3.0);  // any scale
  ASSERT_TRUE(ends.has_value());
  EXPECT_LT((ends->start_w - P).norm(), 1e-9);
  EXPECT_LT((ends->end_w - Q).norm(), 1e-9);
  EXPECT_NEAR(ends->start_depth, (obs[0].T_w_c.Inverse() * P).z(), 1e-9);
  EXPECT_NEAR(ends->end_depth, (obs[0].T_w_c.Inverse() * Q).z(), 1e-9);
}

// Angle [rad] of the direction and distance [m] of the segment midpoint from the estimated line.
std::pair<double, double> LineError(const Line6d& L, const Eigen::Vector3d& P,
                                    const Eigen::Vector3d& Q) {
  const Eigen::Vector3d d = L.tail<3>().normalized();
  const Eigen::Vector3d n = L.head<3>() / L.tail<3>().norm();
  const double angle = std::acos(std::min(1.0, std::abs(d.dot((Q - P).normalized()))));
  return {angle, ((0.5 * (P + Q)).cross(d) - n).norm()};
}

TEST(LineRefinement, ConvergesToTheExactLineFromAPerturbedStart) {
  const Eigen::Vector3d P(-1, 0.3, 0.5), Q(1.2, -0.4, 0.2);
  const auto obs = ObserveFromArc(P, Q, 5);
  const auto start = OrthonormalFromPlucker(TrueLine(P, Q));
  ASSERT_TRUE(start.has_value());
  const Line6d L0 = PluckerFromOrthonormal(start->Plus(Eigen::Vector4d(0.02, -0.03, 0.01, 0.02)));
  const auto refined = RefineLine(TestK(), obs, L0);
  ASSERT_TRUE(refined.has_value());
  EXPECT_TRUE(refined->converged);
  EXPECT_GT(refined->initial_cost, 10.0);  // the start is pixels off
  EXPECT_LT(refined->final_cost, 1e-16);
  const Line6d L = refined->L_w / refined->L_w.tail<3>().norm();
  EXPECT_LT(std::min((L - TrueLine(P, Q)).norm(), (L + TrueLine(P, Q)).norm()), 1e-9);
}

// The refined line is a stationary point of the cost: central differences of the cost along the
// four tangent directions vanish (checks the analytic Jacobian chain of the refinement).
TEST(LineRefinement, NoisyMinimumIsStationary) {
  std::mt19937_64 rng(11);
  const Eigen::Vector3d P(-1, 0.3, 0.5), Q(1.2, -0.4, 0.2);
  const auto obs = ObserveFromArc(P, Q, 6, &rng, 1.0);
  const auto linear = TriangulateLine(TestK(), obs);
  ASSERT_TRUE(linear.ok()) << linear.message;
  const auto refined = RefineLine(TestK(), obs, linear.L_w);
  ASSERT_TRUE(refined.has_value());
  EXPECT_LT(refined->final_cost, refined->initial_cost);
  EXPECT_GE(refined->iterations, 1);
  const auto base = OrthonormalFromPlucker(refined->L_w);
  ASSERT_TRUE(base.has_value());
  auto cost = [&](const Eigen::Vector4d& delta) {
    const auto e = LineReprojectionErrors(TestK(), obs, PluckerFromOrthonormal(base->Plus(delta)));
    EXPECT_TRUE(e.has_value());
    return 0.5 * e->squaredNorm();
  };
  EXPECT_NEAR(cost(Eigen::Vector4d::Zero()), refined->final_cost, 1e-9);
  int checked = 0;
  for (int k = 0; k < 4; ++k) {
    const double h = 1e-6;
    const Eigen::Vector4d e = h * Eigen::Vector4d::Unit(k);
    const double gradient = (cost(e) - cost(-e)) / (2 * h);
    const double curvature = (cost(e) - 2 * cost(Eigen::Vector4d::Zero()) + cost(-e)) / (h * h);
    EXPECT_LT(std::abs(gradient), 1e-5 * std::max(1.0, curvature)) << "direction " << k;
    EXPECT_GT(curvature, 0.0);
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

// Noise -> accuracy: the refined N-view line is at least as accurate as the linear one on
// average, and both errors grow with the pixel noise.
TEST(LineRefinement, AccuracyVersusNoise) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  double previous_refined = 0.0;
  for (const double sigma : {0.5, 1.0, 2.0}) {
    double linear_dist = 0.0, refined_dist = 0.0, linear_rms = 0.0, refined_rms = 0.0;
    int n = 0;
    for (int trial = 0; trial < 60; ++trial) {
      const Eigen::Vector3d P(u(rng), u(rng), u(rng)), Q(u(rng), u(rng), u(rng));
      if ((P - Q).norm() < 1.5) continue;
      const auto obs = ObserveFromArc(P, Q, 6, &rng, sigma);
      const auto lin = TriangulateLine(TestK(), obs);
      const auto ref = TriangulateLineRefined(TestK(), obs);
      if (!lin.ok() || !ref.ok() || lin.max_parallax_rad < 10.0 * M_PI / 180.0) continue;
      EXPECT_LE(ref.rms_error_px, lin.rms_error_px + 1e-9);
      linear_dist += LineError(lin.L_w, P, Q).second;
      refined_dist += LineError(ref.L_w, P, Q).second;
      linear_rms += lin.rms_error_px;
      refined_rms += ref.rms_error_px;
      ++n;
    }
    ASSERT_GT(n, 20);
    std::printf(
        "sigma %.1f px: %d lines, midpoint distance linear %.4f m refined %.4f m, "
        "rms linear %.3f px refined %.3f px\n",
        sigma, n, linear_dist / n, refined_dist / n, linear_rms / n, refined_rms / n);
    EXPECT_LT(refined_rms, linear_rms);
    EXPECT_LE(refined_dist, 1.05 * linear_dist);
    EXPECT_LT(refined_dist / n, 0.03 * sigma);
    EXPECT_GT(refined_dist / n, previous_refined);
    previous_refined = refined_dist / n;
  }
}

// Forward motion along the line (a road edge seen from a car): every camera centre lies in a
// plane with the line, the back-projected planes (nearly) coincide, and the track is rejected;
// the same track seen with a sideways offset of the later cameras passes.
TEST(LineRefinement, ForwardMotionAlongTheLineIsRejected) {
  const Eigen::Vector3d P(1.5, 1.2, 8.0), Q(1.5, 1.2, 20.0);  // right of and below the cameras
  std::vector<LineObservation> obs;
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector3d c(0.0, 0.0, 1.0 * i);
    obs.push_back(Observe(LookAt(c, c + Eigen::Vector3d(0, 0, 10)), P, Q));
  }
  for (const auto& r : {TriangulateLine(TestK(), obs), TriangulateLineRefined(TestK(), obs)}) {
    EXPECT_EQ(r.status, LineTriangulationStatus::kSmallParallax) << r.message;
    EXPECT_LT(r.max_parallax_rad, 1e-6);
  }
  // 0.5 m of lateral drift over the track: a usable plane angle.
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector3d c(0.0, -0.125 * i, 1.0 * i);
    obs[i] = Observe(LookAt(c, c + Eigen::Vector3d(0, 0, 10)), P, Q);
  }
  const auto r = TriangulateLineRefined(TestK(), obs);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_GT(r.max_parallax_rad, 2.0 * M_PI / 180.0);
  EXPECT_LT(LineError(r.L_w, P, Q).second, 1e-8);
}

TEST(LineRefinement, InvalidInput) {
  const Eigen::Vector3d P(-1, 0.3, 0.5), Q(1.2, -0.4, 0.2);
  auto obs = ObserveFromArc(P, Q, 3);
  EXPECT_FALSE(RefineLine(TestK(), {}, TrueLine(P, Q)).has_value());
  EXPECT_FALSE(RefineLine(TestK(), obs, Line6d::Zero()).has_value());
  PinholeIntrinsics badK = TestK();
  badK.fx = -1;
  EXPECT_FALSE(RefineLine(badK, obs, TrueLine(P, Q)).has_value());
  obs[1].start.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(RefineLine(TestK(), obs, TrueLine(P, Q)).has_value());
  EXPECT_EQ(TriangulateLineRefined(TestK(), obs).status, LineTriangulationStatus::kInvalidInput);
  // A line through a camera centre projects to a point there.
  obs = ObserveFromArc(P, Q, 3);
  const Eigen::Vector3d c = obs[0].T_w_c.translation();
  EXPECT_FALSE(RefineLine(TestK(), obs, LineFromPoints<double>(c, c + Eigen::Vector3d::UnitX()))
                   .has_value());
}

}  // namespace
}  // namespace plucker
