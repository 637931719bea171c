#include "plucker/bag/point_cloud.h"

#include <gtest/gtest.h>

#include <cstring>

namespace plucker {
namespace bag {
namespace {

template <typename T>
void Put(std::vector<std::uint8_t>* data, std::size_t at, T v) {
  std::memcpy(data->data() + at, &v, sizeof(T));
}

// An Ouster-like layout: fields out of order, padding, uint32 time in ns, uint16 ring, double x.
CloudLayout Shuffled(std::uint32_t n) {
  CloudLayout layout;
  layout.point_step = 40;
  layout.width = n;
  layout.row_step = layout.point_step * n + 8;  // row padding
  layout.height = 2;
  layout.fields = {{"t", 0, 6, 1},          {"ring", 4, 4, 1}, {"z", 8, 7, 1},
                   {"intensity", 12, 2, 1}, {"x", 16, 8, 1},   {"y", 24, 7, 1}};
  return layout;
}

TEST(CloudToScan, AnyFieldOrderPointStepAndTypes) {
  const CloudLayout layout = Shuffled(3);
  std::vector<std::uint8_t> data(layout.row_step * layout.height, 0xAB);
  for (std::uint32_t r = 0; r < 2; ++r) {
    for (std::uint32_t c = 0; c < 3; ++c) {
      const std::size_t p = r * layout.row_step + c * layout.point_step;
      const std::uint32_t k = r * 3 + c;
      Put<std::uint32_t>(&data, p + 0, 1000000u * (k + 5));  // ns
      Put<std::uint16_t>(&data, p + 4, static_cast<std::uint16_t>(k));
      Put<float>(&data, p + 8, -0.5f * k);
      data[p + 12] = static_cast<std::uint8_t>(10 * k);
      Put<double>(&data, p + 16, 1.25 + k);
      Put<float>(&data, p + 24, 2.0f * k);
    }
  }
  sensor::LidarScan scan;
  CloudStats stats;
  ASSERT_EQ(CloudToScan(layout, data.data(), data.size(), &scan, &stats), "");
  ASSERT_EQ(scan.size(), 6u);
  EXPECT_EQ(stats.points, 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(scan.points[k], Eigen::Vector3d(1.25 + k, 2.0 * k, -0.5 * k)) << k;
    EXPECT_EQ(scan.intensity[k], 10.0f * k);
    EXPECT_EQ(scan.ring[k], static_cast<int>(k));
    EXPECT_NEAR(scan.time[k], 1e-3 * (k + 5), 1e-12);  // ns -> s, within [0, 1]: kept
  }
}

TEST(CloudToScan, AbsoluteTimesBecomeRelativeAndNonFiniteDropped) {
  sensor::LidarScan in;
  in.points = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
  in.time = {1600000000.25, 1600000000.0, 1600000000.05};
  CloudLayout layout = ScanLayout(in);
  std::vector<std::uint8_t> data;
  ScanToCloudData(in, layout, &data);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(data.data() + layout.point_step + 4, &nan, 4);  // point 1: y = NaN
  sensor::LidarScan scan;
  CloudStats stats;
  ASSERT_EQ(CloudToScan(layout, data.data(), data.size(), &scan, &stats), "");
  ASSERT_EQ(scan.size(), 2u);
  EXPECT_EQ(stats.non_finite_dropped, 1u);
  EXPECT_EQ(scan.timestamp, 1600000000.05);
  EXPECT_NEAR(scan.time[0], 0.2, 1e-6);
  EXPECT_EQ(scan.time[1], 0.0);
}

TEST(CloudToScan, RoundTripOfTheWriterLayout) {
  sensor::LidarScan in;
  in.points = {{1.5, -2, 3}, {0.25, 5, -6}};
  in.intensity = {7.0f, 8.0f};
  in.ring = {3, 60};
  in.time = {0.0, 0.05};
  const CloudLayout layout = ScanLayout(in);
  std::vector<std::uint8_t> data;
  ScanToCloudData(in, layout, &data);
  sensor::LidarScan out;
  ASSERT_EQ(CloudToScan(layout, data.data(), data.size(), &out), "");
  EXPECT_EQ(out.points, in.points);
  EXPECT_EQ(out.intensity, in.intensity);
  EXPECT_EQ(out.ring, in.ring);
  EXPECT_EQ(out.time, in.time);
}

TEST(CloudToScan, BadLayoutsAreNamed) {
  sensor::LidarScan in;
  in.points = {{1, 2, 3}};
  CloudLayout layout = ScanLayout(in);
  std::vector<std::uint8_t> data;
  ScanToCloudData(in, layout, &data);
  sensor::LidarScan scan;

  CloudLayout big = layout;
  big.big_endian = true;
  EXPECT_NE(CloudToScan(big, data.data(), data.size(), &scan).find("big-endian"),
            std::string::npos);

  CloudLayout no_z = layout;
  no_z.fields[2].name = "w";
  EXPECT_EQ(CloudToScan(no_z, data.data(), data.size(), &scan),
            "no x, y, z fields (fields: x, y, w)");

  EXPECT_NE(CloudToScan(layout, data.data(), data.size() - 1, &scan).find("need more"),
            std::string::npos);

  CloudLayout outside = layout;
  outside.fields[1].offset = 10;  // 10 + 4 > point_step 12
  EXPECT_NE(CloudToScan(outside, data.data(), data.size(), &scan).find("does not fit"),
            std::string::npos);

  CloudLayout bad_type = layout;
  bad_type.fields[0].datatype = 9;
  EXPECT_NE(CloudToScan(bad_type, data.data(), data.size(), &scan).find("unknown datatype 9"),
            std::string::npos);

  CloudLayout empty = layout;
  empty.width = 0;
  empty.row_step = 0;
  EXPECT_NE(CloudToScan(empty, data.data(), data.size(), &scan).find("empty"), std::string::npos);

  CloudLayout short_row = layout;
  short_row.row_step = 4;
  EXPECT_NE(CloudToScan(short_row, data.data(), data.size(), &scan).find("row_step"),
            std::string::npos);
}

}  // namespace
}  // namespace bag
}  // namespace plucker
