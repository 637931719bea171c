#include "plucker/vision/undistort.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "plucker/sensor/camera_test_utils.h"

namespace plucker {
namespace vision {
namespace {

using sensor::testing::EurocCam0;
using sensor::testing::TumViCam0;

// Draws the image of the 3D segment a-b (camera frame) through the camera's distorted model: a
// dense anti-aliased polyline of projected points, 4 px wide.
cv::Mat DrawDistortedLine(const sensor::Camera& camera, const Eigen::Vector3d& a,
                          const Eigen::Vector3d& b) {
  cv::Mat image(camera.height, camera.width, CV_8UC1, cv::Scalar(0));
  std::vector<cv::Point> curve;
  constexpr int kShift = 4;  // sub-pixel vertices
  for (int i = 0; i <= 2000; ++i) {
    const auto uv = camera.Project(a + (b - a) * (i / 2000.0));
    if (!uv) continue;
    curve.emplace_back(cvRound(uv->x() * (1 << kShift)), cvRound(uv->y() * (1 << kShift)));
  }
  cv::polylines(image, curve, false, cv::Scalar(255), 4, cv::LINE_AA, kShift);
  return image;
}

struct Straightness {
  int columns = 0;              // columns measured
  double max_fit_residual = 0;  // max |v - fitted line| [px]
  double max_truth_error = 0;   // max |v - ideal pinhole projection of the 3D line| [px]
  double mean_truth_error = 0;  // mean of the same
};

// The line's row per column (intensity centroid), a least-squares line through them, and the
// distance to the ideal pinhole image of the 3D line v = truth_a u + truth_b.
Straightness Measure(const cv::Mat& image, int u0, int u1, double truth_a, double truth_b) {
  std::vector<Eigen::Vector2d> centres;
  for (int u = u0; u <= u1; ++u) {
    double sum = 0, sum_v = 0;
    for (int v = 0; v < image.rows; ++v) {
      const double w = image.at<unsigned char>(v, u);
      sum += w;
      sum_v += w * v;
    }
    if (sum > 200) centres.emplace_back(u, sum_v / sum);
  }
  Straightness s;
  s.columns = static_cast<int>(centres.size());
  if (centres.size() < 2) return s;
  Eigen::MatrixXd A(centres.size(), 2);
  Eigen::VectorXd y(centres.size());
  for (std::size_t i = 0; i < centres.size(); ++i) {
    A.row(i) << centres[i].x(), 1.0;
    y(i) = centres[i].y();
  }
  const Eigen::Vector2d fit = A.colPivHouseholderQr().solve(y);
  for (const Eigen::Vector2d& c : centres) {
    s.max_fit_residual = std::max(s.max_fit_residual, std::abs(fit(0) * c.x() + fit(1) - c.y()));
    const double truth_error = std::abs(truth_a * c.x() + truth_b - c.y());
    s.max_truth_error = std::max(s.max_truth_error, truth_error);
    s.mean_truth_error += truth_error / centres.size();
  }
  return s;
}

struct BeforeAfter {
  Straightness before, after;
};

// The 3D segment a-b (camera frame) drawn through the camera's lens model, undistorted with the
// default output (the camera's K and size), and measured against the ideal pinhole image of the
// line v = truth_a u + truth_b, in the raw image and after undistortion (columns inside the
// segment, away from its round caps, and inside the image).
BeforeAfter MeasureUndistortedLine(const char* name, const sensor::Camera& camera,
                                   const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const cv::Mat raw = DrawDistortedLine(camera, a, b);
  const Undistorter undistorter(camera);
  EXPECT_FALSE(undistorter.IsIdentity());
  const cv::Mat ideal = undistorter.Undistort(raw);
  EXPECT_EQ(ideal.size(), raw.size());
  const sensor::Camera pinhole = undistorter.ideal_camera();
  EXPECT_TRUE(pinhole.IsPinhole());
  const Eigen::Vector2d pa = *pinhole.Project(a), pb = *pinhole.Project(b);
  const double truth_a = (pb.y() - pa.y()) / (pb.x() - pa.x());
  const double truth_b = pa.y() - truth_a * pa.x();
  const Eigen::Vector2d ra = *camera.Project(a), rb = *camera.Project(b);
  const int last = camera.width - 6;
  BeforeAfter r;
  r.before = Measure(raw, std::max(cvCeil(ra.x()) + 5, 5), std::min(cvFloor(rb.x()) - 5, last),
                     truth_a, truth_b);
  r.after = Measure(ideal, std::max(cvCeil(pa.x()) + 5, 5), std::min(cvFloor(pb.x()) - 5, last),
                    truth_a, truth_b);
  std::printf(
      "%s raw: %d columns, max fit residual %.3f px; undistorted: %d columns, max fit "
      "residual %.3f px, distance to the pinhole image max %.3f px mean %.3f px\n",
      name, r.before.columns, r.before.max_fit_residual, r.after.columns, r.after.max_fit_residual,
      r.after.max_truth_error, r.after.mean_truth_error);
  return r;
}

// A straight 3D line near the top of the EuRoC image, imaged through the distorted model, is
// curved in the raw image and straight, where the ideal pinhole puts it, after undistortion.
TEST(Undistorter, StraightLineComesOutStraight) {
  const auto [before, after] = MeasureUndistortedLine(
      "radtan", EurocCam0(), Eigen::Vector3d(-2.0, -1.1, 3.0), Eigen::Vector3d(2.0, -1.3, 3.0));
  EXPECT_GT(before.columns, 450);
  EXPECT_GT(after.columns, 550);
  EXPECT_GT(before.max_fit_residual, 5.0);  // the raw image of the line is a curve
  // What is left is the rendering: anti-aliasing, 1/16 px vertices, the 1/32 px maps, and the
  // 4 px band being stretched more on its outer side (the magnification grows with the radius),
  // which moves its centroid outwards by about 0.1 px. Measured: 0.34 px max, 0.15 px mean.
  EXPECT_LT(after.max_fit_residual, 0.5);
  EXPECT_LT(after.max_truth_error, 0.5);
  EXPECT_LT(after.mean_truth_error, 0.25);
}

// The same on the TUM-VI fisheye (equidistant): a line well off the centre, strongly bent in the
// raw image, is straight where the pinhole of the camera's K puts it (across the whole view).
TEST(Undistorter, FisheyeStraightLineComesOutStraight) {
  const auto [before, after] = MeasureUndistortedLine(
      "fisheye", TumViCam0(), Eigen::Vector3d(-3.0, -1.2, 2.0), Eigen::Vector3d(3.0, -1.2, 2.0));
  EXPECT_GT(before.columns, 200);
  EXPECT_GT(after.columns, 450);
  EXPECT_GT(before.max_fit_residual, 10.0);  // measured 19.7 px: a strong curve
  // Measured: 0.42 px max fit residual, 0.40 px max / 0.15 px mean from the pinhole image.
  EXPECT_LT(after.max_fit_residual, 0.5);
  EXPECT_LT(after.max_truth_error, 0.5);
  EXPECT_LT(after.mean_truth_error, 0.25);
}

// Fisheye point mapping: raw <-> ideal round trips, and a dot drawn at the raw position of an
// ideal pixel peaks there after undistortion (the maps and the model agree).
TEST(Undistorter, FisheyePointMappingMatchesTheImage) {
  const sensor::Camera camera = TumViCam0();
  const Undistorter undistorter(camera);
  for (const Eigen::Vector2d& ideal : {Eigen::Vector2d(40, 30), Eigen::Vector2d(470, 480),
                                       Eigen::Vector2d(255, 257), Eigen::Vector2d(100, 400)}) {
    const auto raw_uv = undistorter.RawFromIdeal(ideal);
    ASSERT_TRUE(raw_uv.has_value());
    EXPECT_LT((*undistorter.IdealFromRaw(*raw_uv) - ideal).norm(), 1e-6);
    cv::Mat raw(camera.height, camera.width, CV_8UC1, cv::Scalar(0));
    cv::circle(raw, cv::Point(cvRound(raw_uv->x() * 16), cvRound(raw_uv->y() * 16)), 8,
               cv::Scalar(255), -1, cv::LINE_AA, 4);
    const cv::Moments m = cv::moments(undistorter.Undistort(raw));
    ASSERT_GT(m.m00, 0);
    // The pinhole view magnifies the periphery (1 / cos^2): the dot's centroid moves outwards a
    // little more than in the radtan case.
    EXPECT_LT((Eigen::Vector2d(m.m10 / m.m00, m.m01 / m.m00) - ideal).norm(), 0.4);
  }
  // A raw pixel beyond the lens's valid angle (TUM-VI's corners) has no ideal pixel.
  EXPECT_FALSE(undistorter.IdealFromRaw(Eigen::Vector2d(0, 0)).has_value());
}

TEST(Undistorter, PointMappingMatchesTheImage) {
  const sensor::Camera camera = EurocCam0();
  const Undistorter undistorter(camera);
  int checked = 0;
  for (const Eigen::Vector2d& ideal : {Eigen::Vector2d(30, 20), Eigen::Vector2d(700, 450),
                                       Eigen::Vector2d(367, 248), Eigen::Vector2d(100, 400)}) {
    const Eigen::Vector2d raw_uv = *undistorter.RawFromIdeal(ideal);
    EXPECT_LT((*undistorter.IdealFromRaw(raw_uv) - ideal).norm(), 1e-6);
    // A bright dot drawn at the raw position peaks at the ideal position after undistortion.
    cv::Mat raw(camera.height, camera.width, CV_8UC1, cv::Scalar(0));
    cv::circle(raw, cv::Point(cvRound(raw_uv.x() * 16), cvRound(raw_uv.y() * 16)), 16,
               cv::Scalar(255), -1, cv::LINE_AA, 4);
    const cv::Moments m = cv::moments(undistorter.Undistort(raw));
    ASSERT_GT(m.m00, 0);
    EXPECT_LT((Eigen::Vector2d(m.m10 / m.m00, m.m01 / m.m00) - ideal).norm(), 0.25);
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

TEST(Undistorter, IdentityFastPathForAPinhole) {
  const sensor::Camera pinhole = EurocCam0().Undistorted();
  const Undistorter identity(pinhole);
  EXPECT_TRUE(identity.IsIdentity());
  cv::Mat raw(pinhole.height, pinhole.width, CV_8UC1, cv::Scalar(7));
  const cv::Mat out = identity.Undistort(raw);
  EXPECT_EQ(out.data, raw.data);  // no copy
  // A chosen output pinhole is not the identity even without distortion.
  UndistorterOptions options;
  options.output_K = PinholeIntrinsics{300, 300, 187.5, 119.5};
  options.output_width = 376;
  options.output_height = 240;
  const Undistorter half(pinhole, options);
  EXPECT_FALSE(half.IsIdentity());
  const cv::Mat small = half.Undistort(raw);
  EXPECT_EQ(small.cols, 376);
  EXPECT_EQ(small.rows, 240);
  EXPECT_EQ(small.at<unsigned char>(120, 188), 7);
}

TEST(Undistorter, BadInput) {
  sensor::Camera bad = EurocCam0();
  bad.K.fx = -1;
  EXPECT_THROW(Undistorter{bad}, std::invalid_argument);
  UndistorterOptions options;
  options.output_K = PinholeIntrinsics{0, 300, 1, 1};
  EXPECT_THROW(Undistorter(EurocCam0(), options), std::invalid_argument);
  const Undistorter undistorter(EurocCam0());
  try {
    undistorter.Undistort(cv::Mat(10, 10, CV_8UC1));
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("image of 10x10 for a camera of 752x480"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(undistorter.Undistort(cv::Mat()), std::invalid_argument);
  EXPECT_FALSE(undistorter.IdealFromRaw(Eigen::Vector2d(NAN, 1)).has_value());
  EXPECT_FALSE(undistorter.RawFromIdeal(Eigen::Vector2d(INFINITY, 1)).has_value());
}

}  // namespace
}  // namespace vision
}  // namespace plucker
