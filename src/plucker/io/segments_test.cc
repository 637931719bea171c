#include "plucker/io/segments.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace plucker {
namespace io {
namespace {

// Expects ParseSegments to throw an IoError whose message starts with "f.txt:<line>: " and
// contains `what`.
void ExpectError(const std::string& text, int line, const std::string& what) {
  try {
    ParseSegments(text, "f.txt");
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const IoError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("f.txt:" + std::to_string(line) + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  }
}

TEST(Segments, ParsesSegmentsCommentsAndSeparators) {
  const SegmentFile f = ParseSegments(
      "# York Urban style\n0 106 28 103\n\n  1.5,2.5,\t3.5 4.5\r\n# detection_ms 12.25\n-1e1 0 0 "
      "0\n",
      "f.txt");
  ASSERT_EQ(f.segments.size(), 3u);
  EXPECT_EQ(f.segments[0], Eigen::Vector4d(0, 106, 28, 103));
  EXPECT_EQ(f.segments[1], Eigen::Vector4d(1.5, 2.5, 3.5, 4.5));
  EXPECT_EQ(f.segments[2], Eigen::Vector4d(-10, 0, 0, 0));
  ASSERT_TRUE(f.detection_ms.has_value());
  EXPECT_DOUBLE_EQ(*f.detection_ms, 12.25);
}

TEST(Segments, EmptyFileIsAnImageWithoutLines) {
  EXPECT_TRUE(ParseSegments("", "f.txt").segments.empty());
  EXPECT_TRUE(ParseSegments("# nothing\n\n", "f.txt").segments.empty());
  EXPECT_FALSE(ParseSegments("", "f.txt").detection_ms.has_value());
}

TEST(Segments, ErrorsNameFileAndLine) {
  ExpectError("0 0 1 1\n0 0 1\n", 2, "expected 4 numbers");
  ExpectError("0 0 1 1 5\n", 1, "got 5 fields");
  ExpectError("# c\n0 0 x 1\n", 2, "field 3 is not a finite number: 'x'");
  ExpectError("0 nan 1 1\n", 1, "field 2 is not a finite number");
  ExpectError("0 0 1 inf\n", 1, "field 4 is not a finite number");
  ExpectError("0 0 1 1e7\n", 1, "beyond");
  ExpectError("1 2 3 4abc\n", 1, "'4abc'");
  ExpectError("# detection_ms fast\n", 1, "detection_ms");
  ExpectError("# detection_ms -3\n", 1, "detection_ms");
}

TEST(Segments, WriteReadRoundTrip) {
  SegmentFile f;
  f.segments = {{0.125, 1, 2.5, 3}, {639, 479, 0, 0}};
  f.detection_ms = 7.5;
  const std::string path = ::testing::TempDir() + "/plucker_segments_" +
                           std::to_string(::testing::UnitTest::GetInstance()->random_seed());
  WriteSegments(path, f, {"method test", "image x.png"});
  const SegmentFile back = ReadSegments(path);
  std::remove(path.c_str());
  ASSERT_EQ(back.segments.size(), 2u);
  for (int i = 0; i < 2; ++i) EXPECT_EQ(back.segments[i], f.segments[i]);
  EXPECT_DOUBLE_EQ(*back.detection_ms, 7.5);
  EXPECT_EQ(FormatSegments(f, {"h"}),
            "# h\n# detection_ms 7.500\n0.125 1.000 2.500 3.000\n639.000 479.000 0.000 0.000\n");
}

TEST(Segments, MissingFileIsAnError) {
  try {
    ReadSegments("/nonexistent/plucker/segs.txt");
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/plucker/segs.txt"), std::string::npos);
  }
}

}  // namespace
}  // namespace io
}  // namespace plucker
