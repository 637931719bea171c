#include "plucker/lidar/degeneracy.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

#include "plucker/factors/lidar_factors.h"
#include "plucker/lidar/pose_solver.h"

namespace plucker {
namespace lidar {
namespace {

// Residual blocks (the odometry's factors) at T_w_s, their independent rows, and the analysis of
// their normal equations as SolvePose returns them (no robust loss here: every weight is 1).
struct Rows {
  SE3d T_w_s;
  LidarResiduals residuals;
  int rows = 0;
  // A point-to-plane row at p_s with the world normal m_w (the plane passes through T_w_s p_s).
  void AddPlane(const Eigen::Vector3d& p_s, const Eigen::Vector3d& m_w, double sigma) {
    residuals.planes.push_back(PlaneResidual::Create(p_s, m_w, T_w_s * p_s, sigma));
    rows += 1;
  }
  // A point-to-edge block for the world line through T_w_s p_s with direction u_w (rank 2).
  void AddEdge(const Eigen::Vector3d& p_s, const Eigen::Vector3d& u_w, double sigma) {
    residuals.edges.push_back(EdgeResidual::CreateFromDirection(p_s, T_w_s * p_s, u_w, sigma));
    rows += 2;
  }
  DegeneracyInfo Analyse(const DegeneracyCriterion& criterion) const {
    NormalEquations eq;
    EXPECT_TRUE(EvaluateNormalEquations(residuals, nullptr, T_w_s, &eq));
    return AnalyseDegeneracy(eq.H, rows, criterion);
  }
  // Ratios only (no ceilings): `threshold` for translations, threshold / 3 for rotations.
  DegeneracyInfo Analyse(double threshold) const {
    DegeneracyCriterion criterion;
    criterion.translation_ratio = threshold;
    criterion.rotation_ratio = threshold / 3.0;
    return Analyse(criterion);
  }
};

// Plane points on the floor and two walls of a corridor along x: nothing constrains x.
Rows Corridor(const SE3d& T_w_s) {
  Rows eq;
  eq.T_w_s = T_w_s;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-20, 20);
  for (int i = 0; i < 300; ++i) {
    const double x = u(rng);
    eq.AddPlane(Eigen::Vector3d(x, -2, 0.1 * u(rng)), Eigen::Vector3d(0, 1, 0), 0.05);
    eq.AddPlane(Eigen::Vector3d(x, 2, 0.1 * u(rng)), Eigen::Vector3d(0, -1, 0), 0.05);
    eq.AddPlane(Eigen::Vector3d(x, 0.1 * u(rng), -1.5), Eigen::Vector3d(0, 0, 1), 0.05);
  }
  return eq;
}

TEST(DegeneracyTest, CorridorAxisIsTheDegenerateDirection) {
  const SE3d T_w_s;  // identity: world and scan axes agree
  const DegeneracyInfo info = Corridor(T_w_s).Analyse(1e-3);
  EXPECT_TRUE(info.degenerate);
  EXPECT_EQ(info.num_degenerate_directions, 1);
  EXPECT_NEAR(info.eigenvalues(0), 0.0, 1e-9);
  EXPECT_NEAR(std::abs(info.eigenvectors(3, 0)), 1.0, 1e-9);  // dt_x
  EXPECT_GT(info.eigenvalues(1), 1.0);
}

TEST(DegeneracyTest, RemappingKeepsThePriorAlongTheDegenerateAxis) {
  const SE3d prior(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1.0, 0.0, 0.0));
  const DegeneracyInfo info = Corridor(prior).Analyse(1e-3);
  const SE3d solution(ExpSO3<double>(Eigen::Vector3d(0.0, 0.0, 0.01)),
                      Eigen::Vector3d(3.0, 0.2, -0.1));
  const SE3d remapped = RemapSolution(prior, solution, info);
  EXPECT_NEAR(remapped.translation().x(), 1.0, 1e-9);  // prior kept along x
  EXPECT_NEAR(remapped.translation().y(), 0.2, 1e-9);  // solution kept elsewhere
  EXPECT_NEAR(remapped.translation().z(), -0.1, 1e-9);
  EXPECT_NEAR(LogSO3(remapped.rotation()).z(), 0.01, 1e-9);
  // Not degenerate: the solution is returned unchanged.
  DegeneracyInfo fine = info;
  fine.degenerate = false;
  EXPECT_NEAR(RemapSolution(prior, solution, fine).translation().x(), 3.0, 1e-12);
}

TEST(DegeneracyTest, EdgesAndEmptyProblem) {
  EXPECT_TRUE(Rows().Analyse(1e-3).degenerate);
  Rows eq;
  // Vertical poles at several places: nothing constrains the translation along z (points at
  // different heights make roll and pitch observable through the horizontal residual).
  for (int i = 0; i < 20; ++i)
    eq.AddEdge(Eigen::Vector3d(5.0 * std::cos(i), 5.0 * std::sin(i), 0.1 * i),
               Eigen::Vector3d(0, 0, 1), 0.1);
  const DegeneracyInfo info = eq.Analyse(1e-6);
  EXPECT_EQ(info.num_degenerate_directions, 1);
  EXPECT_NEAR(std::abs(info.eigenvectors(5, 0)), 1.0, 1e-9);  // dt_z
  EXPECT_EQ(eq.rows, 40);
}

// A plane row whose normal is the true one tilted by Gaussian noise of `tilt` radians (what a
// plane fitted to a few noisy map points gives).
void AddTiltedPlane(const Eigen::Vector3d& p, const Eigen::Vector3d& m, double tilt,
                    std::mt19937* rng, Rows* eq) {
  std::normal_distribution<double> n(0.0, tilt);
  const Eigen::Vector3d noisy = (m + Eigen::Vector3d(n(*rng), n(*rng), n(*rng))).normalized();
  eq->AddPlane(p, noisy, 0.05);
}

// Corridor along x, 6 m wide and 4 m high (sensor 1.7 m above the floor), as a VLP-16 sees it;
// normals tilted by `tilt` (0.03 rad ~ 2 cm range noise over a 1 m neighbourhood).
Rows NoisyCorridor(double tilt, int seed) {
  Rows eq;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-40, 40), u(-1, 1);
  for (int i = 0; i < 500; ++i) {
    AddTiltedPlane({x(rng), -3.0, 2.0 * u(rng)}, {0, 1, 0}, tilt, &rng, &eq);
    AddTiltedPlane({x(rng), 3.0, 2.0 * u(rng)}, {0, -1, 0}, tilt, &rng, &eq);
    AddTiltedPlane({0.2 * x(rng), 3.0 * u(rng), -1.7}, {0, 0, 1}, tilt, &rng, &eq);
    AddTiltedPlane({0.2 * x(rng), 3.0 * u(rng), 2.3}, {0, 0, -1}, tilt, &rng, &eq);
  }
  return eq;
}

// A street: ground, two facades along x, and a few surfaces facing the driving direction (cross
// walls, car backs, window recesses: 8% of the rows), same noise.
Rows NoisyStreet(double tilt, int seed) {
  Rows eq;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-40, 40), u(-1, 1);
  for (int i = 0; i < 1000; ++i) {
    const double r = (i % 100) / 100.0;
    if (r < 0.5) {
      AddTiltedPlane({x(rng), 8.0 * u(rng), -1.7}, {0, 0, 1}, tilt, &rng, &eq);
    } else if (r < 0.92) {
      const double side = u(rng) < 0 ? -8.0 : 8.0;
      AddTiltedPlane({x(rng), side, 6.0 * u(rng)}, {0, side < 0 ? 1.0 : -1.0, 0}, tilt, &rng, &eq);
    } else {
      const double ahead = x(rng);
      AddTiltedPlane({ahead, 8.0 * u(rng), u(rng)}, {ahead < 0 ? 1.0 : -1.0, 0, 0}, tilt, &rng,
                     &eq);
    }
  }
  return eq;
}

// The reason for the relative criterion: with noisy normals the corridor axis receives
// (tilt / sigma)^2 of information per row, above the old absolute threshold 0.3 on H/N, but it
// stays a small fraction of the next direction.
TEST(DegeneracyTest, NoisyCorridorIsFlaggedAlongItsAxis) {
  const double kThreshold = 0.03;  // LidarOdometryOptions::degeneracy_threshold
  for (double tilt : {0.005, 0.015, 0.03, 0.05}) {
    for (int seed = 1; seed <= 3; ++seed) {
      const DegeneracyInfo info = NoisyCorridor(tilt, seed).Analyse(kThreshold);
      SCOPED_TRACE(::testing::Message() << "tilt " << tilt << " seed " << seed);
      EXPECT_TRUE(info.degenerate) << info.translation_ratios.transpose();
      EXPECT_EQ(info.num_degenerate_translations, 1);
      EXPECT_EQ(info.num_degenerate_rotations, 0) << info.rotation_ratios.transpose();
      EXPECT_GT(std::abs(info.translation_directions(0, 0)), 0.99);  // along x
      EXPECT_LT(info.translation_ratios(0), 0.01);
      if (tilt >= 0.03) {
        EXPECT_GT(info.eigenvalues(0), 0.3);  // missed by the old absolute test
      }
    }
  }
}

TEST(DegeneracyTest, NoisyStreetIsNotFlagged) {
  for (double tilt : {0.005, 0.03, 0.05}) {
    for (int seed = 1; seed <= 3; ++seed) {
      const DegeneracyInfo info = NoisyStreet(tilt, seed).Analyse(0.03);
      SCOPED_TRACE(::testing::Message() << "tilt " << tilt << " seed " << seed);
      EXPECT_FALSE(info.degenerate)
          << info.translation_ratios.transpose() << " | " << info.rotation_ratios.transpose();
      EXPECT_GT(info.translation_ratios(0), 0.05);
    }
  }
}

// The odometry's default criterion (LidarOdometryOptions): ratio 0.03 and a ceiling of 1.3 on the
// translation information per row; rotations off.
DegeneracyCriterion DefaultCriterion() {
  DegeneracyCriterion c;
  c.translation_ratio = 0.03;
  c.max_translation_information = 1.3;
  c.rotation_ratio = 0.0;
  return c;
}

// An open square: the ground dominates (97 % of the rows) and a few facades far away fix x and
// y. Relative to the ground's z the horizontal directions are weak (ratio < 0.03), but each row
// still carries ~6 (1/sigma^2) of horizontal information: the ceiling keeps them unflagged.
// The noisy corridor's axis stays below the ceiling and is flagged.
TEST(DegeneracyTest, CeilingSeparatesAnOpenSquareFromANoisyCorridor) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  Rows square;
  for (int i = 0; i < 3000; ++i) {
    if (i % 100 < 97) {
      AddTiltedPlane({30 * u(rng), 30 * u(rng), -1.7}, {0, 0, 1}, 0.02, &rng, &square);
    } else {
      const double angle = 3.14159 * u(rng);
      const Eigen::Vector3d m(-std::cos(angle), -std::sin(angle), 0.0);
      AddTiltedPlane(-40.0 * m + Eigen::Vector3d(0, 0, 3 * u(rng)), m, 0.02, &rng, &square);
    }
  }
  const DegeneracyInfo ratio_only = square.Analyse(0.03);
  EXPECT_GE(ratio_only.num_degenerate_translations, 2) << ratio_only.translation_ratios.transpose();
  const DegeneracyInfo with_ceiling = square.Analyse(DefaultCriterion());
  EXPECT_FALSE(with_ceiling.degenerate) << with_ceiling.translation_information.transpose();
  EXPECT_GT(with_ceiling.translation_information(0), 1.3);

  for (double tilt : {0.005, 0.015, 0.03}) {
    const DegeneracyInfo corridor = NoisyCorridor(tilt, 1).Analyse(DefaultCriterion());
    SCOPED_TRACE(::testing::Message() << "tilt " << tilt);
    EXPECT_EQ(corridor.num_degenerate_translations, 1)
        << corridor.translation_information.transpose();
    EXPECT_EQ(corridor.num_degenerate_rotations, 0);
    EXPECT_EQ(corridor.translation_flags(0), 1);
    EXPECT_GT(std::abs(corridor.translation_directions(0, 0)), 0.99);
  }
}

// The criterion is relative: scaling H (sigma, number of points) changes nothing.
TEST(DegeneracyTest, CriterionIsInvariantToScalingH) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 0.02);
  Rows a, b;  // b: sigma 10x larger and every row twice
  std::uniform_real_distribution<double> x(-30, 30), u(-1, 1);
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d p(x(rng), i % 2 ? 3.0 : -3.0, 2.0 * u(rng));
    const Eigen::Vector3d m =
        (Eigen::Vector3d(0, i % 2 ? -1 : 1, 0) + Eigen::Vector3d(n(rng), n(rng), n(rng)))
            .normalized();
    const Eigen::Vector3d g(0.2 * x(rng), 3.0 * u(rng), -1.7);
    a.AddPlane(p, m, 0.05);
    a.AddPlane(g, Eigen::Vector3d::UnitZ(), 0.05);
    for (int k = 0; k < 2; ++k) {
      b.AddPlane(p, m, 0.5);
      b.AddPlane(g, Eigen::Vector3d::UnitZ(), 0.5);
    }
  }
  const DegeneracyInfo ia = a.Analyse(0.03), ib = b.Analyse(0.03);
  EXPECT_TRUE(ia.degenerate);
  EXPECT_EQ(ia.num_degenerate_directions, ib.num_degenerate_directions);
  EXPECT_LT((ia.translation_ratios - ib.translation_ratios).norm(), 1e-9);
  EXPECT_LT((ia.rotation_ratios - ib.rotation_ratios).norm(), 1e-9);
  // The absolute eigenvalues scale by sigma^-2 (the old criterion depended on sigma).
  EXPECT_NEAR(ib.eigenvalues(5) / ia.eigenvalues(5), 0.01, 1e-9);
  // Same remapped pose.
  const SE3d prior(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0));
  const SE3d solution(ExpSO3<double>(Eigen::Vector3d(0.01, -0.02, 0.03)), Eigen::Vector3d(2, 1, 0));
  const Vector6d da = RemapSolution(prior, solution, ia).Minus(prior);
  const Vector6d db = RemapSolution(prior, solution, ib).Minus(prior);
  EXPECT_LT((da - db).norm(), 1e-6);
}

// Rotational degeneracies: a round tunnel leaves the roll about its axis free; a single plane
// leaves the two in-plane translations and the rotation about its normal free.
TEST(DegeneracyTest, RoundTunnelAndSinglePlane) {
  Rows tunnel, plane;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(-30, 30), a(-M_PI, M_PI), u(-1, 1);
  for (int i = 0; i < 600; ++i) {
    const double phi = a(rng);
    const Eigen::Vector3d radial(0, std::cos(phi), std::sin(phi));
    AddTiltedPlane(Eigen::Vector3d(x(rng), 0, 0) + 2.5 * radial, -radial, 0.03, &rng, &tunnel);
    AddTiltedPlane({x(rng), x(rng), -1.7}, {0, 0, 1}, 0.03, &rng, &plane);
  }
  const DegeneracyInfo t = tunnel.Analyse(0.03);
  EXPECT_EQ(t.num_degenerate_rotations, 1) << t.rotation_ratios.transpose();
  EXPECT_GT(std::abs(t.rotation_directions(0, 0)), 0.99);  // roll about x
  EXPECT_EQ(t.num_degenerate_translations, 1) << t.translation_ratios.transpose();
  EXPECT_GT(std::abs(t.translation_directions(0, 0)), 0.99);  // along x
  const DegeneracyInfo p = plane.Analyse(0.03);
  EXPECT_EQ(p.num_degenerate_translations, 2) << p.translation_ratios.transpose();
  EXPECT_GT(std::abs(p.translation_directions(2, 2)), 0.99);  // only z is constrained
  EXPECT_EQ(p.num_degenerate_rotations, 1) << p.rotation_ratios.transpose();
  EXPECT_GT(std::abs(p.rotation_directions(2, 0)), 0.99);  // yaw is free
  // Remapping keeps the prior along all three and the solution elsewhere.
  const SE3d prior(ExpSO3<double>(Eigen::Vector3d(0, 0, 0.1)), Eigen::Vector3d(1, 2, 3));
  const SE3d solution(ExpSO3<double>(Eigen::Vector3d(0.01, 0.02, 0.3)), Eigen::Vector3d(4, 5, 6));
  const Vector6d d = RemapSolution(prior, solution, p).Minus(prior);
  const Vector6d d_solution = solution.Minus(prior);
  for (int i = 0; i < 2; ++i)  // the prior exactly along the flagged (noisy) directions
    EXPECT_NEAR(p.translation_directions.col(i).dot(d.tail<3>()), 0.0, 1e-9);
  EXPECT_NEAR(p.rotation_directions.col(0).dot(d.head<3>()), 0.0, 1e-9);
  EXPECT_LT(d.segment<2>(3).norm(), 0.01);  // ~ the prior in x, y (directions tilted by noise)
  EXPECT_NEAR(d(5), d_solution(5), 0.05);
}

// Coupled degeneracy: the remapped update satisfies the constraints exactly and, for a
// quadratic cost, is the constrained minimiser (the other coordinates re-optimised).
TEST(DegeneracyTest, RemappingIsTheConstrainedMinimiserOfTheQuadraticModel) {
  const DegeneracyInfo info = NoisyCorridor(0.03, 7).Analyse(0.03);
  ASSERT_TRUE(info.degenerate);
  const SE3d prior;
  const Vector6d delta = (Vector6d() << 0.01, -0.02, 0.005, 0.8, 0.1, -0.05).finished();
  const SE3d solution = prior.Plus(delta);
  const Vector6d d = RemapSolution(prior, solution, info).Minus(prior);
  const Eigen::Vector3d v = info.translation_directions.col(0);
  EXPECT_NEAR(v.dot(d.tail<3>()), 0.0, 1e-9);
  // Stationarity of (d - delta)^T H (d - delta) on the constraint surface: the gradient
  // H (d - delta) is along the constraint normal [0; v].
  const Vector6d g = info.information * (d - delta);
  Vector6d c = Vector6d::Zero();
  c.tail<3>() = v;
  EXPECT_LT((g - c * c.dot(g)).norm(), 1e-6 * g.norm() + 1e-9);
}

TEST(DegeneracyTest, NonFiniteInputFlagsEverythingAndKeepsThePrior) {
  Matrix6d H = Matrix6d::Identity();
  H(0, 1) = NAN;
  const DegeneracyInfo info = AnalyseDegeneracy(H, 10, DegeneracyCriterion());
  EXPECT_TRUE(info.degenerate);
  EXPECT_EQ(info.num_degenerate_directions, 6);
  const SE3d prior(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 2, 3));
  const SE3d remapped = RemapSolution(prior, SE3d(), info);
  EXPECT_LT((remapped.translation() - prior.translation()).norm(), 1e-12);
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
