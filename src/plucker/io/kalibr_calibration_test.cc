#include "plucker/io/kalibr_calibration.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <random>

#include "plucker/io/camera_calibration.h"
#include "plucker/io/euroc_imu.h"
#include "plucker/io/io_test_utils.h"

namespace plucker {
namespace io {
namespace {

const std::string kData = PLUCKER_SHARED_DATA_DIR;

// EuRoC's cam0 in a Kalibr camchain-imucam.yaml: the intrinsics and distortion as the same text
// as mav0/cam0/sensor.yaml; T_cam_imu = T_BS^-1 (rotation: the transposed text of T_BS;
// translation -R^T t to 17 digits); cam1 with T_cn_cnm1 and a time shift.
const char* kEurocCamchain = R"(cam0:
  T_cam_imu:
  - [0.0148655429818, 0.999557249008, -0.0257744366974, 0.06522290953550845]
  - [-0.999880929698, 0.0149672133247, 0.00375618835797, -0.020706385492708257]
  - [0.00414029679422, 0.025715529948, 0.999660727178, -0.008054602460028365]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
  distortion_model: radtan
  intrinsics: [458.654, 457.296, 367.215, 248.375]
  resolution: [752, 480]
  rostopic: /cam0/image_raw
  timeshift_cam_imu: 0.0
cam1:
  T_cn_cnm1:
  - [1.0, 0.0, 0.0, -0.110073808127187]
  - [0.0, 0.6, -0.8, 0.000399121547014]
  - [0.0, 0.8, 0.6, -0.000853702503358]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182]
  distortion_model: equidistant
  intrinsics: [190.97847715128717, 190.9733070521226, 254.93170605935475, 256.8974428996504]
  resolution: [512, 512]
  timeshift_cam_imu: -8.121e-05
)";

// OpenVINS' kalibr_imucam_chain.yaml: T_imu_cam = T_BS, the same text.
const char* kOpenVinsChain = R"(%YAML:1.0
cam0:
  T_imu_cam: # camera to IMU
    - [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975]
    - [0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768]
    - [-0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949]
    - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
  distortion_model: radtan
  intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv
  resolution: [752, 480]
  rostopic: /cam0/image_raw
)";

// EuRoC's imu0/sensor.yaml noise figures in Kalibr's imu.yaml.
const char* kEurocImu = R"(#Accelerometers
accelerometer_noise_density: 2.0000e-3   #Noise density (continuous-time)
accelerometer_random_walk:   3.0000e-3   #Bias random walk
#Gyroscopes
gyroscope_noise_density:     1.6968e-04  #Noise density (continuous-time)
gyroscope_random_walk:       1.9393e-05  #Bias random walk
rostopic:                    /imu0       #the IMU ROS topic
update_rate:                 200.0       #Hz (for discretization of the values above)
)";

std::string Write(const testing::ScratchDir& dir, const std::string& name,
                  const std::string& text) {
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

void ExpectSameCamera(const sensor::Camera& a, const sensor::Camera& b) {
  EXPECT_EQ(a.K.fx, b.K.fx);
  EXPECT_EQ(a.K.fy, b.K.fy);
  EXPECT_EQ(a.K.cx, b.K.cx);
  EXPECT_EQ(a.K.cy, b.K.cy);
  EXPECT_EQ(a.distortion.k1, b.distortion.k1);
  EXPECT_EQ(a.distortion.k2, b.distortion.k2);
  EXPECT_EQ(a.distortion.p1, b.distortion.p1);
  EXPECT_EQ(a.distortion.p2, b.distortion.p2);
  EXPECT_EQ(a.distortion.k3, b.distortion.k3);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.model, b.model);
}

// The EuRoC reader on the real sensor.yaml, or GTEST_SKIP.
std::optional<EurocCamera> RealEurocCam0() {
  const std::string path = kData + "/euroc-v101-head/mav0/cam0/sensor.yaml";
  if (!std::filesystem::exists(path)) return std::nullopt;
  return ReadEurocCamera(path);
}

TEST(KalibrCalibration, EurocCamchainGivesTheEurocCamera) {
  const auto euroc = RealEurocCam0();
  if (!euroc) GTEST_SKIP() << "no " << kData << "/euroc-v101-head";
  const testing::ScratchDir dir;
  const KalibrCameraChain chain =
      ReadKalibrCameraChain(Write(dir, "camchain-imucam.yaml", kEurocCamchain));
  ASSERT_EQ(chain.cameras.size(), 2u);
  EXPECT_EQ(chain.cameras[0].name, "cam0");
  ExpectSameCamera(chain.cameras[0].camera, euroc->camera);  // the same text: bit-identical
  // T_cam_imu inverted: the same up to rounding. The file's translation is -R^T t of the raw
  // 12-digit rotation, the reader's inverse uses its projection onto SO(3) (measured 1.1e-14 m).
  const SE3d T_b_c = chain.RequireT_b_c(0);
  EXPECT_LT((T_b_c.rotation().toRotationMatrix() - euroc->T_b_c.rotation().toRotationMatrix())
                .cwiseAbs()
                .maxCoeff(),
            1e-14);
  EXPECT_LT((T_b_c.translation() - euroc->T_b_c.translation()).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_EQ(chain.cameras[0].timeshift_cam_imu, 0.0);
  EXPECT_FALSE(chain.cameras[0].T_cn_cnm1.has_value());
}

TEST(KalibrCalibration, OpenVinsChainIsBitIdenticalToTheEurocReader) {
  const auto euroc = RealEurocCam0();
  if (!euroc) GTEST_SKIP() << "no " << kData << "/euroc-v101-head";
  const testing::ScratchDir dir;
  const KalibrCameraChain chain =
      ReadKalibrCameraChain(Write(dir, "kalibr_imucam_chain.yaml", kOpenVinsChain));
  ASSERT_EQ(chain.cameras.size(), 1u);
  ExpectSameCamera(chain.cameras[0].camera, euroc->camera);
  const SE3d T_b_c = chain.RequireT_b_c(0);
  EXPECT_EQ(T_b_c.rotation().coeffs(), euroc->T_b_c.rotation().coeffs());
  EXPECT_EQ(T_b_c.translation(), euroc->T_b_c.translation());
}

TEST(KalibrCalibration, SecondCameraEquidistantExtrinsicAndTimeShift) {
  const KalibrCameraChain chain = ParseKalibrCameraChain(kEurocCamchain, "camchain.yaml");
  ASSERT_EQ(chain.cameras.size(), 2u);
  const KalibrCamera& cam1 = chain.cameras[1];
  EXPECT_EQ(cam1.name, "cam1");
  EXPECT_EQ(cam1.camera.model, sensor::CameraModel::kEquidistant);
  EXPECT_FALSE(cam1.camera.IsPinhole());
  EXPECT_EQ(cam1.camera.equidistant.k1, 0.0034823894022493434);  // k1..k4 in the file's order
  EXPECT_EQ(cam1.camera.equidistant.k2, 0.0007150348452162257);
  EXPECT_EQ(cam1.camera.equidistant.k3, -0.0020532361418706202);
  EXPECT_EQ(cam1.camera.equidistant.k4, 0.00020293673591811182);
  EXPECT_EQ(cam1.camera.K.fx, 190.97847715128717);
  EXPECT_EQ(cam1.camera.width, 512);
  EXPECT_EQ(cam1.timeshift_cam_imu, -8.121e-05);
  ASSERT_TRUE(cam1.T_cn_cnm1.has_value());
  EXPECT_NEAR(cam1.T_cn_cnm1->translation().x(), -0.110073808127187, 1e-15);
  // No IMU extrinsic for cam1: an error naming the key when asked for.
  EXPECT_FALSE(cam1.T_b_c.has_value());
  try {
    chain.RequireT_b_c(1);
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), "camchain.yaml");
    EXPECT_NE(e.problem().find("cam1.T_cam_imu"), std::string::npos) << e.what();
  }
  EXPECT_THROW(chain.RequireT_b_c(2), IoError);
}

// Kalibr's equidistant coefficients mean what OpenCV's fisheye model means: a camera read from a
// camchain projects points as cv::fisheye::projectPoints does (an independent implementation of
// the same formula, with the same coefficient order).
TEST(KalibrCalibration, EquidistantCameraProjectsLikeOpenCvFisheye) {
  const sensor::Camera c =
      ParseKalibrCameraChain(kEurocCamchain, "camchain.yaml").cameras[1].camera;
  ASSERT_EQ(c.model, sensor::CameraModel::kEquidistant);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> angle(0.0, 1.4), azimuth(-M_PI, M_PI), depth(0.5, 20);
  std::vector<cv::Point3d> points;
  for (int i = 0; i < 500; ++i) {
    const double t = i == 0 ? 0.0 : angle(rng), a = azimuth(rng), d = depth(rng);
    points.emplace_back(d * std::sin(t) * std::cos(a), d * std::sin(t) * std::sin(a),
                        d * std::cos(t));
  }
  const cv::Matx33d K(c.K.fx, 0, c.K.cx, 0, c.K.fy, c.K.cy, 0, 0, 1);
  const cv::Vec4d D(c.equidistant.k1, c.equidistant.k2, c.equidistant.k3, c.equidistant.k4);
  std::vector<cv::Point2d> uv_cv;
  cv::fisheye::projectPoints(points, uv_cv, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D);
  ASSERT_EQ(uv_cv.size(), points.size());
  double worst = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto uv = c.Project(Eigen::Vector3d(points[i].x, points[i].y, points[i].z));
    ASSERT_TRUE(uv.has_value()) << i;
    worst = std::max(worst, (*uv - Eigen::Vector2d(uv_cv[i].x, uv_cv[i].y)).norm());
  }
  EXPECT_LT(worst, 1e-9);  // pixels
}

TEST(KalibrCalibration, ImuYamlGivesTheEurocImuModel) {
  const sensor::ImuModel m = ParseKalibrImu(kEurocImu, "imu.yaml");
  const std::string euroc_path = kData + "/euroc-v101-head/mav0/imu0/sensor.yaml";
  if (!std::filesystem::exists(euroc_path)) GTEST_SKIP() << "no " << euroc_path;
  std::ifstream in(euroc_path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const sensor::ImuModel e = ParseEurocImuYaml(text, euroc_path);
  EXPECT_EQ(m.rate_hz, e.rate_hz);
  EXPECT_EQ(m.gyro_noise_density, e.gyro_noise_density);
  EXPECT_EQ(m.gyro_bias_random_walk, e.gyro_bias_random_walk);
  EXPECT_EQ(m.accel_noise_density, e.accel_noise_density);
  EXPECT_EQ(m.accel_bias_random_walk, e.accel_bias_random_walk);
  // OpenVINS' kalibr_imu_chain.yaml: the same keys under imu0.
  std::string nested = "imu0:\n";
  std::istringstream lines(kEurocImu);
  for (std::string line; std::getline(lines, line);) nested += "  " + line + "\n";
  const sensor::ImuModel n = ParseKalibrImu(nested, "kalibr_imu_chain.yaml");
  EXPECT_EQ(n.gyro_noise_density, e.gyro_noise_density);
  EXPECT_EQ(n.rate_hz, 200.0);
}

// Replaces the first occurrence of `from` in `text` (which must contain it).
std::string Edit(const std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  std::string out = text;
  if (at != std::string::npos) out.replace(at, from.size(), to);
  return out;
}

void ExpectChainError(const std::string& text, const std::string& needle) {
  try {
    ParseKalibrCameraChain(text, "bad.yaml");
    ADD_FAILURE() << "no error for: " << needle;
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), "bad.yaml");
    EXPECT_NE(e.problem().find(needle), std::string::npos) << e.what();
  }
}

TEST(KalibrCalibration, TrapsGetNamedErrors) {
  const std::string t = kEurocCamchain;
  ExpectChainError(Edit(t, "camera_model: pinhole", "camera_model: omni"),
                   "cam0: camera_model 'omni' with distortion_model 'radtan' is not supported");
  ExpectChainError(Edit(t, "distortion_model: equidistant", "distortion_model: fov"),
                   "cam1: camera_model 'pinhole' with distortion_model 'fov' is not supported");
  ExpectChainError(Edit(t, "camera_model: pinhole", "camera_model: ds"), "'ds'");
  ExpectChainError(Edit(t, "  intrinsics: [458.654, 457.296, 367.215, 248.375]\n", ""),
                   "missing key 'cam0.intrinsics'");
  ExpectChainError(Edit(t, "[458.654, 457.296, 367.215, 248.375]", "[458.654, 457.296, 367.215]"),
                   "'cam0.intrinsics' [fu, fv, pu, pv]: expected 4 numbers, found 3");
  ExpectChainError(Edit(t, "1.76187114e-05]", "1.76187114e-05, 0.1]"),
                   "'cam0.distortion_coeffs' [k1, k2, p1, p2]: expected 4 numbers, found 5");
  ExpectChainError(Edit(t, "[458.654,", "[-458.654,"), "cam0: focal length fx");
  ExpectChainError(Edit(t, "0.00020293673591811182]", ".nan]"), "cam1.distortion_coeffs' value 4");
  ExpectChainError(Edit(t, "[752, 480]", "[752.5, 480]"), "cam0.resolution width");
  // Non-rigid 4x4s name the key: a scaled rotation, a shear, a reflection, a wrong last row.
  ExpectChainError(Edit(t, "[0.0148655429818, 0.999557249008", "[0.0148755429818, 0.999557249008"),
                   "'cam0.T_cam_imu' rotation is not a rotation");
  ExpectChainError(Edit(t, "- [1.0, 0.0, 0.0,", "- [1.0, 0.001, 0.0,"),
                   "'cam1.T_cn_cnm1' rotation is not a rotation");
  ExpectChainError(Edit(t, "- [0.00414029679422, 0.025715529948, 0.999660727178,",
                        "- [-0.00414029679422, -0.025715529948, -0.999660727178,"),
                   "det = -");
  ExpectChainError(Edit(t, "  - [0.0, 0.0, 0.0, 1.0]\n  cam_overlaps",
                        "  - [0.0, 0.0, 1.0, 1.0]\n  cam_overlaps"),
                   "'cam0.T_cam_imu' is not a rigid transform: last row is not (0, 0, 0, 1)");
  ExpectChainError(
      Edit(t, "  - [0.0, 0.0, 0.0, 1.0]\n  cam_overlaps", "  - [0.0, 0.0, 1.0]\n  cam_overlaps"),
      "'cam0.T_cam_imu' row 4: expected 4 numbers, found 3");
  ExpectChainError(Edit(t, "cam1:", "cam2:"), "'cam2' follows 'cam0'");
  ExpectChainError("cam_0: {}\n", "no camera");
  ExpectChainError("- 1\n- 2\n", "not a YAML map");
  ExpectChainError(Edit(kOpenVinsChain, "  cam_overlaps",
                        "  T_cam_imu: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]\n  cam_overlaps"),
                   "both T_cam_imu and T_imu_cam");
  ExpectChainError(Edit(t, "timeshift_cam_imu: 0.0", "timeshift_cam_imu: soon"),
                   "'cam0.timeshift_cam_imu' is not a number");
  // Within the 1e-6 orthonormality bound: accepted (and projected onto a rotation).
  const KalibrCameraChain nearly = ParseKalibrCameraChain(
      Edit(t, "[0.0148655429818, 0.999557249008", "[0.0148655439818, 0.999557249008"), "ok.yaml");
  EXPECT_LT((nearly.RequireT_b_c().rotation().toRotationMatrix() -
             ParseKalibrCameraChain(t, "t").RequireT_b_c().rotation().toRotationMatrix())
                .norm(),
            1e-8);
  // A camera-only camchain (no T_cam_imu) reads; asking for the IMU extrinsic is the error.
  const KalibrCameraChain camera_only = ParseKalibrCameraChain(
      Edit(kOpenVinsChain, "T_imu_cam: # camera to IMU", "T_other: # ignored"), "camchain.yaml");
  EXPECT_FALSE(camera_only.cameras[0].T_b_c.has_value());
  EXPECT_THROW(camera_only.RequireT_b_c(0), IoError);
}

TEST(KalibrCalibration, ImuErrorsNameTheKey) {
  const std::string t = kEurocImu;
  const auto expect = [](const std::string& text, const std::string& needle) {
    try {
      ParseKalibrImu(text, "imu.yaml");
      ADD_FAILURE() << "no error for: " << needle;
    } catch (const IoError& e) {
      EXPECT_NE(e.problem().find(needle), std::string::npos) << e.what();
    }
  };
  expect(Edit(t, "update_rate:", "rate:"), "missing key 'update_rate'");
  expect(Edit(t, "1.6968e-04", "-1.6968e-04"),
         "'gyroscope_noise_density' = -0.00016968 is not > 0");
  expect(Edit(t, "3.0000e-3", "x"), "'accelerometer_random_walk' is not a number");
  expect("imu0: 3\n", "'imu0' is not a map");
}

TEST(KalibrCalibration, MissingFile) {
  EXPECT_THROW(ReadKalibrCameraChain("/nonexistent/camchain.yaml"), IoError);
  EXPECT_THROW(ReadKalibrImu("/nonexistent/imu.yaml"), IoError);
}

}  // namespace
}  // namespace io
}  // namespace plucker
