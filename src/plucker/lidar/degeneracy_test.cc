#include "plucker/lidar/degeneracy.h"

#include <gtest/gtest.h>

#include <random>

namespace plucker {
namespace lidar {
namespace {

// Plane points on the floor and two walls of a corridor along x: nothing constrains x.
NormalEquations Corridor(const SE3d& T_w_s) {
  NormalEquations eq;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-20, 20);
  for (int i = 0; i < 300; ++i) {
    const double x = u(rng);
    eq.AddPlane(T_w_s, Eigen::Vector3d(x, -2, 0.1 * u(rng)), Eigen::Vector3d(0, 1, 0), 0.05);
    eq.AddPlane(T_w_s, Eigen::Vector3d(x, 2, 0.1 * u(rng)), Eigen::Vector3d(0, -1, 0), 0.05);
    eq.AddPlane(T_w_s, Eigen::Vector3d(x, 0.1 * u(rng), -1.5), Eigen::Vector3d(0, 0, 1), 0.05);
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
  const SE3d remapped = RemapSolution(prior, solution, info, 1e-3);
  EXPECT_NEAR(remapped.translation().x(), 1.0, 1e-9);  // prior kept along x
  EXPECT_NEAR(remapped.translation().y(), 0.2, 1e-9);  // solution kept elsewhere
  EXPECT_NEAR(remapped.translation().z(), -0.1, 1e-9);
  EXPECT_NEAR(LogSO3(remapped.rotation()).z(), 0.01, 1e-9);
  // Not degenerate: the solution is returned unchanged.
  DegeneracyInfo fine = info;
  fine.degenerate = false;
  EXPECT_NEAR(RemapSolution(prior, solution, fine, 1e-3).translation().x(), 3.0, 1e-12);
}

// The normal equations use tangent Jacobians d r / d (dtheta, dt) written by hand: compare
// J^T J with central differences of the residuals through SE3d::Plus.
TEST(DegeneracyTest, JacobiansMatchCentralDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const SE3d T(ExpSO3<double>(Eigen::Vector3d(u(rng), u(rng), u(rng))),
                 Eigen::Vector3d(5 * u(rng), 5 * u(rng), u(rng)));
    const Eigen::Vector3d p_s(10 * u(rng), 10 * u(rng), 2 * u(rng));
    const Eigen::Vector3d m = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const Eigen::Vector3d q(u(rng), u(rng), u(rng));
    const double sigma = 0.05;
    auto plane = [&](const SE3d& X) { return m.dot(X * p_s - q) / sigma; };
    auto edge = [&](const SE3d& X) -> Eigen::Vector3d { return m.cross(X * p_s - q) / sigma; };
    Eigen::Matrix<double, 1, 6> Jp;
    Eigen::Matrix<double, 3, 6> Je;
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      Vector6d d = Vector6d::Zero();
      d(k) = h;
      Jp(0, k) = (plane(T.Plus(d)) - plane(T.Plus(-d))) / (2 * h);
      Je.col(k) = (edge(T.Plus(d)) - edge(T.Plus(-d))) / (2 * h);
    }
    NormalEquations eq_p, eq_e;
    eq_p.AddPlane(T, p_s, m, sigma);
    eq_e.AddEdge(T, p_s, m, sigma);
    const Matrix6d Hp = Jp.transpose() * Jp, He = Je.transpose() * Je;
    EXPECT_LT((eq_p.H() - Hp).norm(), 1e-5 * (1 + Hp.norm()));
    EXPECT_LT((eq_e.H() - He).norm(), 1e-5 * (1 + He.norm()));
  }
}

TEST(DegeneracyTest, EdgesAndEmptyProblem) {
  NormalEquations empty;
  EXPECT_TRUE(empty.Analyse(1e-3).degenerate);
  NormalEquations eq;
  // Vertical poles at several places: nothing constrains the translation along z (points at
  // different heights make roll and pitch observable through the horizontal residual).
  for (int i = 0; i < 20; ++i)
    eq.AddEdge(SE3d(), Eigen::Vector3d(5.0 * std::cos(i), 5.0 * std::sin(i), 0.1 * i),
               Eigen::Vector3d(0, 0, 1), 0.1);
  const DegeneracyInfo info = eq.Analyse(1e-6);
  EXPECT_EQ(info.num_degenerate_directions, 1);
  EXPECT_NEAR(std::abs(info.eigenvectors(5, 0)), 1.0, 1e-9);  // dt_z
  EXPECT_EQ(eq.rows(), 40);
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
