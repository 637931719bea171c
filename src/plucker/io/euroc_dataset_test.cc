#include "plucker/io/euroc_dataset.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>

#include "plucker/io/io_test_utils.h"

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kT0 = 1403715273262142976;  // ns, the first IMU sample
constexpr std::int64_t kImuStep = 5000000;         // 200 Hz
constexpr std::int64_t kCamStep = 50000000;        // 20 Hz

const char* kImuYaml =
    "T_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n"
    "rate_hz: 200\ngyroscope_noise_density: 1.6968e-04\ngyroscope_random_walk: 1.9393e-05\n"
    "accelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\n";
const char* kCamYaml =
    "T_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, 0.1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n"
    "rate_hz: 20\nresolution: [752, 480]\ncamera_model: pinhole\n"
    "intrinsics: [458.654, 457.296, 367.215, 248.375]\ndistortion_model: radial-tangential\n"
    "distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n";

void Write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

// A EuRoC folder: 1 s of IMU at 200 Hz without the samples in `imu_gap` (ns after kT0), and
// camera rows (timestamp ns, file) whose image files exist unless named "absent*" (or absolute).
struct FakeEuroc {
  explicit FakeEuroc(const fs::path& root) : mav0(root / "mav0") {}
  void Build(const std::vector<std::pair<std::int64_t, std::string>>& rows,
             std::pair<std::int64_t, std::int64_t> imu_gap = {-1, -1}) const {
    std::string imu = "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n";
    for (std::int64_t dt = 0; dt <= 1000000000; dt += kImuStep) {
      if (dt > imu_gap.first && dt < imu_gap.second) continue;
      imu += std::to_string(kT0 + dt) + ",0.01,0.02,0.03,0.1,0.2,9.8\n";
    }
    Write(mav0 / "imu0/data.csv", imu);
    Write(mav0 / "imu0/sensor.yaml", kImuYaml);
    Write(mav0 / "cam0/sensor.yaml", kCamYaml);
    std::string cam = "#timestamp [ns],filename\n";
    for (const auto& [ns, file] : rows) {
      cam += std::to_string(ns) + "," + file + "\n";
      if (file.rfind("absent", 0) != 0 && !fs::path(file).is_absolute()) {
        Write(mav0 / "cam0/data" / file, "png");
      }
    }
    Write(mav0 / "cam0/data.csv", cam);
  }
  fs::path mav0;
};

std::vector<std::pair<std::int64_t, std::string>> Rows(int n, std::int64_t first_ns) {
  std::vector<std::pair<std::int64_t, std::string>> rows;
  for (int i = 0; i < n; ++i) rows.push_back({first_ns + i * kCamStep, std::to_string(i) + ".png"});
  return rows;
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const IoError& e) {
    return e.what();
  }
  return "(no error)";
}

bool AnyContains(const std::vector<std::string>& v, const std::string& text) {
  for (const std::string& s : v) {
    if (s.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(EurocDataset, CleanFolderKeepsEveryFrameOnTheImuClock) {
  const testing::ScratchDir dir;
  FakeEuroc(dir.path()).Build(Rows(10, kT0 + 100000000));
  const EurocDataset d = ReadEurocDataset(dir.path().string());
  ASSERT_EQ(d.frames.size(), 10u);
  EXPECT_TRUE(d.skipped.empty());
  EXPECT_TRUE(d.warnings.empty());
  EXPECT_NEAR(d.frames[0].t, 0.1, 1e-12);  // seconds after the first IMU sample
  EXPECT_NEAR(d.frames[9].t - d.frames[0].t, 0.45, 1e-12);
  EXPECT_EQ(fs::path(d.frames[3].image).filename(), "3.png");
  EXPECT_EQ(d.frames[3].line, 5);  // header + 3 rows before it
  EXPECT_EQ(d.cam0.camera.width, 752);
  EXPECT_DOUBLE_EQ(d.cam0.T_b_c.translation().x(), 0.1);
}

TEST(EurocDataset, UnusableFramesAreSkippedWithTheirRowAndReason) {
  const testing::ScratchDir dir;
  auto rows = Rows(12, kT0 + 100000000);
  rows[3].first = rows[2].first;                             // duplicated timestamp
  rows[6].first = rows[4].first - 1;                         // goes back
  rows[8].second = "absent.png";                             // dropped file
  rows[10].second = "/etc/hostname";                         // exists, but outside the image folder
  rows.insert(rows.begin(), {kT0 - 20000000, "early.png"});  // before the IMU starts
  FakeEuroc(dir.path()).Build(rows);
  const EurocDataset d = ReadEurocDataset(dir.path().string());
  EXPECT_EQ(d.frames.size(), 8u);
  const std::vector<std::string> skipped = ToStrings(d.skipped);
  ASSERT_EQ(skipped.size(), 5u) << ::testing::PrintToString(skipped);
  for (const FrameSkip& s : d.skipped) {  // structured: the file, its row, the reason
    EXPECT_NE(s.file.find("cam0/data.csv"), std::string::npos);
    EXPECT_GT(s.line, 1);
    EXPECT_FALSE(s.reason.empty());
    EXPECT_EQ(s.reason.find("data.csv"), std::string::npos) << s.reason;
  }
  EXPECT_TRUE(AnyContains(skipped, "data.csv:13: '/etc/hostname' is not a file name inside"));
  EXPECT_TRUE(AnyContains(skipped, "data.csv:6: duplicated timestamp")) << skipped[0];
  EXPECT_TRUE(AnyContains(skipped, "data.csv:9: timestamp goes back"));
  EXPECT_TRUE(AnyContains(skipped, "data.csv:11: image file missing"));
  EXPECT_TRUE(AnyContains(skipped, "data.csv:2: no IMU coverage (before the first IMU sample)"));
  for (std::size_t i = 1; i < d.frames.size(); ++i) EXPECT_GT(d.frames[i].t, d.frames[i - 1].t);
}

TEST(EurocDataset, ImuGapsAndDroppedImagesAreReported) {
  const testing::ScratchDir dir;
  auto rows = Rows(16, kT0 + 100000000);
  rows.erase(rows.begin() + 12, rows.begin() + 14);  // two images dropped
  // IMU samples missing from 0.30 to 0.42 s: the frame at 0.35 s and the one at 0.40 s fall in.
  FakeEuroc(dir.path()).Build(rows, {300000000, 420000000});
  const EurocDataset d = ReadEurocDataset(dir.path().string());
  EXPECT_EQ(d.frames.size(), 12u);
  EXPECT_EQ(d.skipped.size(), 2u);
  EXPECT_TRUE(AnyContains(ToStrings(d.skipped), "inside a gap of 0.120 s"));
  EXPECT_TRUE(AnyContains(d.warnings, "imu0/data.csv: a gap of 0.120 s"));
  EXPECT_TRUE(AnyContains(d.warnings, "about 2 image(s) dropped"));
}

TEST(EurocDataset, WhatCannotBeUsedIsAnError) {
  const testing::ScratchDir dir;
  const FakeEuroc euroc(dir.path());
  euroc.Build(Rows(5, kT0 + 5000000000));  // 5 s after the IMU's only second
  EXPECT_NE(ErrorOf([&] { ReadEurocDataset(dir.path().string()); }).find("do not overlap"),
            std::string::npos);
  euroc.Build(Rows(5, kT0));
  Write(euroc.mav0 / "cam0/data.csv", "#t,f\n1403715273262142976,0.png\nnot a row\n");
  EXPECT_NE(ErrorOf([&] { ReadEurocDataset(dir.path().string()); }).find("data.csv:3: expected 2"),
            std::string::npos);
  Write(euroc.mav0 / "cam0/data.csv", "#t,f\n");
  EXPECT_NE(ErrorOf([&] { ReadEurocDataset(dir.path().string()); }).find("empty file"),
            std::string::npos);
  Write(euroc.mav0 / "cam0/data.csv", "#t,f\n1403715273262142976,absent.png\n");
  EXPECT_NE(ErrorOf([&] { ReadEurocDataset(dir.path().string()); }).find("no usable frame"),
            std::string::npos);
  euroc.Build(Rows(5, kT0));
  Write(euroc.mav0 / "cam0/sensor.yaml", "rate_hz: 20\n");  // intrinsics and the rest missing
  EXPECT_NE(ErrorOf([&] { ReadEurocDataset(dir.path().string()); }).find("sensor.yaml"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { ReadEurocDataset((dir.path() / "nope").string()); }).find("not a EuRoC"),
            std::string::npos);
}

TEST(EurocDataset, RealV101HeadIsCoveredFrameByFrame) {
  const fs::path root = fs::path(PLUCKER_SHARED_DATA_DIR) / "euroc-v101-head";
  if (!fs::exists(root)) GTEST_SKIP() << "no " << root << " (../shared/data): skipped";
  const EurocDataset d = ReadEurocDataset(root.string());
  EXPECT_EQ(d.frames.size(), 95u);
  EXPECT_TRUE(d.skipped.empty()) << d.skipped.front().ToString();
  EXPECT_TRUE(d.warnings.empty()) << d.warnings.front();
  EXPECT_GE(d.frames.front().t, d.imu.imu.front().t);  // the first image is at the first sample
  EXPECT_NEAR(d.frames[1].t - d.frames[0].t, 0.05, 1e-3);
}

}  // namespace
}  // namespace io
}  // namespace plucker
