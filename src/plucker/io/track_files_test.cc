#include "plucker/io/track_files.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

TEST(TrackFiles, RoundTrip) {
  const fs::path dir = fs::temp_directory_path() / ("plucker_track_files_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<sensor::SegmentObservation> segs(2);
  segs[0] = {0, 4, Eigen::Vector2d(1.25, 2.5), Eigen::Vector2d(30.125, 40)};
  segs[1] = {3, -1, Eigen::Vector2d(-1, 0), Eigen::Vector2d(5, 6)};
  WriteSegmentTracks((dir / "segments.txt").string(), segs, {"test"});
  const auto back = ReadSegmentTracks((dir / "segments.txt").string());
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back[i].frame, segs[i].frame);
    EXPECT_EQ(back[i].line_id, segs[i].line_id);
    EXPECT_EQ(back[i].s_px, segs[i].s_px);
    EXPECT_EQ(back[i].e_px, segs[i].e_px);
  }
  std::vector<sensor::PointObservation> pts = {{2, 7, Eigen::Vector2d(3.5, 4.25)}};
  WritePointTracks((dir / "points.txt").string(), pts);
  const auto pback = ReadPointTracks((dir / "points.txt").string());
  ASSERT_EQ(pback.size(), 1u);
  EXPECT_EQ(pback[0].point_id, 7);
  EXPECT_EQ(pback[0].uv, pts[0].uv);
  fs::remove_all(dir);
}

TEST(TrackFiles, ErrorsNameTheFileAndLine) {
  auto message = [](const std::string& text) {
    try {
      ParseSegmentTracks(text, "s.txt");
    } catch (const IoError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(ParseSegmentTracks("# only a comment\n\n", "s.txt").size(), 0u);
  EXPECT_NE(message("0 1 2 3 4\n").find("s.txt:1: expected 6 fields, got 5"), std::string::npos);
  EXPECT_NE(message("# c\n0 1 2 3 4 x\n").find("s.txt:2: 'x' is not a number"), std::string::npos);
  EXPECT_NE(message("0 1 2 3 4 nan\n").find("s.txt:1: non-finite"), std::string::npos);
  EXPECT_NE(message("-1 1 2 3 4 5\n").find("frame must be an integer >= 0"), std::string::npos);
  EXPECT_NE(message("0 1.5 2 3 4 5\n").find("id must be an integer >= -1"), std::string::npos);
  EXPECT_THROW(ParsePointTracks("0 1 2\n", "p.txt"), IoError);
  EXPECT_THROW(ReadSegmentTracks("/nonexistent/plucker/segments.txt"), IoError);
}

}  // namespace
}  // namespace io
}  // namespace plucker
