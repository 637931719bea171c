#include "plucker/io/camera_calibration.h"
#include "plucker/io/fuzz_util.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;

const std::string kData = PLUCKER_SHARED_DATA_DIR;

std::string Write(const std::string& name, const std::string& text) {
  const fs::path dir =
      fs::temp_directory_path() / ("plucker_camera_calibration_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

// True when the pieces of `pattern` between ".*" occur in `text` in that order.
bool Matches(const std::string& text, const std::string& pattern) {
  std::size_t at = 0, from = 0;
  while (true) {
    const std::size_t wildcard = pattern.find(".*", from);
    const std::string piece =
        pattern.substr(from, wildcard == std::string::npos ? std::string::npos : wildcard - from);
    at = text.find(piece, at);
    if (at == std::string::npos) return false;
    at += piece.size();
    if (wildcard == std::string::npos) return true;
    from = wildcard + 2;
  }
}

// The text with the first `from` replaced by `to`.
std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Runs `read`, expects IoError, and checks that the message names the file and matches `problem`
// (".*" matches anything).
template <typename F>
void ExpectError(F read, const std::string& path, const std::string& problem) {
  try {
    read();
    ADD_FAILURE() << "no error for " << path << " (expected '" << problem << "')";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_TRUE(Matches(e.problem(), problem))
        << "'" << e.what() << "' does not match '" << problem << "'";
  }
}

const char* kKittiCalib =
    "P0: 7.070912000000e+02 0 6.018873000000e+02 0 0 7.070912000000e+02 1.831104000000e+02 0 0 0 "
    "1 0\n"
    "P1: 7.070912000000e+02 0 6.018873000000e+02 -3.798145000000e+02 0 7.070912000000e+02 "
    "1.831104000000e+02 0 0 0 1 0\n";

TEST(KittiCalibration, ReadsP0AndP1) {
  const std::string path = Write("calib.txt", kKittiCalib);
  const KittiCalibration c = ReadKittiCalibration(path, 1226, 370);
  EXPECT_DOUBLE_EQ(c.camera.K.fx, 707.0912);
  EXPECT_DOUBLE_EQ(c.camera.K.fy, 707.0912);
  EXPECT_DOUBLE_EQ(c.camera.K.cx, 601.8873);
  EXPECT_DOUBLE_EQ(c.camera.K.cy, 183.1104);
  EXPECT_TRUE(c.camera.IsPinhole());
  EXPECT_EQ(c.camera.width, 1226);
  EXPECT_EQ(c.camera.height, 370);
  const KittiCalibration c1 = ReadKittiCalibration(path, 1226, 370, "P1");
  EXPECT_NEAR(-c1.P(0, 3) / c1.camera.K.fx, 0.537, 1e-3);  // stereo baseline [m]
}

TEST(KittiCalibration, BadInput) {
  const std::string ok = Write("ok.txt", kKittiCalib);
  ExpectError([&] { ReadKittiCalibration(ok, 1226, 370, "P2"); }, ok, "no 'P2:' line");
  ExpectError([&] { ReadKittiCalibration(ok, 0, 370); }, ok, "image size 0x370");
  const std::string missing = Write("x", "") + "_missing";
  ExpectError([&] { ReadKittiCalibration(missing, 10, 10); }, missing, "cannot open");
  const std::string short_line = Write("short.txt", "P0: 1 0 2 0 0 1 2 0 0 0 1\n");
  ExpectError([&] { ReadKittiCalibration(short_line, 10, 10); }, short_line,
              "expected 12 numbers, found 11");
  const std::string text = Write("text.txt", "P0: 1 0 2 0 0 abc 2 0 0 0 1 0\n");
  ExpectError([&] { ReadKittiCalibration(text, 10, 10); }, text, "value 6 is not a number: 'abc'");
  const std::string nan = Write("nan.txt", "P0: nan 0 2 0 0 1 2 0 0 0 1 0\n");
  ExpectError([&] { ReadKittiCalibration(nan, 10, 10); }, nan, "value 1 is not finite");
  const std::string zero_f = Write("zero_f.txt", "P0: 0 0 2 0 0 1 2 0 0 0 1 0\n");
  ExpectError([&] { ReadKittiCalibration(zero_f, 10, 10); }, zero_f, "non-positive focal length");
  const std::string negative_f = Write("neg_f.txt", "P0: 5 0 2 0 0 -1 2 0 0 0 1 0\n");
  ExpectError([&] { ReadKittiCalibration(negative_f, 10, 10); }, negative_f,
              "non-positive focal length");
  const std::string skew = Write("skew.txt", "P0: 5 0.5 2 0 0 5 2 0 0 0 1 0\n");
  ExpectError([&] { ReadKittiCalibration(skew, 10, 10); }, skew, "non-zero skew");
  const std::string row = Write("row.txt", "P0: 5 0 2 0 0 5 2 0 0 0 2 0\n");
  ExpectError([&] { ReadKittiCalibration(row, 10, 10); }, row, "last row");
}

TEST(KittiCalibration, RealClip) {
  const std::string path = kData + "/kitti-mono-clip/calib.txt";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data absent: " << path;
  const KittiCalibration c = ReadKittiCalibration(path, 1226, 370);
  EXPECT_DOUBLE_EQ(c.camera.K.fx, 707.0912);
  EXPECT_DOUBLE_EQ(c.camera.K.cy, 183.1104);
}

TEST(StrechaCalibration, IntrinsicsAndBadInput) {
  const std::string k = Write("K.txt", "2759.48 0 1520.69\n0 2764.16 1006.81\n0 0 1\n");
  const sensor::Camera c = ReadStrechaIntrinsics(k, 3072, 2048);
  EXPECT_DOUBLE_EQ(c.K.fx, 2759.48);
  EXPECT_DOUBLE_EQ(c.K.fy, 2764.16);
  EXPECT_DOUBLE_EQ(c.K.cx, 1520.69);
  EXPECT_DOUBLE_EQ(c.K.cy, 1006.81);
  const std::string eight = Write("K8.txt", "2759.48 0 1520.69\n0 2764.16 1006.81\n0 0\n");
  ExpectError([&] { ReadStrechaIntrinsics(eight, 10, 10); }, eight, "expected 9 numbers, found 8");
  const std::string neg = Write("Kneg.txt", "-2759.48 0 1520.69\n0 2764.16 1006.81\n0 0 1\n");
  ExpectError([&] { ReadStrechaIntrinsics(neg, 10, 10); }, neg, "non-positive focal length");
  const std::string word = Write("Kword.txt", "2759.48 0 1520.69\n0 f 1006.81\n0 0 1\n");
  ExpectError([&] { ReadStrechaIntrinsics(word, 10, 10); }, word, "not a number: 'f'");
}

const char* kStrechaCamera =
    "2759.48 0 1520.69\n0 2764.16 1006.81\n0 0 1\n0 0 0\n"
    "0.450927 -0.0945642 -0.887537\n-0.892535 -0.0401974 -0.449183\n"
    "0.00679989 0.994707 -0.102528\n-7.28137 -7.57667 0.204446\n3072 2048\n";

TEST(StrechaCalibration, CameraFile) {
  const std::string path = Write("0000.jpg.camera", kStrechaCamera);
  const StrechaCamera s = ReadStrechaCamera(path);
  EXPECT_EQ(s.camera.width, 3072);
  EXPECT_EQ(s.camera.height, 2048);
  EXPECT_TRUE(s.camera.IsPinhole());
  // T_w_c = [R | C]: the translation is the camera centre, the first column of R the camera's x
  // axis in the world.
  EXPECT_LT((s.T_w_c.translation() - Eigen::Vector3d(-7.28137, -7.57667, 0.204446)).norm(), 1e-12);
  EXPECT_LT(
      (s.T_w_c.RotationMatrix().col(0) - Eigen::Vector3d(0.450927, -0.892535, 0.00679989)).norm(),
      1e-5);
}

TEST(StrechaCalibration, CameraFileBadInput) {
  std::string text = kStrechaCamera;
  const std::string no_size = Write("nosize.camera", text.substr(0, text.rfind("3072")));
  ExpectError([&] { ReadStrechaCamera(no_size); }, no_size, "expected 26 numbers, found 24");
  const std::string bad_r = Write("badr.camera", Replace(text, "0.450927", "0.9"));
  ExpectError([&] { ReadStrechaCamera(bad_r); }, bad_r, "R is not a rotation");
  const std::string bad_w = Write("badw.camera", Replace(text, "3072", "30.5"));
  ExpectError([&] { ReadStrechaCamera(bad_w); }, bad_w, "width = 30.5 is not a positive integer");
  const std::string zero_f = Write("zerof.camera", Replace(text, "2759.48", "0"));
  ExpectError([&] { ReadStrechaCamera(zero_f); }, zero_f, "non-positive focal length");
  const std::string dir = fs::path(no_size).parent_path().string();
  ExpectError([&] { ReadStrechaCamera(dir); }, dir, "is a folder");
  const std::string empty_dir = dir + "/empty";
  fs::create_directories(empty_dir);
  ExpectError([&] { ListStrechaCameraFiles(empty_dir); }, empty_dir, "no *.camera files");
  ExpectError([&] { ListStrechaCameraFiles(empty_dir + "/nope"); }, empty_dir + "/nope",
              "not a folder");
}

TEST(StrechaCalibration, RealFountain) {
  const std::string dir = kData + "/strecha-fountain-p11/cameras";
  if (!fs::exists(dir)) GTEST_SKIP() << "shared data absent: " << dir;
  const std::vector<std::string> files = ListStrechaCameraFiles(dir);
  ASSERT_EQ(files.size(), 11u);
  EXPECT_EQ(fs::path(files.front()).filename(), "0000.jpg.camera");
  const sensor::Camera K =
      ReadStrechaIntrinsics(kData + "/strecha-fountain-p11/images/K.txt", 3072, 2048);
  for (const std::string& f : files) {
    const StrechaCamera s = ReadStrechaCamera(f);
    EXPECT_DOUBLE_EQ(s.camera.K.fx, K.K.fx) << f;
    EXPECT_DOUBLE_EQ(s.camera.K.cy, K.K.cy) << f;
    EXPECT_EQ(s.camera.width, 3072) << f;
  }
  // The cameras stand a few metres apart (the centres are in metres).
  const double baseline = (ReadStrechaCamera(files[0]).T_w_c.translation() -
                           ReadStrechaCamera(files[10]).T_w_c.translation())
                              .norm();
  EXPECT_GT(baseline, 1.0);
  EXPECT_LT(baseline, 30.0);
}

const char* kEurocYaml = R"(%YAML:1.0
sensor_type: camera
comment: VI-Sensor cam0 (MT9M034)
T_BS:
  cols: 4
  rows: 4
  data: [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
         0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,
        -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,
         0.0, 0.0, 0.0, 1.0]
rate_hz: 20
resolution: [752, 480]
camera_model: pinhole
intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv
distortion_model: radial-tangential
distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
)";

void CheckEurocCam0(const EurocCamera& e) {
  EXPECT_DOUBLE_EQ(e.camera.K.fx, 458.654);
  EXPECT_DOUBLE_EQ(e.camera.K.fy, 457.296);
  EXPECT_DOUBLE_EQ(e.camera.K.cx, 367.215);
  EXPECT_DOUBLE_EQ(e.camera.K.cy, 248.375);
  EXPECT_DOUBLE_EQ(e.camera.distortion.k1, -0.28340811);
  EXPECT_DOUBLE_EQ(e.camera.distortion.p2, 1.76187114e-05);
  EXPECT_EQ(e.camera.distortion.k3, 0.0);
  EXPECT_EQ(e.camera.width, 752);
  EXPECT_EQ(e.camera.height, 480);
  EXPECT_EQ(e.rate_hz, 20.0);
  EXPECT_LT(
      (e.T_b_c.translation() - Eigen::Vector3d(-0.0216401454975, -0.064676986768, 0.00981073058949))
          .norm(),
      1e-12);
  // Row-major T_BS: the camera's optical axis (z) is almost the body's z axis (third column
  // of R, about (0.004, 0.026, 1.0)) and its x axis the body's y axis.
  EXPECT_GT(e.T_b_c.RotationMatrix()(2, 2), 0.99);
  EXPECT_NEAR(e.T_b_c.RotationMatrix()(0, 1), -0.999880929698, 1e-6);
}

TEST(EurocCalibration, Reads) { CheckEurocCam0(ReadEurocCamera(Write("sensor.yaml", kEurocYaml))); }

TEST(EurocCalibration, RealSensorYaml) {
  const std::string path = kData + "/euroc-v101-head/mav0/cam0/sensor.yaml";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data absent: " << path;
  CheckEurocCam0(ReadEurocCamera(path));
}

TEST(EurocCalibration, BadInput) {
  const std::string text = kEurocYaml;
  struct Case {
    std::string name, from, to, problem;
  };
  const std::vector<Case> cases = {
      {"no_intrinsics", "intrinsics:", "intrinsic:", "missing key 'intrinsics'"},
      {"three_intrinsics", "458.654, ", "", "'intrinsics' .*expected 4 numbers, found 3"},
      {"text_intrinsics", "458.654", "abc", "'intrinsics' value 1 is not a number: 'abc'"},
      {"nan_intrinsics", "458.654", ".nan", "'intrinsics' value 1 is not a number: '.nan'"},
      {"zero_focal", "458.654", "0.0", "non-positive focal length"},
      {"negative_focal", "457.296", "-457.296", "non-positive focal length"},
      {"model", "camera_model: pinhole", "camera_model: omni", "camera_model 'omni'"},
      {"distortion_model", "radial-tangential", "equidistant", "'equidistant' is not supported"},
      {"distortion_count", "0.00019359, ", "", "expected 4 numbers .* found 3"},
      {"no_resolution", "resolution:", "res:", "missing key 'resolution'"},
      {"resolution_count", "[752, 480]", "[752]", "expected 2 numbers, found 1"},
      {"resolution_fraction", "[752, 480]", "[752.5, 480]", "is not a positive integer"},
      {"no_tbs", "T_BS:", "T_SB:", "missing key 'T_BS'"},
      {"tbs_rows", "rows: 4", "rows: 3", "'T_BS' is 3x4"},
      {"tbs_count", "0.0, 0.0, 0.0, 1.0]", "0.0, 0.0, 1.0]", "expected 16 numbers, found 15"},
      {"tbs_not_rotation", "0.0148655429818", "0.5", "'T_BS' rotation is not a rotation"},
      {"tbs_last_row", "0.0, 0.0, 0.0, 1.0]", "0.0, 0.0, 0.0, 2.0]", "last row"},
      {"intrinsics_scalar", "[458.654, 457.296, 367.215, 248.375]", "458", "not a list"},
      {"yaml_syntax", "resolution: [752, 480]", "resolution: [752, 480", "not valid YAML"},
      {"not_a_map", text, "- 1\n- 2\n", "not a YAML map"},
      {"sensor_type", "sensor_type: camera", "sensor_type: imu", "sensor_type is 'imu'"},
  };
  for (const Case& c : cases) {
    std::string bad = text;
    const std::size_t at = bad.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.name;
    bad.replace(at, c.from.size(), c.to);
    const std::string path = Write(c.name + ".yaml", bad);
    ExpectError([&] { ReadEurocCamera(path); }, path, c.problem);
  }
  EXPECT_EQ(cases.size(), 21u);
  const std::string empty = Write("empty.yaml", "");
  ExpectError([&] { ReadEurocCamera(empty); }, empty, "not a YAML map");
}

// Random mutations of valid files (io/fuzz_util.h): every reader either returns a valid camera
// (finite, positive focal lengths) or throws IoError; nothing else escapes, nothing crashes.
TEST(CameraCalibration, MutatedFilesGiveAValidCameraOrIoError) {
  std::mt19937_64 rng(11);
  const std::vector<std::pair<std::string, std::string>> seeds = {
      {"kitti", kKittiCalib}, {"strecha", kStrechaCamera}, {"euroc", kEurocYaml}};
  int accepted = 0, rejected = 0;
  for (int k = 0; k < 1500; ++k) {
    const auto& [kind, seed] = seeds[k % seeds.size()];
    std::string text = seed;
    const int depth = 1 + static_cast<int>(rng() % 4);
    for (int d = 0; d < depth; ++d) text = fuzz::Mutate(text, rng);
    const std::string path = Write("mutated_" + kind, text);
    try {
      sensor::Camera camera;
      if (kind == "kitti") camera = ReadKittiCalibration(path, 100, 50).camera;
      if (kind == "strecha") camera = ReadStrechaCamera(path).camera;
      if (kind == "euroc") camera = ReadEurocCamera(path).camera;
      EXPECT_TRUE(camera.IsValid()) << kind << ": " << camera.Problem() << "\n" << text;
      ++accepted;
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), path);
      ++rejected;
    }
  }
  EXPECT_GT(accepted, 100);
  EXPECT_GT(rejected, 300);
}

}  // namespace
}  // namespace io
}  // namespace plucker
