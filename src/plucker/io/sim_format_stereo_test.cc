// The second camera of a stereo rig in the sim format (docs/sim-format.md): T_c0_c1 and
// cam1_counts in rig.txt, cam1_points.txt and cam1_segments.txt; exact round trip, the files
// removed when a mono sequence overwrites a stereo one, errors naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "plucker/io/io_test_utils.h"
#include "plucker/io/sim_format.h"
#include "plucker/sim/camera_observations.h"

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

using testing::ReadText;

sensor::CameraImuSequence StereoSimulation(bool stereo) {
  sim::CameraSimulationOptions o;
  o.num_frames = 8;
  o.obs.outlier_ratio = 0.1;
  o.imu.model.rate_hz = 100.0;
  o.seed = 5;
  if (stereo) o.T_c0_c1 = sim::StereoPose(0.11);
  return sim::ToCameraImuSequence(sim::SimulateCamera(o));
}

std::string ErrorOf(const std::string& dir) {
  try {
    ReadCameraImuSequence(dir);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(SimFormatStereo, RoundTripIsExact) {
  const testing::ScratchDir scratch;
  const std::string dir = (scratch / "a").string(), dir2 = (scratch / "b").string();
  const sensor::CameraImuSequence a = StereoSimulation(true);
  ASSERT_TRUE(a.cam1);
  ASSERT_FALSE(a.cam1->points.empty());
  ASSERT_FALSE(a.cam1->segments.empty());
  WriteCameraImuSequence(dir, a);
  const sensor::CameraImuSequence b = ReadCameraImuSequence(dir);
  ASSERT_TRUE(b.cam1);
  EXPECT_EQ(b.cam1->T_c0_c1.translation(), a.cam1->T_c0_c1.translation());
  EXPECT_EQ(b.cam1->T_c0_c1.rotation().coeffs(), a.cam1->T_c0_c1.rotation().coeffs());
  ASSERT_EQ(b.cam1->points.size(), a.cam1->points.size());
  for (std::size_t i = 0; i < a.cam1->points.size(); ++i) {
    EXPECT_EQ(b.cam1->points[i].frame, a.cam1->points[i].frame);
    EXPECT_EQ(b.cam1->points[i].point_id, a.cam1->points[i].point_id);
    EXPECT_EQ(b.cam1->points[i].uv, a.cam1->points[i].uv);
  }
  ASSERT_EQ(b.cam1->segments.size(), a.cam1->segments.size());
  for (std::size_t i = 0; i < a.cam1->segments.size(); ++i) {
    EXPECT_EQ(b.cam1->segments[i].line_id, a.cam1->segments[i].line_id);
    EXPECT_EQ(b.cam1->segments[i].s_px, a.cam1->segments[i].s_px);
    EXPECT_EQ(b.cam1->segments[i].e_px, a.cam1->segments[i].e_px);
  }
  EXPECT_EQ(b.points.size(), a.points.size());  // cam0's unchanged
  WriteCameraImuSequence(dir2, b);
  for (const std::string& name : CameraImuSequenceFileNames())
    EXPECT_EQ(ReadText(fs::path(dir) / name), ReadText(fs::path(dir2) / name)) << name;
}

TEST(SimFormatStereo, MonoOutputHasNoSecondCameraAndRemovesOne) {
  const testing::ScratchDir scratch;
  const std::string dir = (scratch / "a").string();
  WriteCameraImuSequence(dir, StereoSimulation(true));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "cam1_points.txt"));
  std::string why;
  EXPECT_TRUE(IsSafeToWriteCameraImuSequence(dir, &why)) << why;
  const sensor::CameraImuSequence mono = StereoSimulation(false);
  EXPECT_FALSE(mono.cam1);
  WriteCameraImuSequence(dir, mono);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "cam1_points.txt"));
  EXPECT_FALSE(fs::exists(fs::path(dir) / "cam1_segments.txt"));
  EXPECT_EQ(ReadText(fs::path(dir) / "rig.txt").find("T_c0_c1"), std::string::npos);
  EXPECT_FALSE(ReadCameraImuSequence(dir).cam1);
}

TEST(SimFormatStereo, ErrorsNameTheFile) {
  const testing::ScratchDir scratch;
  const std::string dir = (scratch / "a").string();
  WriteCameraImuSequence(dir, StereoSimulation(true));
  fs::remove(fs::path(dir) / "cam1_segments.txt");
  EXPECT_NE(ErrorOf(dir).find("cam1_segments.txt"), std::string::npos) << ErrorOf(dir);

  WriteCameraImuSequence(dir, StereoSimulation(true));
  {
    std::ofstream out(fs::path(dir) / "cam1_points.txt", std::ios::app);
    out << "0 1 10 10\n";  // one row more than cam1_counts announces
  }
  EXPECT_NE(ErrorOf(dir).find("cam1_points.txt"), std::string::npos) << ErrorOf(dir);

  WriteCameraImuSequence(dir, StereoSimulation(true));
  std::string rig = ReadText(fs::path(dir) / "rig.txt");
  rig.erase(rig.find("cam1_counts"));
  std::ofstream(fs::path(dir) / "rig.txt", std::ios::binary | std::ios::trunc) << rig;
  const std::string e = ErrorOf(dir);
  EXPECT_NE(e.find("rig.txt"), std::string::npos) << e;
  EXPECT_NE(e.find("cam1_counts"), std::string::npos) << e;
}

}  // namespace
}  // namespace io
}  // namespace plucker
