#include "plucker/io/ply.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "plucker/io/io_test_utils.h"

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

std::vector<Eigen::Vector3d> Points() {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 100; ++i) p.emplace_back(0.5 * i, -0.25 * i, 3.0 - 0.125 * i);
  return p;
}

void ExpectError(const std::string& bytes, const std::string& what) {
  try {
    ParsePly(bytes, "map.ply");
    ADD_FAILURE() << "no error, expected '" << what << "'";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), "map.ply");
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(Ply, RoundTripBothFormats) {
  const testing::ScratchDir scratch;
  const fs::path& dir = scratch.path();
  const std::vector<Eigen::Vector3d> pts = Points();
  std::vector<float> intensity;
  for (std::size_t i = 0; i < pts.size(); ++i) intensity.push_back(0.01f * i);
  for (PlyFormat f : {PlyFormat::kBinaryLittleEndian, PlyFormat::kAscii}) {
    for (bool with_i : {false, true}) {
      const std::string path = (dir / "m.ply").string();
      WritePly(path, pts, with_i ? intensity : std::vector<float>{}, f);
      const LidarScan back = ReadPly(path);
      ASSERT_EQ(back.size(), pts.size());
      EXPECT_EQ(back.intensity.size(), with_i ? pts.size() : 0u);
      for (std::size_t i = 0; i < pts.size(); ++i) {
        EXPECT_EQ(back.points[i], pts[i]);
        if (with_i) {
          EXPECT_FLOAT_EQ(back.intensity[i], intensity[i]);
        }
      }
    }
  }
  EXPECT_EQ(fs::file_size(dir / "m.ply") > 0, true);
  EXPECT_THROW(WritePly((dir / "bad.ply").string(), pts, std::vector<float>(3)), IoError);
}

TEST(Ply, ReadsOtherPropertiesAndTrailingElements) {
  const std::string bytes =
      "ply\nformat ascii 1.0\ncomment x\nelement vertex 2\nproperty double x\nproperty uchar red\n"
      "property double y\nproperty double z\nelement face 1\nproperty list uchar int "
      "vertex_indices\n"
      "end_header\n1 255 2 3\n4 0 5 nan\n3 0 1 2\n";
  ScanReadStats stats;
  const LidarScan cloud = ParsePly(bytes, "m.ply", &stats);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_EQ(cloud.points[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(stats.non_finite_dropped, 1u);
}

TEST(Ply, SegmentsAsVertexPairsAndEdges) {
  testing::ScratchDir dir;
  const std::string path = (dir / "lines.ply").string();
  WriteSegmentsPly(path, {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 2, 3)},
                          {Eigen::Vector3d(-1, 0.5, 2), Eigen::Vector3d(4, 5, 6)}});
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string t = text.str();
  EXPECT_NE(t.find("element vertex 4\n"), std::string::npos) << t;
  EXPECT_NE(t.find("element edge 2\n"), std::string::npos) << t;
  EXPECT_NE(t.find("end_header\n0 0 0\n1 2 3\n-1 0.5 2\n4 5 6\n0 1\n2 3\n"), std::string::npos)
      << t;
  // The vertices read back with the point reader (the edge element after them is ignored).
  EXPECT_EQ(ReadPly(path).points.size(), 4u);
}

TEST(Ply, Errors) {
  ExpectError("plx\n", "no 'ply' magic");
  ExpectError("ply\nformat binary_big_endian 1.0\nelement vertex 1\nend_header\n", "big_endian");
  ExpectError(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "end_header\n1 2\n",
      "lacks x, y or z");
  ExpectError(
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1 2 3\n",
      "truncated ascii");
  ExpectError(
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n" +
          std::string(12, '\0'),
      "truncated binary");
  ExpectError(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\n",
      "missing end_header");
  ExpectError(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1 b 3\n",
      "malformed number");
  ExpectError("ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar int x\nend_header\n",
              "list property");
  ExpectError(
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n",
      "empty point cloud");
}

}  // namespace
}  // namespace io
}  // namespace plucker
