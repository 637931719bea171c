// Runs the libFuzzer entry points of io/*_fuzz.cc as an ordinary test: every seed, then a few
// thousand seeded random mutations of them (stacked up to 4 deep). Under the sanitizer build
// this catches crashes, leaks and undefined behaviour without clang's libFuzzer.
#include <gtest/gtest.h>

#include <random>

#include "euroc_fuzz.cc"      // NOLINT(build/include): the fuzz targets are not in the library
#include "kalibr_fuzz.cc"     // NOLINT(build/include)
#include "kitti_bin_fuzz.cc"  // NOLINT(build/include)
#include "pcd_fuzz.cc"        // NOLINT(build/include)
#include "png_gray_fuzz.cc"   // NOLINT(build/include)
#include "pose_fuzz.cc"       // NOLINT(build/include)
#include "segments_fuzz.cc"   // NOLINT(build/include)

namespace plucker {
namespace io {
namespace fuzz {
namespace {

using Entry = int (*)(const std::uint8_t*, std::size_t);

void RunCorpus(Entry entry, const std::vector<std::string>& seeds, int mutations,
               std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (const std::string& s : seeds) {
    ASSERT_EQ(entry(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()), 0);
  }
  for (int k = 0; k < mutations; ++k) {
    std::string s = seeds[rng() % seeds.size()];
    const int depth = 1 + static_cast<int>(rng() % 4);
    for (int d = 0; d < depth; ++d) s = Mutate(s, rng);
    ASSERT_EQ(entry(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()), 0);
  }
  const std::string empty;
  entry(reinterpret_cast<const std::uint8_t*>(empty.data()), 0);
}

TEST(FuzzTargets, SeedsParse) {
  // The seeds are valid inputs: each parses without error in its own format.
  EXPECT_EQ(ParseKittiBin(KittiBinSeeds()[0], "seed").size(), 3u);
  EXPECT_TRUE(ParseKittiCalibTr(KittiBinSeeds()[1], "seed").has_value());
  const std::vector<std::string> pcd = PcdSeeds();
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NO_THROW(ParsePcd(pcd[i], "seed")) << i;
  for (std::size_t i = 4; i < 6; ++i) EXPECT_NO_THROW(ParsePly(pcd[i], "seed")) << i;
  for (const std::string& s : PoseSeeds()) {
    EXPECT_EQ(ParseTrajectory(s, "seed", TrajectoryFormat::kAuto).poses.size(), 2u);
  }
}

TEST(FuzzTargets, PngGray) {
  for (const std::string& s : PngGraySeeds()) {
    const auto* d = reinterpret_cast<const std::uint8_t*>(s.data());
    EXPECT_EQ(DecodeGrayPng(d, s.size()).has_value(), HasFastGrayPng());
  }
  RunCorpus(&PngGrayOneInput, PngGraySeeds(), 3000, 7);
}

TEST(FuzzTargets, Kalibr) {
  const std::vector<std::string> seeds = KalibrSeeds();
  EXPECT_EQ(ParseKalibrCameraChain(seeds[0], "seed").cameras.size(), 2u);
  EXPECT_EQ(ParseKalibrImu(seeds[1], "seed").rate_hz, 200.0);
  RunCorpus(&KalibrOneInput, seeds, 600, 6);  // YAML parses are slow under ASan
}

TEST(FuzzTargets, KittiBin) { RunCorpus(&KittiBinOneInput, KittiBinSeeds(), 4000, 1); }
TEST(FuzzTargets, Pcd) { RunCorpus(&PcdOneInput, PcdSeeds(), 4000, 2); }
TEST(FuzzTargets, Pose) { RunCorpus(&PoseOneInput, PoseSeeds(), 3000, 3); }
TEST(FuzzTargets, Euroc) {
  const std::vector<std::string> seeds = EurocSeeds();
  EXPECT_EQ(ParseEurocImuCsv(seeds[0], "seed", 0).size(), 2u);
  EXPECT_EQ(ParseEurocGroundTruthCsv(seeds[1], "seed", 0).size(), 1u);
  EXPECT_EQ(ParseEurocImuYaml(seeds[2], "seed").rate_hz, 200.0);
  RunCorpus(&EurocOneInput, seeds, 3000, 4);
}
TEST(FuzzTargets, Segments) {
  EXPECT_EQ(ParseSegments(SegmentSeeds()[0], "seed").segments.size(), 3u);
  EXPECT_EQ(ParseSegments(SegmentSeeds()[1], "seed").segments.size(), 1u);
  RunCorpus(&SegmentOneInput, SegmentSeeds(), 3000, 4);
}

}  // namespace
}  // namespace fuzz
}  // namespace io
}  // namespace plucker
