#include "plucker/geometry/fitting.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <array>
#include <limits>
#include <random>

namespace plucker {
namespace {

// The covariance of n points with standard deviations `sd` along a random orthonormal frame,
// centred far from the origin.
Eigen::Matrix3d RandomCovariance(std::mt19937* rng, const Eigen::Vector3d& sd, int n) {
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Matrix3d R =
      Eigen::Quaterniond(g(*rng), g(*rng), g(*rng), g(*rng)).normalized().toRotationMatrix();
  const Eigen::Vector3d offset(1e3 * g(*rng), 1e3 * g(*rng), 10.0 * g(*rng));
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i)
    points.push_back(offset + R * sd.cwiseProduct(Eigen::Vector3d(g(*rng), g(*rng), g(*rng))));
  int count = 0;
  Eigen::Vector3d centroid;
  Eigen::Matrix3d cov;
  EXPECT_TRUE(fitting_internal::Moments(points.begin(), points.end(), &count, &centroid, &cov));
  return cov;
}

// Checks an extreme eigenpair against Eigen's solver; returns true when it took the fast path.
bool CheckExtremeEigenpair(const Eigen::Matrix3d& A, bool largest) {
  const ExtremeEigenpair eig = largest ? LargestEigenpair(A) : SmallestEigenpair(A);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A);
  const Eigen::Vector3d l = es.eigenvalues();
  const int end = largest ? 2 : 0;
  const double tol = 1e-12 * l.cwiseAbs().maxCoeff();
  EXPECT_NEAR(eig.value, l(end), tol);
  // The middle one comes from a quadratic: where the other two nearly coincide, its discriminant
  // cancels and it is good to ~sqrt(epsilon) only (as is any quadratic's double root).
  const double other_gap = largest ? l(1) - l(0) : l(2) - l(1);
  EXPECT_NEAR(eig.middle, l(1), other_gap > 1e-3 * l(2) ? tol : 1e-7 * l(2));
  EXPECT_NEAR(eig.vector.norm(), 1.0, 1e-12);
  EXPECT_LE((A * eig.vector - eig.value * eig.vector).norm(), 1e-10 * l.cwiseAbs().maxCoeff());
  // The direction itself where the eigenvalue is separated (else any vector of its eigenspace).
  const double gap = largest ? l(2) - l(1) : l(1) - l(0);
  if (gap > 1e-3 * l(2)) {
    EXPECT_NEAR(std::abs(eig.vector.dot(es.eigenvectors().col(end))), 1.0, 1e-9);
  }
  return !eig.fallback;
}

TEST(ExtremeEigenpair, MatchesTheFullSolverOnCovariances) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> log_scale(-3.0, 3.0);
  int checked = 0, fast = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const double scale = std::pow(10.0, log_scale(rng));
    // Planar (a map plane), linear (a map edge) and general spreads, from 5 or 20 points.
    for (const Eigen::Vector3d& sd :
         {Eigen::Vector3d(1.0, 0.8, 0.01), Eigen::Vector3d(1.0, 0.05, 0.02),
          Eigen::Vector3d(1.0, 0.6, 0.3)}) {
      const Eigen::Matrix3d A = RandomCovariance(&rng, scale * sd, trial % 2 ? 5 : 20);
      for (const bool largest : {false, true}) {
        fast += CheckExtremeEigenpair(A, largest);
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 6000);
  EXPECT_GT(fast, 5900);  // the fallback is for eigenvalues that are not well separated
}

TEST(ExtremeEigenpair, DegenerateMatricesFallBackToTheFullSolver) {
  int checked = 0;
  auto expect = [&](const Eigen::Matrix3d& A, bool largest, bool fallback) {
    const ExtremeEigenpair eig = largest ? LargestEigenpair(A) : SmallestEigenpair(A);
    EXPECT_EQ(eig.fallback, fallback) << A << (largest ? " largest" : " smallest");
    ++checked;
    return eig;
  };
  // Three equal eigenvalues (zero, isotropic): any unit vector.
  for (const double c : {0.0, 2.5}) {
    for (const bool largest : {false, true}) {
      const ExtremeEigenpair eig = expect(c * Eigen::Matrix3d::Identity(), largest, true);
      EXPECT_NEAR(eig.value, c, 1e-14);
      EXPECT_NEAR(eig.middle, c, 1e-14);
      EXPECT_NEAR(eig.vector.norm(), 1.0, 1e-15);
    }
  }
  // Collinear points (rank 1): the smallest eigenvalue is double, the largest is separated.
  const Eigen::Vector3d u = Eigen::Vector3d(1.0, 2.0, -0.5).normalized();
  const Eigen::Matrix3d line = 3.0 * u * u.transpose();
  EXPECT_TRUE(expect(line, true, false).vector.cross(u).norm() < 1e-12);
  EXPECT_NEAR(expect(line, false, true).value, 0.0, 1e-14);
  // A round disc (two equal largest eigenvalues): its normal is separated.
  const Eigen::Matrix3d disc = Eigen::Vector3d(2.0, 2.0, 0.0).asDiagonal();
  EXPECT_TRUE(CheckExtremeEigenpair(disc, false));
  EXPECT_NEAR(std::abs(SmallestEigenpair(disc).vector.z()), 1.0, 1e-15);
  expect(disc, true, true);
  EXPECT_NEAR(LargestEigenpair(disc).value, 2.0, 1e-14);
  // Not positive semi-definite (the start from [0, trace] would lie between the roots): the same
  // eigenpairs as the full solver, from the general bound.
  const Eigen::Matrix3d indefinite = Eigen::Vector3d(-3.0, 0.5, 2.0).asDiagonal();
  EXPECT_TRUE(CheckExtremeEigenpair(indefinite, false));
  EXPECT_TRUE(CheckExtremeEigenpair(indefinite, true));
  EXPECT_NEAR(SmallestEigenpair(indefinite).value, -3.0, 1e-14);
  EXPECT_NEAR(LargestEigenpair(indefinite).value, 2.0, 1e-14);
  // Non-finite input goes to the full solver (whatever it returns is not finite).
  Eigen::Matrix3d bad = line;
  bad(1, 0) = std::numeric_limits<double>::quiet_NaN();
  expect(bad, false, true);
  EXPECT_EQ(checked, 8);
}

TEST(Fitting, PlaneFromThreePoints) {
  const Eigen::Vector3d p1(1, 0, 2), p2(0, 1, 2), p3(3, 3, 2);
  const PlaneFit f = PlaneFromPoints(p1, p2, p3);
  ASSERT_TRUE(f.ok());
  // (p2 - p1) x (p3 - p1) = (-1, 1, 0) x (2, 3, 0) = (0, 0, -5): m = -z, e = 2.
  EXPECT_TRUE(f.plane.isApprox(Eigen::Vector4d(0, 0, -1, 2), 1e-15));
  for (const auto& p : {p1, p2, p3}) EXPECT_NEAR(PointPlaneDistance(f.plane, p), 0.0, 1e-15);
  EXPECT_NEAR(PointPlaneDistance(f.plane, Eigen::Vector3d(5, -7, 0)), 2.0, 1e-15);
}

TEST(Fitting, PlaneFromThreePointsDegenerate) {
  const Eigen::Vector3d a(1, 2, 3), dir(0.3, -0.2, 0.5);
  EXPECT_EQ(PlaneFromPoints(a, a + dir, a + 2.5 * dir).status, FitStatus::kDegenerate);
  EXPECT_EQ(PlaneFromPoints(a, a, a + dir).status, FitStatus::kDegenerate);
  EXPECT_EQ(PlaneFromPoints(a, a, a).status, FitStatus::kDegenerate);
  const PlaneFit f = PlaneFromPoints(a, Eigen::Vector3d(std::nan(""), 0, 0), a + dir);
  EXPECT_EQ(f.status, FitStatus::kNonFinite);
  EXPECT_TRUE(f.plane.allFinite());
}

TEST(Fitting, LeastSquaresPlaneExact) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-5, 5);
  const Eigen::Vector3d m = Eigen::Vector3d(0.2, -0.5, 0.8).normalized();
  const double e = -3.0;
  const Eigen::Vector3d a = m.unitOrthogonal(), b = m.cross(a);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 5; ++i) pts.push_back(-e * m + u(rng) * a + u(rng) * b);
  const PlaneFit f = FitPlane(pts);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f.num_points, 5);
  const Eigen::Vector4d expected(m.x(), m.y(), m.z(), e);
  EXPECT_LT(std::min((f.plane - expected).norm(), (f.plane + expected).norm()), 1e-12);
  EXPECT_NEAR(f.plane.head<3>().norm(), 1.0, 1e-15);
  EXPECT_LT(f.rms_distance, 1e-12);
  EXPECT_LT(f.max_abs_distance, 1e-12);
  EXPECT_LT(f.thickness_ratio, 1e-24);
}

TEST(Fitting, LeastSquaresPlaneNoisyMeasures) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::array<Eigen::Vector3f, 200> pts;  // float points through iterators
  for (auto& p : pts) p = Eigen::Vector3d(u(rng), u(rng), 2.0 + noise(rng)).cast<float>();
  const PlaneFit f = FitPlane(pts.begin(), pts.end());
  ASSERT_TRUE(f.ok());
  EXPECT_NEAR(std::abs(f.plane(2)), 1.0, 1e-3);
  EXPECT_NEAR(f.rms_distance, 0.01, 0.002);
  EXPECT_GT(f.max_abs_distance, f.rms_distance);
  EXPECT_LT(f.max_abs_distance, 0.05);
  // Uniform in a 2 x 2 square: lambda1 ~ 1/3; lambda0 ~ 1e-4.
  EXPECT_NEAR(f.thickness_ratio, 3e-4, 1.5e-4);
  EXPECT_TRUE(f.eigenvalues(0) <= f.eigenvalues(1) && f.eigenvalues(1) <= f.eigenvalues(2));
}

TEST(Fitting, LeastSquaresPlaneDegenerate) {
  std::vector<Eigen::Vector3d> pts = {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(2, 2, 2)};
  EXPECT_EQ(FitPlane(pts).status, FitStatus::kTooFewPoints);
  EXPECT_EQ(FitPlane(std::vector<Eigen::Vector3d>{}).status, FitStatus::kTooFewPoints);
  pts.push_back(Eigen::Vector3d(5, 5, 5));  // collinear
  pts.push_back(Eigen::Vector3d(-1, -1, -1));
  PlaneFit f = FitPlane(pts);
  EXPECT_EQ(f.status, FitStatus::kDegenerate);
  EXPECT_TRUE(f.plane.allFinite());
  const std::vector<Eigen::Vector3d> same(6, Eigen::Vector3d(1, 2, 3));  // coincident
  EXPECT_EQ(FitPlane(same).status, FitStatus::kDegenerate);
  pts.push_back(Eigen::Vector3d(0, std::numeric_limits<double>::infinity(), 0));
  f = FitPlane(pts);
  EXPECT_EQ(f.status, FitStatus::kNonFinite);
  EXPECT_TRUE(f.plane.allFinite());
  EXPECT_TRUE(f.centroid.allFinite());
}

TEST(Fitting, LineFitExactAndNoisy) {
  const Eigen::Vector3d c(1, -2, 3), d = Eigen::Vector3d(1, 2, -0.5).normalized();
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 5; ++i) pts.push_back(c + (i - 2) * 0.7 * d);
  const LineFit f = FitLine(pts);
  ASSERT_TRUE(f.ok());
  const Eigen::Vector3d fd = f.L.tail<3>();
  EXPECT_NEAR(std::abs(fd.dot(d)), 1.0, 1e-14);
  EXPECT_NEAR(fd.norm(), 1.0, 1e-15);
  EXPECT_LT((f.L.head<3>() - c.cross(fd)).norm(), 1e-12);  // n = p x d for a point p on it
  EXPECT_LT(f.linearity_ratio, 1e-14);
  EXPECT_LT(f.rms_distance, 1e-12);
  EXPECT_LT(f.max_distance, 1e-12);

  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<Eigen::Vector3d> noisy;
  for (int i = 0; i < 100; ++i) {
    noisy.push_back(c + (i * 0.05 - 2.5) * d + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  }
  const LineFit g = FitLine(noisy);
  ASSERT_TRUE(g.ok());
  EXPECT_GT(std::abs(g.L.tail<3>().dot(d)), std::cos(1.0 * M_PI / 180));
  EXPECT_NEAR(g.rms_distance, 0.02 * std::sqrt(2.0), 0.008);
  EXPECT_LT(g.linearity_ratio, 1.0 / 3.0);

  // A plane patch is not a line.
  std::vector<Eigen::Vector3d> patch = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                        Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 1, 0)};
  EXPECT_NEAR(FitLine(patch).linearity_ratio, 1.0, 1e-12);
}

TEST(Fitting, LineFitDegenerate) {
  EXPECT_EQ(FitLine(std::vector<Eigen::Vector3d>{Eigen::Vector3d(1, 2, 3)}).status,
            FitStatus::kTooFewPoints);
  const LineFit f = FitLine(std::vector<Eigen::Vector3d>(5, Eigen::Vector3d(1, 2, 3)));
  EXPECT_EQ(f.status, FitStatus::kDegenerate);
  EXPECT_TRUE(f.L.allFinite());
  std::vector<Eigen::Vector3d> pts = {Eigen::Vector3d(0, 0, 0),
                                      Eigen::Vector3d(std::nan(""), 0, 0)};
  EXPECT_EQ(FitLine(pts).status, FitStatus::kNonFinite);
  // Two distinct points are enough.
  pts[1] = Eigen::Vector3d(0, 0, 2);
  const LineFit two = FitLine(pts);
  ASSERT_TRUE(two.ok());
  EXPECT_NEAR(std::abs(two.L(5)), 1.0, 1e-15);
}

TEST(Fitting, NormalizePlane) {
  EXPECT_TRUE(NormalizePlane(Eigen::Vector4d(0, 0, 2, 4))->isApprox(Eigen::Vector4d(0, 0, 1, 2)));
  EXPECT_FALSE(NormalizePlane(Eigen::Vector4d(0, 0, 0, 1)).has_value());
  EXPECT_FALSE(NormalizePlane(Eigen::Vector4d(0, std::nan(""), 1, 1)).has_value());
}

TEST(Fitting, FarFromTheOriginIsAccurate) {
  // KITTI-scale coordinates: the two-pass covariance keeps the small spread exact.
  const Eigen::Vector3d o(4000.0, -2500.0, 30.0);
  std::vector<Eigen::Vector3d> pts = {
      o, o + Eigen::Vector3d(0.1, 0, 0), o + Eigen::Vector3d(0, 0.1, 0),
      o + Eigen::Vector3d(0.1, 0.1, 0), o + Eigen::Vector3d(0.05, 0.02, 0)};
  const PlaneFit f = FitPlane(pts);
  ASSERT_TRUE(f.ok());
  EXPECT_NEAR(std::abs(f.plane(2)), 1.0, 1e-9);
  EXPECT_LT(f.max_abs_distance, 1e-9);
}

}  // namespace
}  // namespace plucker
