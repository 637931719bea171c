#include "plucker/io/sim_format.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// Replaces line `line` (1-based) of a file.
void ReplaceLine(const fs::path& path, int line, const std::string& replacement) {
  std::istringstream in(ReadText(path));
  std::string out, l;
  for (int i = 1; std::getline(in, l); ++i) out += (i == line ? replacement : l) + "\n";
  WriteText(path, out);
}

std::string Line(const fs::path& path, int line) {
  std::istringstream in(ReadText(path));
  std::string l;
  for (int i = 1; i <= line; ++i) std::getline(in, l);
  return l;
}

sim::CameraSimulation SmallSimulation() {
  sim::CameraSimulationOptions o;
  o.num_frames = 12;
  o.obs.outlier_ratio = 0.1;
  o.imu.rate_hz = 100.0;
  o.imu.initial_gyro_bias = Eigen::Vector3d(1e-3, -2e-3, 3e-4);
  o.seed = 77;
  return sim::SimulateCamera(o);
}

class SimFormatTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("plucker_sim_format_" + std::string(info->name()) + "_" + std::to_string(getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    dir_ = (root_ / "sim").string();
  }
  void TearDown() override { fs::remove_all(root_); }

  // Writes a valid simulation, applies `mutate` to it and expects ReadCameraSimulation to throw
  // an IoError whose message contains `expected` (the file name and line).
  template <typename Mutate>
  void ExpectReadError(Mutate mutate, const std::string& expected) {
    WriteCameraSimulation(dir_, SmallSimulation());
    mutate(fs::path(dir_));
    try {
      ReadCameraSimulation(dir_);
      ADD_FAILURE() << "no error, expected one containing '" << expected << "'";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }

  fs::path root_;
  std::string dir_;
};

TEST_F(SimFormatTest, RoundTripIsExact) {
  const sim::CameraSimulation a = SmallSimulation();
  ASSERT_FALSE(a.imu.empty());
  ASSERT_GT(a.stats.num_point_outliers, 0);
  WriteCameraSimulation(dir_, a);
  const sim::CameraSimulation b = ReadCameraSimulation(dir_);

  EXPECT_EQ(a.scene.kind, b.scene.kind);
  EXPECT_EQ(a.scene.free_space_w.min(), b.scene.free_space_w.min());
  EXPECT_EQ(a.scene.free_space_w.max(), b.scene.free_space_w.max());
  ASSERT_EQ(a.scene.points_w.size(), b.scene.points_w.size());
  for (std::size_t i = 0; i < a.scene.points_w.size(); ++i) {
    EXPECT_EQ(a.scene.points_w[i], b.scene.points_w[i]);
    EXPECT_EQ(a.scene.point_plane_ids[i], b.scene.point_plane_ids[i]);
  }
  ASSERT_EQ(a.scene.segments_w.size(), b.scene.segments_w.size());
  for (std::size_t i = 0; i < a.scene.segments_w.size(); ++i) {
    EXPECT_EQ(a.scene.segments_w[i].a_w, b.scene.segments_w[i].a_w);
    EXPECT_EQ(a.scene.segments_w[i].b_w, b.scene.segments_w[i].b_w);
  }
  ASSERT_EQ(a.scene.planes_w.size(), b.scene.planes_w.size());
  for (std::size_t i = 0; i < a.scene.planes_w.size(); ++i) {
    EXPECT_EQ(a.scene.planes_w[i], b.scene.planes_w[i]);
  }
  EXPECT_EQ(a.rig.width, b.rig.width);
  EXPECT_EQ(a.rig.height, b.rig.height);
  EXPECT_EQ(a.rig.K.K(), b.rig.K.K());
  EXPECT_EQ(a.rig.T_b_c.rotation().coeffs(), b.rig.T_b_c.rotation().coeffs());
  EXPECT_EQ(a.rig.T_b_c.translation(), b.rig.T_b_c.translation());
  EXPECT_EQ(a.imu_options.rate_hz, b.imu_options.rate_hz);
  EXPECT_EQ(a.imu_options.gyro_noise_density, b.imu_options.gyro_noise_density);
  EXPECT_EQ(a.imu_options.accel_bias_random_walk, b.imu_options.accel_bias_random_walk);
  EXPECT_EQ(a.imu_options.initial_gyro_bias, b.imu_options.initial_gyro_bias);
  EXPECT_EQ(a.imu_options.gravity_w, b.imu_options.gravity_w);
  EXPECT_EQ(a.obs_options.pixel_sigma, b.obs_options.pixel_sigma);
  EXPECT_EQ(a.obs_options.outlier_ratio, b.obs_options.outlier_ratio);
  EXPECT_EQ(a.obs_options.max_depth, b.obs_options.max_depth);
  EXPECT_EQ(a.frame_times, b.frame_times);
  ASSERT_EQ(a.T_w_c_gt.size(), b.T_w_c_gt.size());
  for (std::size_t i = 0; i < a.T_w_c_gt.size(); ++i) {
    EXPECT_EQ(a.T_w_c_gt[i].rotation().coeffs(), b.T_w_c_gt[i].rotation().coeffs());
    EXPECT_EQ(a.T_w_c_gt[i].translation(), b.T_w_c_gt[i].translation());
    EXPECT_EQ(a.T_w_b_gt[i].rotation().coeffs(), b.T_w_b_gt[i].rotation().coeffs());
    EXPECT_EQ(a.T_w_b_gt[i].translation(), b.T_w_b_gt[i].translation());
    EXPECT_EQ(a.v_w_gt[i], b.v_w_gt[i]);
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
  EXPECT_EQ(a.stats.num_point_inliers, b.stats.num_point_inliers);
  EXPECT_EQ(a.stats.num_point_outliers, b.stats.num_point_outliers);
  EXPECT_EQ(a.stats.num_segment_inliers, b.stats.num_segment_inliers);
  EXPECT_EQ(a.stats.num_segment_outliers, b.stats.num_segment_outliers);

  // Writing what was read gives byte-identical files.
  const std::string dir2 = (root_ / "again").string();
  WriteCameraSimulation(dir2, b);
  for (const std::string& name : CameraSimulationFileNames()) {
    EXPECT_EQ(ReadText(fs::path(dir_) / name), ReadText(fs::path(dir2) / name)) << name;
  }
}

TEST_F(SimFormatTest, TrajectoryIsPlainTum) {
  WriteCameraSimulation(dir_, SmallSimulation());
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
  sim::CameraSimulation s = SmallSimulation();
  s.scene.points_w[0].x() = std::nan("");
  EXPECT_THROW(WriteCameraSimulation(dir_, s), IoError);
  s = SmallSimulation();
  s.T_w_b_gt.pop_back();
  EXPECT_THROW(WriteCameraSimulation(dir_, s), IoError);
}

TEST_F(SimFormatTest, SafeToWriteOnlyIntoEmptyOrPreviousOutput) {
  std::string why;
  EXPECT_TRUE(IsSafeToWriteCameraSimulation(dir_, &why));  // does not exist
  fs::create_directories(dir_);
  EXPECT_TRUE(IsSafeToWriteCameraSimulation(dir_, &why));  // empty
  WriteCameraSimulation(dir_, SmallSimulation());
  EXPECT_TRUE(IsSafeToWriteCameraSimulation(dir_, &why)) << why;  // a previous simulation
  WriteText(fs::path(dir_) / "imu.txt.tmp-plucker", "partial");   // an interrupted write
  EXPECT_TRUE(IsSafeToWriteCameraSimulation(dir_, &why)) << why;
  WriteText(fs::path(dir_) / "notes.md", "mine");
  EXPECT_FALSE(IsSafeToWriteCameraSimulation(dir_, &why));
  EXPECT_NE(why.find("notes.md"), std::string::npos) << why;

  const fs::path other = root_ / "user";
  fs::create_directories(other);
  WriteText(other / "points.txt", "user data");  // our file name, but no simulation header
  EXPECT_FALSE(IsSafeToWriteCameraSimulation(other.string(), &why));
  WriteText(root_ / "file", "x");
  EXPECT_FALSE(IsSafeToWriteCameraSimulation((root_ / "file").string(), &why));
}

}  // namespace
}  // namespace io
}  // namespace plucker
