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
  EXPECT_NEAR(remapped.translation().x(), 1.0, 1e-9);   // prior kept along x
  EXPECT_NEAR(remapped.translation().y(), 0.2, 1e-9);   // solution kept elsewhere
  EXPECT_NEAR(remapped.translation().z(), -0.1, 1e-9);
  EXPECT_NEAR(LogSO3(remapped.rotation()).z(), 0.01, 1e-9);
  // Not degenerate: the solution is returned unchanged.
  DegeneracyInfo fine = info;
  fine.degenerate = false;
  EXPECT_NEAR(RemapSolution(prior, solution, fine, 1e-3).translation().x(), 3.0, 1e-12);
}

TEST(DegeneracyTest, EdgesAndEmptyProblem) {
  NormalEquations empty;
  EXPECT_TRUE(empty.Analyse(1e-3).degenerate);
  NormalEquations eq;
  // Vertical poles at several places constrain x, y and yaw only.
  for (int i = 0; i < 20; ++i)
    eq.AddEdge(SE3d(), Eigen::Vector3d(5.0 * std::cos(i), 5.0 * std::sin(i), 0.1 * i),
               Eigen::Vector3d(0, 0, 1), 0.1);
  const DegeneracyInfo info = eq.Analyse(1e-6);
  EXPECT_EQ(info.num_degenerate_directions, 3);  // z, roll, pitch
  EXPECT_EQ(eq.rows(), 40);
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
