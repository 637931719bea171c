#include "plucker/io/pcd.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>

#include "plucker/io/io_test_utils.h"

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

LidarScan MakeScan(bool with_channels) {
  LidarScan scan;
  for (int i = 0; i < 50; ++i) {
    scan.points.emplace_back(0.5f * i, -0.25f * i, 1.0f + 0.125f * i);
    if (with_channels) {
      scan.intensity.push_back(0.01f * i);
      scan.ring.push_back(i % 16);
      scan.time.push_back(0.002 * i);
    }
  }
  return scan;
}

void ExpectSameScan(const LidarScan& a, const LidarScan& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.intensity.size(), b.intensity.size());
  ASSERT_EQ(a.ring.size(), b.ring.size());
  ASSERT_EQ(a.time.size(), b.time.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.points[i], b.points[i]);
    if (!a.intensity.empty()) {
      EXPECT_FLOAT_EQ(a.intensity[i], b.intensity[i]);
    }
    if (!a.ring.empty()) {
      EXPECT_EQ(a.ring[i], b.ring[i]);
    }
    if (!a.time.empty()) {
      EXPECT_DOUBLE_EQ(a.time[i], b.time[i]);
    }
  }
}

std::string ExpectError(const std::string& bytes, const std::string& what) {
  try {
    ParsePcd(bytes, "cloud.pcd");
    ADD_FAILURE() << "no error, expected '" << what << "'";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), "cloud.pcd");
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    return e.what();
  }
  return "";
}

// A valid LZF stream made only of literal runs (what a trivial compressor would emit).
std::string LzfLiterals(const std::string& raw) {
  std::string out;
  for (std::size_t i = 0; i < raw.size(); i += 32) {
    const std::size_t n = std::min<std::size_t>(32, raw.size() - i);
    out.push_back(static_cast<char>(n - 1));
    out.append(raw, i, n);
  }
  return out;
}

void AppendU32(std::uint32_t v, std::string* s) {
  for (int i = 0; i < 4; ++i) s->push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

const char* kHeader3 =
    "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\n";

TEST(Pcd, AsciiAndBinaryRoundTrip) {
  for (PcdEncoding enc : {PcdEncoding::kAscii, PcdEncoding::kBinary}) {
    for (bool channels : {false, true}) {
      const LidarScan scan = MakeScan(channels);
      ScanReadStats stats;
      const LidarScan back = ParsePcd(SerializePcd(scan, enc), "mem.pcd", &stats);
      ExpectSameScan(scan, back);
      EXPECT_EQ(stats.points_in_file, scan.size());
      const PcdHeader h = ParsePcdHeader(SerializePcd(scan, enc), "mem.pcd");
      EXPECT_EQ(h.has_time(), channels);
      EXPECT_EQ(h.encoding, enc);
    }
  }
}

TEST(Pcd, WriteReadFile) {
  const testing::ScratchDir scratch;
  const fs::path& dir = scratch.path();
  const LidarScan scan = MakeScan(true);
  WritePcd((dir / "a.pcd").string(), scan);
  ExpectSameScan(scan, ReadPcd((dir / "a.pcd").string()));
  EXPECT_TRUE(ReadPcdHeader((dir / "a.pcd").string()).has_time());
  EXPECT_THROW(WritePcd((dir / "b.pcd").string(), scan, PcdEncoding::kBinaryCompressed), IoError);
  EXPECT_THROW(ReadPcd((dir / "absent.pcd").string()), IoError);
}

TEST(Pcd, MixedTypesCountsAndOusterTime) {
  // double x/y/z, uint8 intensity, an ignored 3-element normal, uint16 ring, uint32 t in ns.
  std::string bytes =
      "# comment\nVERSION .7\nFIELDS x y z intensity normal ring t\nSIZE 8 8 8 1 4 2 4\n"
      "TYPE F F F U F U U\nCOUNT 1 1 1 1 3 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n";
  auto put = [&](const void* p, std::size_t n) { bytes.append(static_cast<const char*>(p), n); };
  for (int i = 0; i < 2; ++i) {
    const double xyz[3] = {1.5 + i, -2.0, 3.25};
    const std::uint8_t inten = 200;
    const float normal[3] = {0, 0, 1};
    const std::uint16_t ring = 7 + i;
    const std::uint32_t t_ns = 50000000u * i;
    put(xyz, 24), put(&inten, 1), put(normal, 12), put(&ring, 2), put(&t_ns, 4);
  }
  const LidarScan scan = ParsePcd(bytes, "ouster.pcd");
  ASSERT_EQ(scan.size(), 2u);
  EXPECT_EQ(scan.points[1], Eigen::Vector3d(2.5, -2.0, 3.25));
  EXPECT_FLOAT_EQ(scan.intensity[0], 200.0f);
  EXPECT_EQ(scan.ring[1], 8);
  EXPECT_NEAR(scan.time[1], 0.05, 1e-12);
}

TEST(Pcd, TimesRelativeToSweepEndAreShifted) {
  const std::string bytes =
      "VERSION 0.7\nFIELDS x y z time\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 3\nHEIGHT 1\n"
      "DATA ascii\n1 0 0 -0.1\n2 0 0 -0.05\n3 0 0 0\n";
  const LidarScan scan = ParsePcd(bytes, "velodyne.pcd");
  ASSERT_EQ(scan.time.size(), 3u);
  EXPECT_NEAR(scan.time[0], 0.0, 1e-7);
  EXPECT_NEAR(scan.time[2], 0.1, 1e-7);
}

TEST(Pcd, OrganisedCloudNaNsAreDroppedAndCounted) {
  const std::string bytes =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 4\n"
      "DATA ascii\n1 2 3\nnan nan nan\n4 5 6\n7 inf 8\n";
  ScanReadStats stats;
  const LidarScan scan = ParsePcd(bytes, "organised.pcd", &stats);
  EXPECT_EQ(scan.size(), 2u);
  EXPECT_EQ(stats.points_in_file, 4u);
  EXPECT_EQ(stats.non_finite_dropped, 2u);
}

TEST(Pcd, BinaryCompressed) {
  // Field-major layout: all x, then all y, then all z, then intensity.
  const float x[3] = {1, 2, 3}, y[3] = {4, 5, 6}, z[3] = {7, 8, 9}, in[3] = {0.1f, 0.2f, 0.3f};
  std::string raw;
  for (const float* f : {x, y, z, in}) raw.append(reinterpret_cast<const char*>(f), 12);
  const std::string lzf = LzfLiterals(raw);
  std::string bytes =
      "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
      "WIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA binary_compressed\n";
  AppendU32(static_cast<std::uint32_t>(lzf.size()), &bytes);
  AppendU32(static_cast<std::uint32_t>(raw.size()), &bytes);
  const LidarScan scan = ParsePcd(bytes + lzf, "c.pcd");
  ASSERT_EQ(scan.size(), 3u);
  EXPECT_EQ(scan.points[2], Eigen::Vector3d(3, 6, 9));
  EXPECT_FLOAT_EQ(scan.intensity[1], 0.2f);
  // Corrupt stream: cut the last literal short.
  ExpectError(
      bytes.substr(0, bytes.size() - 8) +
          [&] {
            std::string s;
            AppendU32(static_cast<std::uint32_t>(lzf.size() - 3), &s);
            AppendU32(static_cast<std::uint32_t>(raw.size()), &s);
            return s + lzf.substr(0, lzf.size() - 3);
          }(),
      "corrupt LZF");
  ExpectError(bytes + lzf.substr(0, 10), "truncated binary_compressed");
}

TEST(Pcd, LzfBackReference) {
  // "abc" literal, then a back reference of length 6 at offset 3: "abcabcabc".
  const unsigned char in[] = {2, 'a', 'b', 'c', (4 << 5), 2};
  std::string out;
  ASSERT_TRUE(LzfDecompress(in, sizeof(in), 9, &out));
  EXPECT_EQ(out, "abcabcabc");
  EXPECT_FALSE(LzfDecompress(in, sizeof(in), 10, &out));     // wrong size
  const unsigned char bad_offset[] = {0, 'a', (1 << 5), 5};  // refers before the start
  EXPECT_FALSE(LzfDecompress(bad_offset, sizeof(bad_offset), 4, &out));
}

TEST(Pcd, HeaderErrors) {
  ExpectError("VERSION 0.7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nHEIGHT 1\nDATA ascii\n1 2\n",
              "required field 'z' missing");
  ExpectError("VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA ascii\n",
              "SIZE has 2 entries");
  ExpectError("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\nWIDTH 1\nHEIGHT 1\nDATA ascii\n",
              "invalid TYPE");
  ExpectError("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA ascii\n",
              "invalid SIZE");
  ExpectError("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA ascii\n",
              "must have SIZE 4 or 8");
  ExpectError(
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 0\nWIDTH 1\nHEIGHT 1\n"
      "DATA ascii\n",
      "invalid COUNT");
  ExpectError(
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 3\n"
      "DATA ascii\n",
      "POINTS 3 != WIDTH*HEIGHT 2");
  ExpectError("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\n",
              "missing DATA");
  ExpectError("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA zip\n",
              "unknown data encoding");
  ExpectError("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH -1\nHEIGHT 1\nDATA ascii\n",
              "non-negative integer");
  ExpectError("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nHEIGHT 1\nDATA ascii\n",
              "missing WIDTH");
  ExpectError("hello world\n", "unknown header entry");
  ExpectError("", "missing DATA");
  ExpectError(std::string(kHeader3) + "VIEWPOINT 0 0\nDATA ascii\n", "expected 7 numbers");
  ExpectError("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 0\nHEIGHT 1\nDATA ascii\n",
              "empty point cloud");
  ExpectError(
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE I F F\nWIDTH 1\nHEIGHT 1\nDATA ascii\n"
      "1 2 3\n",
      "must be a float");
}

TEST(Pcd, DataErrors) {
  ExpectError(std::string(kHeader3) + "DATA ascii\n1 2 3\n4 5\n", "truncated ascii data");
  ExpectError(std::string(kHeader3) + "DATA ascii\n1 2 3\n4 five 6\n", "malformed number 'five'");
  ExpectError(std::string(kHeader3) + "DATA binary\n" + std::string(20, '\0'),
              "truncated binary data");
  ExpectError(std::string(kHeader3) + "DATA ascii\nnan 0 0\n0 nan 0\n", "no finite point");
  ExpectError(std::string(kHeader3) + "DATA binary_compressed\n\x01\x02",
              "truncated binary_compressed");
}

}  // namespace
}  // namespace io
}  // namespace plucker
