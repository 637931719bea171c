#include "plucker/io/sim_format.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "plucker/io/io_test_utils.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

using testing::Line;
using testing::ReadText;
using testing::ReplaceLine;
using testing::WriteText;

sensor::CameraImuSequence SmallSimulation() {
  sim::CameraSimulationOptions o;
  o.num_frames = 12;
  o.obs.outlier_ratio = 0.1;
  o.imu.model.rate_hz = 100.0;
  o.imu.initial_gyro_bias = Eigen::Vector3d(1e-3, -2e-3, 3e-4);
  o.seed = 77;
  return sim::ToCameraImuSequence(sim::SimulateCamera(o));
}

int CountOutliers(const sensor::CameraImuSequence& s) {
  int n = 0;
  for (const sensor::PointObservation& o : s.points) n += o.point_id < 0;
  for (const sensor::SegmentObservation& o : s.segments) n += o.line_id < 0;
  return n;
}

class SimFormatTest : public ::testing::Test {
 protected:
  // Writes a valid simulation, applies `mutate` to it and expects ReadCameraImuSequence to throw
  // an IoError whose message contains `expected` (the file name and line).
  template <typename Mutate>
  void ExpectReadError(Mutate mutate, const std::string& expected) {
    WriteCameraImuSequence(dir_, SmallSimulation());
    mutate(fs::path(dir_));
    try {
      ReadCameraImuSequence(dir_);
      ADD_FAILURE() << "no error, expected one containing '" << expected << "'";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }

  const testing::ScratchDir scratch_;
  const fs::path& root_ = scratch_.path();
  const std::string dir_ = (root_ / "sim").string();
};

TEST_F(SimFormatTest, RoundTripIsExact) {
  const sensor::CameraImuSequence a = SmallSimulation();
  ASSERT_FALSE(a.imu.empty());
  ASSERT_GT(CountOutliers(a), 0);
  WriteCameraImuSequence(dir_, a);
  const sensor::CameraImuSequence b = ReadCameraImuSequence(dir_);
  ASSERT_TRUE(a.ground_truth && b.ground_truth);
  const sensor::CameraImuGroundTruth& ga = *a.ground_truth;
  const sensor::CameraImuGroundTruth& gb = *b.ground_truth;

  EXPECT_EQ(ga.scene_kind, "room");
  EXPECT_EQ(ga.scene_kind, gb.scene_kind);
  EXPECT_EQ(ga.free_space_w.min(), gb.free_space_w.min());
  EXPECT_EQ(ga.free_space_w.max(), gb.free_space_w.max());
  ASSERT_EQ(ga.points_w.size(), gb.points_w.size());
  for (std::size_t i = 0; i < ga.points_w.size(); ++i) {
    EXPECT_EQ(ga.points_w[i], gb.points_w[i]);
    EXPECT_EQ(ga.point_plane_ids[i], gb.point_plane_ids[i]);
  }
  ASSERT_EQ(ga.segments_w.size(), gb.segments_w.size());
  for (std::size_t i = 0; i < ga.segments_w.size(); ++i) {
    EXPECT_EQ(ga.segments_w[i].a_w, gb.segments_w[i].a_w);
    EXPECT_EQ(ga.segments_w[i].b_w, gb.segments_w[i].b_w);
  }
  ASSERT_EQ(ga.planes_w.size(), gb.planes_w.size());
  for (std::size_t i = 0; i < ga.planes_w.size(); ++i) {
    EXPECT_EQ(ga.planes_w[i], gb.planes_w[i]);
  }
  EXPECT_EQ(a.rig.width, b.rig.width);
  EXPECT_EQ(a.rig.height, b.rig.height);
  EXPECT_EQ(a.rig.K.K(), b.rig.K.K());
  EXPECT_EQ(a.rig.T_b_c.rotation().coeffs(), b.rig.T_b_c.rotation().coeffs());
  EXPECT_EQ(a.rig.T_b_c.translation(), b.rig.T_b_c.translation());
  EXPECT_EQ(a.imu_model.rate_hz, 100.0);
  EXPECT_EQ(a.imu_model.rate_hz, b.imu_model.rate_hz);
  EXPECT_EQ(a.imu_model.gyro_noise_density, b.imu_model.gyro_noise_density);
  EXPECT_EQ(a.imu_model.accel_noise_density, b.imu_model.accel_noise_density);
  EXPECT_EQ(a.imu_model.gyro_bias_random_walk, b.imu_model.gyro_bias_random_walk);
  EXPECT_EQ(a.imu_model.accel_bias_random_walk, b.imu_model.accel_bias_random_walk);
  EXPECT_EQ(ga.initial_gyro_bias, Eigen::Vector3d(1e-3, -2e-3, 3e-4));
  EXPECT_EQ(ga.initial_gyro_bias, gb.initial_gyro_bias);
  EXPECT_EQ(ga.initial_accel_bias, gb.initial_accel_bias);
  EXPECT_EQ(a.gravity_w, b.gravity_w);
  EXPECT_EQ(a.observation_model.pixel_sigma, b.observation_model.pixel_sigma);
  EXPECT_EQ(a.observation_model.outlier_ratio, b.observation_model.outlier_ratio);
  EXPECT_EQ(a.observation_model.min_segment_px, b.observation_model.min_segment_px);
  EXPECT_EQ(a.observation_model.min_depth, b.observation_model.min_depth);
  EXPECT_EQ(a.observation_model.max_depth, b.observation_model.max_depth);
  EXPECT_EQ(a.observation_model.observe_points, b.observation_model.observe_points);
  EXPECT_EQ(a.observation_model.observe_segments, b.observation_model.observe_segments);
  EXPECT_EQ(a.frame_times, b.frame_times);
  ASSERT_EQ(ga.T_w_c.size(), gb.T_w_c.size());
  for (std::size_t i = 0; i < ga.T_w_c.size(); ++i) {
    EXPECT_EQ(ga.T_w_c[i].rotation().coeffs(), gb.T_w_c[i].rotation().coeffs());
    EXPECT_EQ(ga.T_w_c[i].translation(), gb.T_w_c[i].translation());
    EXPECT_EQ(ga.T_w_b[i].rotation().coeffs(), gb.T_w_b[i].rotation().coeffs());
    EXPECT_EQ(ga.T_w_b[i].translation(), gb.T_w_b[i].translation());
    EXPECT_EQ(ga.v_w[i], gb.v_w[i]);
  }
  ASSERT_EQ(a.imu.size(), b.imu.size());
  for (std::size_t k = 0; k < a.imu.size(); ++k) {
    EXPECT_EQ(a.imu[k].t, b.imu[k].t);
    EXPECT_EQ(a.imu[k].gyro, b.imu[k].gyro);
    EXPECT_EQ(a.imu[k].accel, b.imu[k].accel);
    EXPECT_EQ(a.imu[k].gyro_bias, b.imu[k].gyro_bias);
    EXPECT_EQ(a.imu[k].accel_bias, b.imu[k].accel_bias);
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].frame, b.points[i].frame);
    EXPECT_EQ(a.points[i].point_id, b.points[i].point_id);
    EXPECT_EQ(a.points[i].uv, b.points[i].uv);
  }
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    EXPECT_EQ(a.segments[i].frame, b.segments[i].frame);
    EXPECT_EQ(a.segments[i].line_id, b.segments[i].line_id);
    EXPECT_EQ(a.segments[i].s_px, b.segments[i].s_px);
    EXPECT_EQ(a.segments[i].e_px, b.segments[i].e_px);
  }
  EXPECT_EQ(CountOutliers(a), CountOutliers(b));

  // Writing what was read gives byte-identical files.
  const std::string dir2 = (root_ / "again").string();
  WriteCameraImuSequence(dir2, b);
  for (const std::string& name : CameraImuSequenceFileNames()) {
    EXPECT_EQ(ReadText(fs::path(dir_) / name), ReadText(fs::path(dir2) / name)) << name;
  }
}

TEST_F(SimFormatTest, TrajectoryIsPlainTum) {
  WriteCameraImuSequence(dir_, SmallSimulation());
  std::istringstream first_row(Line(fs::path(dir_) / "trajectory.txt", 3));
  int fields = 0;
  for (std::string f; first_row >> f;) ++fields;
  EXPECT_EQ(fields, 8);
}

TEST_F(SimFormatTest, TruncatedLineNamesFileAndLine) {
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "points.txt", 4, "0 3 12.5"); },
                  "points.txt:4");
}

TEST_F(SimFormatTest, TruncatedFileNamesFileAndLine) {
  ExpectReadError(
      [](const fs::path& d) {
        const std::string text = ReadText(d / "imu.txt");
        WriteText(d / "imu.txt", text.substr(0, text.size() - 9));  // cut the last row short
      },
      "imu.txt:");
}

TEST_F(SimFormatTest, FileCutAtALineBoundary) {
  ExpectReadError(
      [](const fs::path& d) {
        const std::string text = ReadText(d / "segments.txt");
        WriteText(d / "segments.txt", text.substr(0, text.rfind('\n', text.size() - 2) + 1));
      },
      "segments.txt: has ");
}

TEST_F(SimFormatTest, NonNumericField) {
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "segments.txt", 3, "0 1 abc 2 3 4"); },
                  "segments.txt:3");
}

TEST_F(SimFormatTest, NanField) {
  ExpectReadError(
      [](const fs::path& d) { ReplaceLine(d / "imu.txt", 5, "0.02 nan 0 0 0 0 9.8 0 0 0 0 0 0"); },
      "imu.txt:5");
}

TEST_F(SimFormatTest, NonUnitQuaternion) {
  ExpectReadError(
      [](const fs::path& d) { ReplaceLine(d / "trajectory.txt", 3, "0 1 2 3 0.5 0.5 0.5 0.9"); },
      "trajectory.txt:3");
}

TEST_F(SimFormatTest, IdOutOfRange) {
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "points.txt", 3, "0 99999 1 2"); },
                  "points.txt:3");
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "points.txt", 3, "500 1 1 2"); },
                  "points.txt:3");
}

TEST_F(SimFormatTest, UnknownSceneRecord) {
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "scene.txt", 5, "triangle 0 1 2"); },
                  "scene.txt:5");
}

TEST_F(SimFormatTest, MissingRigRecord) {
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "rig.txt", 3, "# gone"); },
                  "rig.txt: missing 'image'");
}

TEST_F(SimFormatTest, BodyStatesDisagreeWithTrajectory) {
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "body_states.txt", 4, "# gone"); },
                  "body_states.txt");
}

TEST_F(SimFormatTest, MissingFile) {
  ExpectReadError([](const fs::path& d) { fs::remove(d / "imu.txt"); }, "imu.txt: cannot open");
  ExpectReadError([](const fs::path& d) { fs::remove(d / "rig.txt"); }, "rig.txt: cannot open");
}

TEST_F(SimFormatTest, WriterRefusesNonFiniteValues) {
  sensor::CameraImuSequence s = SmallSimulation();
  s.ground_truth->points_w[0].x() = std::nan("");
  EXPECT_THROW(WriteCameraImuSequence(dir_, s), IoError);
  s = SmallSimulation();
  s.ground_truth->T_w_b.pop_back();
  EXPECT_THROW(WriteCameraImuSequence(dir_, s), IoError);
  s = SmallSimulation();
  s.ground_truth->scene_kind = "two words";
  EXPECT_THROW(WriteCameraImuSequence(dir_, s), IoError);
  s = SmallSimulation();
  s.frame_times.clear();
  EXPECT_THROW(WriteCameraImuSequence(dir_, s), IoError);
}

// A user's own front end: no scene, no trajectories, no bias columns; ids are any track ids.
TEST_F(SimFormatTest, RoundTripWithoutGroundTruth) {
  sensor::CameraImuSequence a = SmallSimulation();
  a.ground_truth.reset();
  ASSERT_FALSE(a.points.empty());
  a.points.back().point_id = 1000000;  // beyond any scene: a track id
  WriteCameraImuSequence(dir_, a);
  for (const char* name : {"scene.txt", "trajectory.txt", "body_states.txt"}) {
    EXPECT_FALSE(fs::exists(fs::path(dir_) / name)) << name;
  }
  const sensor::CameraImuSequence b = ReadCameraImuSequence(dir_);
  EXPECT_FALSE(b.ground_truth.has_value());
  EXPECT_EQ(b.frame_times, a.frame_times);
  ASSERT_EQ(b.imu.size(), a.imu.size());
  for (std::size_t i = 0; i < a.imu.size(); ++i) {
    EXPECT_EQ(b.imu[i].gyro, a.imu[i].gyro);
    EXPECT_EQ(b.imu[i].accel, a.imu[i].accel);
    EXPECT_EQ(b.imu[i].gyro_bias, Eigen::Vector3d::Zero());  // unknown without ground truth
  }
  ASSERT_EQ(b.points.size(), a.points.size());
  EXPECT_EQ(b.points.back().point_id, 1000000);
  EXPECT_EQ(b.segments.size(), a.segments.size());
  ExpectReadError(
      [](const fs::path& d) {
        WriteCameraImuSequence(d.string(), [] {
          sensor::CameraImuSequence s = SmallSimulation();
          s.ground_truth.reset();
          return s;
        }());
        fs::remove(d / "frames.txt");
      },
      "frames.txt: cannot open");
}

TEST_F(SimFormatTest, GroundTruthIsAllThreeFilesOrNone) {
  ExpectReadError([](const fs::path& d) { fs::remove(d / "trajectory.txt"); },
                  "trajectory.txt: missing: the ground truth is scene.txt, trajectory.txt");
  ExpectReadError([](const fs::path& d) { fs::remove(d / "scene.txt"); }, "scene.txt: missing");
}

// Folders written before frames.txt existed read as before, with trajectory.txt's times.
TEST_F(SimFormatTest, FolderWithoutFramesTxtTakesTheTrajectoryTimes) {
  const sensor::CameraImuSequence a = SmallSimulation();
  WriteCameraImuSequence(dir_, a);
  fs::remove(fs::path(dir_) / "frames.txt");
  const sensor::CameraImuSequence b = ReadCameraImuSequence(dir_);
  EXPECT_EQ(b.frame_times, a.frame_times);
  ASSERT_TRUE(b.ground_truth.has_value());
  EXPECT_EQ(b.ground_truth->T_w_c.size(), a.frame_times.size());
}

TEST_F(SimFormatTest, FramesAndTrajectoryTimesMustAgree) {
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "frames.txt", 4, "-1"); },
                  "frames.txt:4");
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "frames.txt", 3, "0.05"); },
                  "trajectory.txt:3: time differs from frames.txt row 1");
}

TEST_F(SimFormatTest, ImuBiasColumnsAllRowsOrNone) {
  ExpectReadError([](const fs::path& d) { ReplaceLine(d / "imu.txt", 5, "0.02 0 0 0 0 0 9.8"); },
                  "imu.txt:5");
}

TEST_F(SimFormatTest, SafeToWriteOnlyIntoEmptyOrPreviousOutput) {
  std::string why;
  EXPECT_TRUE(IsSafeToWriteCameraImuSequence(dir_, &why));  // does not exist
  fs::create_directories(dir_);
  EXPECT_TRUE(IsSafeToWriteCameraImuSequence(dir_, &why));  // empty
  WriteCameraImuSequence(dir_, SmallSimulation());
  EXPECT_TRUE(IsSafeToWriteCameraImuSequence(dir_, &why)) << why;  // a previous simulation
  WriteText(fs::path(dir_) / "imu.txt.tmp-plucker", "partial");    // an interrupted write
  EXPECT_TRUE(IsSafeToWriteCameraImuSequence(dir_, &why)) << why;
  WriteText(fs::path(dir_) / "notes.md", "mine");
  EXPECT_FALSE(IsSafeToWriteCameraImuSequence(dir_, &why));
  EXPECT_NE(why.find("notes.md"), std::string::npos) << why;

  const fs::path other = root_ / "user";
  fs::create_directories(other);
  WriteText(other / "points.txt", "user data");  // our file name, but no simulation header
  EXPECT_FALSE(IsSafeToWriteCameraImuSequence(other.string(), &why));
  WriteText(root_ / "file", "x");
  EXPECT_FALSE(IsSafeToWriteCameraImuSequence((root_ / "file").string(), &why));
}

}  // namespace
}  // namespace io
}  // namespace plucker
