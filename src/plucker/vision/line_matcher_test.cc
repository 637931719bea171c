#include "plucker/vision/line_matcher.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "plucker/geometry/point_projection.h"
#include "plucker/vision/line_tracker.h"
#include "plucker/vision/vision_test_utils.h"

// OpenCV 4.6's EdgeDrawing (the line detector) leaks ~32 bytes per detector inside
// libopencv_ximgproc; only that module is suppressed (as in line_detector_test.cc).
extern "C" const char* __lsan_default_suppressions() { return "leak:libopencv_ximgproc\n"; }

namespace plucker {
namespace vision {
namespace {

// Textured background with filled quadrilaterals of random grey: straight edges of both
// polarities, texture for optical flow.
cv::Mat Scene(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> g(0, 255), noise(-12, 12);
  cv::Mat image(height, width, CV_8UC1, cv::Scalar(128));
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c)
      image.at<uchar>(r, c) = cv::saturate_cast<uchar>(128 + noise(rng));
  }
  std::uniform_real_distribution<double> x(0.05 * width, 0.95 * width),
      y(0.05 * height, 0.95 * height);
  std::uniform_real_distribution<double> size(25, 70), skew(-10, 10);
  for (int i = 0; i < 14; ++i) {
    const double cx = x(rng), cy = y(rng), w = size(rng), h = size(rng);
    std::vector<cv::Point> poly = {
        cv::Point(cvRound(cx - w / 2 + skew(rng)), cvRound(cy - h / 2 + skew(rng))),
        cv::Point(cvRound(cx + w / 2 + skew(rng)), cvRound(cy - h / 2 + skew(rng))),
        cv::Point(cvRound(cx + w / 2 + skew(rng)), cvRound(cy + h / 2 + skew(rng))),
        cv::Point(cvRound(cx - w / 2 + skew(rng)), cvRound(cy + h / 2 + skew(rng)))};
    cv::fillConvexPoly(image, poly, cv::Scalar(g(rng)), cv::LINE_AA);
  }
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.7);
  return image;
}

using testing::Shifted;

double LineDistance(const Eigen::Vector2d& p, const Segment2d& s) {
  const Eigen::Vector2d a = s.head<2>(), d = (s.tail<2>() - a).normalized();
  return std::abs(d.x() * (p.y() - a.y()) - d.y() * (p.x() - a.x()));
}

TEST(LineMatcher, ShiftedImageMatchesItsOwnEdges) {
  const cv::Mat a = Scene(400, 300, 1);
  const Eigen::Vector2d shift(6.0, -3.0);
  const cv::Mat b = Shifted(a, shift.x(), shift.y());
  const auto fa = DescribeLines(a, DetectLineSegments(a).segments);
  const auto fb = DescribeLines(b, DetectLineSegments(b).segments);
  ASSERT_GT(fa.size(), 20);
  ASSERT_GT(fb.size(), 20);
  EXPECT_EQ(fa.descriptors.rows, fa.size());
  EXPECT_EQ(fa.descriptors.cols, 32);
  // With a prediction: the shifted sample points of each segment of a.
  LinePredictions predicted(fa.size());
  for (int i = 0; i < fa.size(); ++i) {
    for (int k = 0; k < 5; ++k) {
      const Segment2d& s = fa.segments[i];
      predicted[i].push_back(s.head<2>() + (k + 0.5) / 5 * (s.tail<2>() - s.head<2>()) + shift);
    }
  }
  const LinePredictions* none = nullptr;
  for (const LinePredictions* p : {none, static_cast<const LinePredictions*>(&predicted)}) {
    const LineMatchResult r = MatchLines(fa, fb, {}, std::nullopt, p);
    int correct = 0;
    std::set<int> used_a, used_b;
    for (const LineMatch& m : r.matches) {
      EXPECT_TRUE(used_a.insert(m.a).second);
      EXPECT_TRUE(used_b.insert(m.b).second);
      const Segment2d& sa = fa.segments[m.a];
      const Segment2d& sb = fb.segments[m.b];
      correct += LineDistance(sa.head<2>() + shift, sb) < 1.5 &&
                 LineDistance(sa.tail<2>() + shift, sb) < 1.5;
    }
    EXPECT_EQ(r.stats.matches, static_cast<int>(r.matches.size()));
    EXPECT_GT(r.stats.matches, fa.size() / 2) << "of " << fa.size();
    EXPECT_GE(correct, 0.95 * r.stats.matches);
    if (p) {
      EXPECT_GT(r.stats.rejected_prediction, 0);
    }
  }
}

// Few segments are described on crops of the image around them: the descriptors are those of
// the whole image, bit for bit (segments in the middle and at the borders); PrepareLines with
// ComputeLineDescriptors is DescribeLines.
TEST(LineMatcher, DescriptorsOnCropsEqualTheWholeImage) {
  const cv::Mat image = Scene(400, 300, 5);
  const std::vector<Segment2d> segments = DetectLineSegments(image).segments;
  ASSERT_GT(segments.size(), 12u);
  LineDescriberOptions whole;
  whole.crop = false;
  const LineFeatures all = DescribeLines(image, segments, whole);
  const LineFeatures prepared = PrepareLines(image, segments);
  ASSERT_EQ(prepared.segments, all.segments);
  EXPECT_TRUE(prepared.descriptors.empty());
  const cv::Mat again = ComputeLineDescriptors(image, prepared.segments, whole);
  EXPECT_EQ(cv::norm(again, all.descriptors, cv::NORM_HAMMING), 0.0);
  std::vector<Segment2d> few = {Segment2d(2, 2, 60, 2), Segment2d(397, 10, 397, 290),
                                Segment2d(150, 297, 260, 280)};
  for (int i = 0; i < 3; ++i) few.push_back(all.segments[i * 4]);
  const LineFeatures few_prepared = PrepareLines(image, few);
  ASSERT_EQ(few_prepared.size(), 6);
  const cv::Mat on_crops = ComputeLineDescriptors(image, few_prepared.segments);
  const cv::Mat on_whole = ComputeLineDescriptors(image, few_prepared.segments, whole);
  for (int i = 0; i < few_prepared.size(); ++i) {
    EXPECT_EQ(HammingDistance(on_whole, i, on_crops, i), 0) << "segment " << i;
  }
}

TEST(LineMatcher, OrientationByPolarityAndClipping) {
  cv::Mat image(100, 120, CV_8UC1, cv::Scalar(40));
  image(cv::Rect(0, 0, 60, 100)).setTo(200);  // bright left half: a vertical edge at x = 59.5
  const std::vector<Segment2d> segments = {Segment2d(59.5, 10, 59.5, 90),
                                           Segment2d(59.5, 90, 59.5, 10),
                                           Segment2d(59.5, -50, 59.5, 500),  // clipped
                                           Segment2d(59.5, 10, 59.5, 12)};   // too short
  LineDescriptionStats stats;
  const LineFeatures f = DescribeLines(image, segments, {}, &stats);
  ASSERT_EQ(f.size(), 3);
  EXPECT_EQ(stats.rejected_short, 1);
  EXPECT_EQ(stats.flipped, 2);  // 0 and 2 run downwards with the bright side on their right
  EXPECT_EQ(f.source_index, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(f.segments[0], f.segments[1]);  // same orientation whatever the input order
  EXPECT_EQ(HammingDistance(f.descriptors, 0, f.descriptors, 1), 0);
  EXPECT_GE(f.segments[2].minCoeff(), 2.0);
  EXPECT_LE(f.segments[2][3], 97.0);
  EXPECT_LE(f.segments[2][1], 97.0);
}

TEST(LineMatcher, EmptyInputAndNoLines) {
  const cv::Mat blank(80, 90, CV_8UC1, cv::Scalar(77));
  EXPECT_TRUE(DetectLineSegments(blank).segments.empty());
  const LineFeatures none = DescribeLines(blank, {});
  EXPECT_EQ(none.size(), 0);
  const cv::Mat a = Scene(200, 150, 3);
  const LineFeatures fa = DescribeLines(a, DetectLineSegments(a).segments);
  ASSERT_GT(fa.size(), 0);
  for (const auto& r : {MatchLines(none, fa), MatchLines(fa, none), MatchLines(none, none)}) {
    EXPECT_TRUE(r.matches.empty());
    EXPECT_EQ(r.stats.matches, 0);
  }
  EXPECT_EQ(MatchLines(fa, none).stats.no_candidate, fa.size());
  EXPECT_THROW(DescribeLines(cv::Mat(), {}), std::invalid_argument);
  EXPECT_THROW(DescribeLines(cv::Mat(10, 10, CV_32FC1), {}), std::invalid_argument);
  LinePredictions wrong_size(fa.size() + 1);
  EXPECT_THROW(MatchLines(fa, fa, {}, std::nullopt, &wrong_size), std::invalid_argument);
  // Two unrelated scenes: few matches, each segment at most once.
  const cv::Mat c = Scene(200, 150, 4);
  const LineFeatures fc = DescribeLines(c, DetectLineSegments(c).segments);
  const LineMatchResult r = MatchLines(fa, fc);
  std::set<int> used;
  for (const LineMatch& m : r.matches) EXPECT_TRUE(used.insert(m.b).second);
}

TEST(LineMatcher, NeverOneSegmentTwiceWithoutTheMutualTest) {
  const cv::Mat image = Scene(300, 200, 5);
  const LineFeatures fb = DescribeLines(image, DetectLineSegments(image).segments);
  ASSERT_GT(fb.size(), 5);
  // a = b with every segment twice: both copies want the same b at distance 0.
  LineFeatures fa = fb;
  fa.segments.insert(fa.segments.end(), fb.segments.begin(), fb.segments.end());
  cv::vconcat(fb.descriptors, fb.descriptors, fa.descriptors);
  LineMatcherOptions o;
  o.mutual = false;
  const auto r = MatchLines(fa, fb, o);
  std::set<int> used_b;
  for (const LineMatch& m : r.matches) EXPECT_TRUE(used_b.insert(m.b).second);
  EXPECT_GT(r.stats.matches, fb.size() / 2);
  EXPECT_GE(r.stats.rejected_mutual, r.stats.matches);  // the second copies
  o.mutual = true;
  EXPECT_LE(MatchLines(fa, fb, o).stats.matches, fb.size());
}

TEST(LineMatcher, EpipolarOverlap) {
  PinholeIntrinsics K;
  K.fx = K.fy = 500;
  K.cx = 320;
  K.cy = 240;
  const SE3d T_w_a;
  const SE3d T_w_b(Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d(0.5, 0.1, 0.0));
  const Eigen::Matrix3d F = FundamentalFromPoses(K, T_w_a, T_w_b);
  const Eigen::Vector3d P(-0.5, -1.0, 6.0), Q(0.3, 1.0, 7.0), R(0.7, 2.0, 7.5);
  auto project = [&](const SE3d& T, const Eigen::Vector3d& X) { return *ProjectPoint(K, T, X); };
  auto seg = [&](const SE3d& T, const Eigen::Vector3d& A, const Eigen::Vector3d& B) {
    const Eigen::Vector2d a = project(T, A), b = project(T, B);
    return Segment2d(a.x(), a.y(), b.x(), b.y());
  };
  // Epipolar constraint of the pose-built F.
  EXPECT_NEAR(project(T_w_b, P).homogeneous().dot(F * project(T_w_a, P).homogeneous()), 0.0,
              1e-9 * F.norm() * 1e6);
  const auto same = EpipolarOverlap(seg(T_w_a, P, Q), seg(T_w_b, P, Q), F, 2.0);
  ASSERT_TRUE(same.has_value());
  EXPECT_NEAR(*same, 1.0, 1e-6);
  // The same 3D line, but the other part of it in b: no overlap.
  const Eigen::Vector3d Q2 = Q + 1.5 * (Q - P);
  const auto apart = EpipolarOverlap(seg(T_w_a, P, Q), seg(T_w_b, Q + 0.1 * (Q - P), Q2), F, 2.0);
  ASSERT_TRUE(apart.has_value());
  EXPECT_NEAR(*apart, 0.0, 1e-9);
  // A segment along the epipolar lines: undefined.
  const Eigen::Vector3d C_a = T_w_a.translation();
  const auto along =
      EpipolarOverlap(seg(T_w_a, P, Q), seg(T_w_b, P, C_a + 0.5 * (P - C_a)), F, 2.0);
  EXPECT_FALSE(along.has_value());
  (void)R;
}

TEST(LineMatcher, FundamentalFromPointTracks) {
  PinholeIntrinsics K;
  K.fx = K.fy = 500;
  K.cx = 320;
  K.cy = 240;
  const SE3d T_w_a;
  const SE3d T_w_b(Eigen::Quaterniond(Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d(0.3, 0.05, 0.4));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-3, 3), z(5, 15);
  std::vector<sensor::PointObservation> pa, pb;
  for (int i = 0; i < 60; ++i) {
    const Eigen::Vector3d X(u(rng), u(rng), z(rng));
    const auto xa = ProjectPoint(K, T_w_a, X), xb = ProjectPoint(K, T_w_b, X);
    ASSERT_TRUE(xa && xb);
    pa.push_back({0, i, *xa});
    pb.push_back({1, i, *xb});
  }
  for (const auto& Kopt :
       {std::optional<PinholeIntrinsics>(K), std::optional<PinholeIntrinsics>()}) {
    const auto F = FundamentalFromPointTracks(pa, pb, Kopt, 0.5);
    ASSERT_TRUE(F.has_value());
    SCOPED_TRACE(Kopt ? "essential" : "fundamental");
    // Epipolar distances of all points below 0.1 px.
    for (std::size_t i = 0; i < pa.size(); ++i) {
      const Eigen::Vector3d l = *F * pa[i].uv.homogeneous();
      EXPECT_LT(std::abs(l.dot(pb[i].uv.homogeneous())) / l.head<2>().norm(), 0.1);
    }
  }
  pb.resize(10);
  EXPECT_FALSE(FundamentalFromPointTracks(pa, pb, K).has_value());  // too few common tracks
}

// The angle gate (no atan2) accepts exactly the pairs whose oriented direction change
// atan2(|a x b|, a . b) is within max_angle_deg, for gates below and above 90 deg.
TEST(LineMatcher, AngleGateIsTheOrientedAngle) {
  LineFeatures a, b;
  a.segments = {Segment2d(0, 0, 100, 0)};
  a.descriptors = cv::Mat::zeros(1, 32, CV_8UC1);
  b.descriptors = cv::Mat::zeros(1, 32, CV_8UC1);
  LineMatcherOptions o;
  o.max_midpoint_distance_px = 0.0;
  int checked = 0;
  for (const double max_angle : {12.0, 30.0, 90.0, 120.0}) {
    o.max_angle_deg = max_angle;
    for (double deg = -179.75; deg < 180.0; deg += 0.5) {
      const double r = deg * M_PI / 180.0;
      b.segments = {Segment2d(10, 5, 10 + 80 * std::cos(r), 5 + 80 * std::sin(r))};
      const LineMatchResult m = MatchLines(a, b, o);
      const bool within = std::abs(deg) <= max_angle;
      EXPECT_EQ(m.stats.rejected_angle, within ? 0 : 1) << deg << " deg, gate " << max_angle;
      EXPECT_EQ(m.stats.matches, within ? 1 : 0) << deg << " deg, gate " << max_angle;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 4 * 720);
}

}  // namespace
}  // namespace vision
}  // namespace plucker
