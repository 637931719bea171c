// TEMPORARY dev harness (deleted before hand-off).
#include <gtest/gtest.h>
#include <cstdlib>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include "plucker/io/lidar_sequence.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/lidar/odometry.h"
#include "plucker/lidar/scan_test_utils.h"
namespace plucker { namespace lidar {
static double Env(const char* n, double d) { const char* v = std::getenv(n); return v ? std::atof(v) : d; }
static LidarOdometryOptions Opts() {
  LidarOdometryOptions o;
  o.association_rounds = Env("ROUNDS", o.association_rounds);
  o.max_iterations = Env("ITERS", o.max_iterations);
  o.use_edges = Env("EDGES", 1) > 0;
  o.plane_sigma = Env("PSIG", o.plane_sigma);
  o.edge_sigma = Env("ESIG", o.edge_sigma);
  o.loss_scale = Env("LOSS", o.loss_scale);
  o.features.plane_voxel_size = Env("PVOX", o.features.plane_voxel_size);
  o.features.edge_voxel_size = Env("EVOX", o.features.edge_voxel_size);
  o.plane_map.min_point_distance = Env("PMIN", o.plane_map.min_point_distance);
  o.plane_map.max_points_per_voxel = Env("PCAP", o.plane_map.max_points_per_voxel);
  o.plane_map.voxel_size = Env("PMV", o.plane_map.voxel_size);
  o.edge_map.voxel_size = Env("PMV", o.edge_map.voxel_size);
  o.max_correspondence_distance = Env("MAXD", o.max_correspondence_distance);
  o.max_plane_points = Env("MAXP", o.max_plane_points);
  o.max_edge_points = Env("MAXE", o.max_edge_points);
  o.num_neighbours = Env("KNN", o.num_neighbours);
  o.features.min_range = Env("MINR", o.features.min_range);
  o.degeneracy_threshold = Env("DEG", o.degeneracy_threshold);
  o.handle_degeneracy = Env("HDEG", 1) > 0;
  o.plane_max_residual = Env("PRES", o.plane_max_residual);
  return o;
}
static double AngleDeg(const Eigen::Quaterniond& q) { return LogSO3(q).norm() * 180.0 / M_PI; }
TEST(Scratch, Kitti) {
  const std::string root = std::string(PLUCKER_SHARED_DATA_DIR) + "/kitti-odometry-00";
  const io::LidarSequence seq = io::LidarSequence::Open(root, "00");
  const std::vector<SE3d> gt = io::ReadTrajectory(root + "/poses/00.txt").poses;
  LidarOdometry odo(Opts());
  std::vector<double> ms;
  for (std::size_t i = 0; i < seq.size(); ++i) {
    LidarScan scan; std::string e; seq.Read(i, &scan, &e);
    const double corr = Env("VCORR", 0.0) * M_PI / 180.0;
    if (corr != 0) for (auto& p : scan.points) { Eigen::Vector3d axis = Eigen::Vector3d::UnitZ().cross(p).normalized(); p = Eigen::AngleAxisd(corr, axis) * p; }
    FrameResult r = odo.ProcessScan(std::move(scan));
    ms.push_back(r.timing.cpu);
    if (Env("V", 0)) printf("%zu ok=%d e=%d p=%d ce=%d cp=%d it=%d t: r%.1f f%.1f c%.1f s%.1f m%.1f tot%.1f eig %.3g %.3g %.3g\n", i, r.ok, r.edge_points, r.plane_points, r.edge_correspondences, r.plane_correspondences, r.solver_iterations, r.timing.rings, r.timing.features, r.timing.correspondences, r.timing.solve, r.timing.map_update, r.timing.cpu, r.degeneracy.eigenvalues(0), r.degeneracy.eigenvalues(1), r.degeneracy.eigenvalues(2));
  }
  const SE3d Tr = *seq.T_cam0_velo();
  std::vector<double> dt, dr;
  const auto& est = odo.poses();
  for (std::size_t i = 0; i + 1 < seq.size(); ++i) {
    const SE3d rel_est = Tr * (est[i].Inverse() * est[i + 1]) * Tr.Inverse();
    const SE3d rel_gt = gt[i].Inverse() * gt[i + 1];
    const SE3d E = rel_gt.Inverse() * rel_est;
    dt.push_back(E.translation().norm()); dr.push_back(AngleDeg(E.rotation()));
    if (Env("V", 0)) printf("  rel %zu: %.2f cm %.4f deg  (gt %.3f est %.3f) E.t=%.3f %.3f %.3f\n", i, 100*dt.back(), dr.back(), rel_gt.translation().norm(), rel_est.translation().norm(), 100*E.translation().x(), 100*E.translation().y(), 100*E.translation().z());
  }
  std::sort(dt.begin(), dt.end()); std::sort(dr.begin(), dr.end()); std::sort(ms.begin(), ms.end());
  printf("KITTI median %.2f cm %.4f deg  mean-ish; ms median %.1f\n", 100*0.5*(dt[7]+dt[7]), dr[7], ms[8]);
}
TEST(Scratch, Urban) {
  const test::Scene scene = test::UrbanScene();
  test::ScanPattern pattern; pattern.noise = Env("NOISE", 0.01);
  LidarOdometry odo(Opts());
  for (int i = 0; i < 8; ++i) {
    const double yaw = i * M_PI / 180.0 * Env("YAW", 1.0);
    const SE3d T(ExpSO3<double>(Eigen::Vector3d(0, 0.0, yaw)), Eigen::Vector3d(1.0 * i, 0.05 * i * i, 0.0));
    FrameResult r = odo.ProcessScan(test::MakeScan(scene, T, pattern, i + 1));
    const SE3d E = T.Inverse() * r.T_w_s;
    printf("%d ok=%d ce=%d cp=%d it=%d err %.2f cm %.4f deg  %s cost %.3g\n", i, r.ok, r.edge_correspondences, r.plane_correspondences, r.solver_iterations, 100*E.translation().norm(), AngleDeg(E.rotation()), "", r.final_cost);
  }
}
}}
namespace plucker { namespace lidar {
TEST(Scratch, Consistency) {
  const std::string root = std::string(PLUCKER_SHARED_DATA_DIR) + "/kitti-odometry-00";
  const io::LidarSequence seq = io::LidarSequence::Open(root, "00");
  const std::vector<SE3d> gt = io::ReadTrajectory(root + "/poses/00.txt").poses;
  const SE3d Tr = *seq.T_cam0_velo();
  const int a = Env("A", 0), b = Env("B", 1);
  LidarScan s0, s1; std::string e; seq.Read(a, &s0, &e); seq.Read(b, &s1, &e);
  const double corr = Env("VCORR", 0.0) * M_PI / 180.0;
  for (LidarScan* sc : {&s0, &s1}) for (auto& p : sc->points) { Eigen::Vector3d axis = p.cross(Eigen::Vector3d::UnitZ()).normalized(); p = Eigen::AngleAxisd(corr, axis) * p; }
  VoxelMap map({1.0, 200, 0.05, 1e9});
  std::vector<Eigen::Vector3d> p0;
  for (auto& p : s0.points) if (p.norm() > 3 && p.norm() < 60) p0.push_back(p);
  map.AddPoints(p0);
  const SE3d rel_gt = Tr.Inverse() * (gt[a].Inverse() * gt[b]) * Tr;  // velo frame
  printf("gt rel velo t = %.3f %.3f %.3f\n", rel_gt.translation().x(), rel_gt.translation().y(), rel_gt.translation().z());
  for (double s = 0.6; s <= 1.05; s += 0.05) {
    SE3d T(rel_gt.rotation(), s * rel_gt.translation());
    std::vector<double> d; std::vector<Eigen::Vector3d> nb;
    for (std::size_t i = 0; i < s1.points.size(); i += 7) {
      const auto& p = s1.points[i]; if (p.norm() < 3 || p.norm() > 60) continue;
      Eigen::Vector3d q = T * p;
      if (map.KNearest(q, 6, 1.0, &nb) < 6) continue;
      Eigen::Vector3d m = Eigen::Vector3d::Zero(); for (auto& x : nb) m += x; m /= 6;
      Eigen::Matrix3d C = Eigen::Matrix3d::Zero(); for (auto& x : nb) C += (x - m) * (x - m).transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
      if (es.eigenvalues()(0) > 0.05 * es.eigenvalues()(1)) continue;
      d.push_back(std::abs(es.eigenvectors().col(0).dot(q - m)));
    }
    std::sort(d.begin(), d.end());
    double mean = 0; int c = 0; for (double x : d) if (x < 0.2) { mean += x; ++c; }
    printf("scale %.2f: n=%zu median %.4f  mean(<0.2) %.4f\n", s, d.size(), d[d.size()/2], mean / c);
  }
}
}}
