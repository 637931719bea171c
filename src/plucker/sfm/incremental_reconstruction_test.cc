// Incremental reconstruction on synthetic views (projections of a known scene of points and lines
// with unique descriptors) and on three real Strecha images (skipped without the shared data).
#include "plucker/sfm/incremental_reconstruction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>

#include "plucker/eval/camera_set.h"
#include "plucker/geometry/point_projection.h"
#include "plucker/io/camera_calibration.h"
#include "plucker/io/image_folder.h"

namespace plucker {
namespace sfm {
namespace {

namespace fs = std::filesystem;

struct Scene {
  PinholeIntrinsics K{800, 800, 400, 300};
  std::vector<SE3d> T_w_c;
  std::vector<Eigen::Vector3d> points;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines;
};

// Cameras on an arc of radius 8 around a box of points and segments at the origin, each looking
// at the centre.
Scene MakeScene(int num_views, int num_points, int num_lines, std::mt19937* rng) {
  Scene s;
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int i = 0; i < num_points; ++i) s.points.emplace_back(u(*rng), u(*rng), u(*rng));
  for (int i = 0; i < num_lines; ++i) {
    const Eigen::Vector3d a(u(*rng), u(*rng), u(*rng));
    Eigen::Vector3d d(u(*rng), u(*rng), u(*rng));
    s.lines.emplace_back(a, a + 1.5 * d.normalized());
  }
  for (int i = 0; i < num_views; ++i) {
    const double angle = -0.5 + 1.0 * i / std::max(1, num_views - 1);
    const Eigen::Vector3d c(8 * std::sin(angle), 0.5 * std::cos(3 * angle), -8 * std::cos(angle));
    const Eigen::Vector3d z = (-c).normalized();
    const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
    const Eigen::Vector3d y = z.cross(x);
    Eigen::Matrix3d R;
    R << x, y, z;
    s.T_w_c.emplace_back(R, c);
  }
  return s;
}

// One view's features: projected points with a per-point descriptor (plus noise), projected
// segments with a per-line binary descriptor.
ViewFeatures Render(const Scene& s, int view, double noise_px, std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, noise_px);
  std::mt19937 desc_rng(7);  // the same descriptors in every view
  std::normal_distribution<float> d(0.0f, 1.0f);
  ViewFeatures f;
  f.width = 800;
  f.height = 600;
  cv::Mat desc(static_cast<int>(s.points.size()), 128, CV_32F);
  for (int r = 0; r < desc.rows; ++r)
    for (int c = 0; c < 128; ++c) desc.at<float>(r, c) = d(desc_rng);
  std::vector<int> rows;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const auto uv = ProjectPoint(s.K, s.T_w_c[view], s.points[i]);
    if (!uv || uv->x() < 0 || uv->y() < 0 || uv->x() > 799 || uv->y() > 599) continue;
    f.keypoints.push_back(*uv + Eigen::Vector2d(n(*rng), n(*rng)));
    rows.push_back(static_cast<int>(i));
  }
  f.descriptors = cv::Mat(static_cast<int>(rows.size()), 128, CV_32F);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    desc.row(rows[k]).copyTo(f.descriptors.row(static_cast<int>(k)));
    for (int c = 0; c < 128; ++c)
      f.descriptors.at<float>(static_cast<int>(k), c) += 0.05f * d(*rng);
  }
  std::mt19937 line_rng(11);
  std::uniform_int_distribution<int> byte(0, 255);
  cv::Mat line_desc(static_cast<int>(s.lines.size()), 32, CV_8UC1);
  for (int r = 0; r < line_desc.rows; ++r)
    for (int c = 0; c < 32; ++c) line_desc.at<uchar>(r, c) = static_cast<uchar>(byte(line_rng));
  std::vector<int> line_rows;
  for (std::size_t i = 0; i < s.lines.size(); ++i) {
    const auto a = ProjectPoint(s.K, s.T_w_c[view], s.lines[i].first);
    const auto b = ProjectPoint(s.K, s.T_w_c[view], s.lines[i].second);
    if (!a || !b || (*a - *b).norm() < 20) continue;
    vision::Segment2d seg;
    seg << *a + Eigen::Vector2d(n(*rng), n(*rng)), *b + Eigen::Vector2d(n(*rng), n(*rng));
    f.lines.segments.push_back(seg);
    f.lines.source_index.push_back(static_cast<int>(i));
    line_rows.push_back(static_cast<int>(i));
  }
  f.lines.descriptors = cv::Mat(static_cast<int>(line_rows.size()), 32, CV_8UC1);
  for (std::size_t k = 0; k < line_rows.size(); ++k)
    line_desc.row(line_rows[k]).copyTo(f.lines.descriptors.row(static_cast<int>(k)));
  return f;
}

eval::CameraSetErrors Compare(const std::vector<std::optional<SE3d>>& est,
                              const std::vector<SE3d>& gt) {
  const eval::CameraSetErrors e = eval::CompareCameraSets(est, gt);
  EXPECT_TRUE(e.ok) << e.message;
  return e;
}

TEST(IncrementalReconstruction, RecoversSyntheticPosesPointsAndLines) {
  std::mt19937 rng(3);
  const Scene s = MakeScene(6, 400, 40, &rng);
  std::vector<ViewFeatures> views;
  for (int v = 0; v < 6; ++v) views.push_back(Render(s, v, 0.3, &rng));
  SfmOptions options;
  std::vector<SfmStage> stages;
  const SfmResult r = Reconstruct(s.K, views, options, [&](SfmStage st) { stages.push_back(st); });
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.stats.registered, 6);
  EXPECT_GT(r.stats.points, 350);
  EXPECT_GT(r.stats.lines, 25);
  EXPECT_LT(r.stats.mean_point_error_px, 0.6);
  EXPECT_LT(r.stats.mean_line_error_px, 0.6);
  ASSERT_FALSE(stages.empty());
  EXPECT_EQ(stages.back(), SfmStage::kDone);
  const eval::CameraSetErrors e = Compare(r.T_w_c, s.T_w_c);
  std::printf(
      "synthetic: %d points, %d lines, max centre error %.2e, max rotation %.4f deg (%.4f deg "
      "with the centres' rotation)\n",
      r.stats.points, r.stats.lines, e.max_centre, e.max_rotation_deg, e.max_rotation_centres_deg);
  EXPECT_LT(e.max_centre, 0.01);  // of an 8-unit radius
  EXPECT_LT(e.max_rotation_deg, 0.05);
  // Every reconstructed line reprojects close to its observed segments.
  for (const SfmLine& l : r.lines) EXPECT_GE(l.observations.size(), 2u);
}

TEST(IncrementalReconstruction, ABadViewStaysUnregisteredAndTheBudgetHolds) {
  std::mt19937 rng(5);
  const Scene s = MakeScene(5, 300, 0, &rng);
  std::vector<ViewFeatures> views;
  for (int v = 0; v < 5; ++v) views.push_back(Render(s, v, 0.3, &rng));
  views[2] = ViewFeatures();  // unreadable image
  SfmOptions options;
  options.use_lines = false;
  options.max_points = 100;
  const SfmResult r = Reconstruct(s.K, views, options);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.stats.registered, 4);
  EXPECT_FALSE(r.T_w_c[2].has_value());
  EXPECT_NE(r.view_status[2], "registered");
  EXPECT_LE(r.stats.points, 100);
  EXPECT_GT(r.stats.points, 50);
  for (const auto& T : r.T_w_c) {
    if (T) {
      EXPECT_TRUE(T->translation().allFinite() && T->rotation().coeffs().allFinite());
    }
  }
  const eval::CameraSetErrors e = Compare(r.T_w_c, s.T_w_c);
  EXPECT_LT(e.max_centre, 0.02);
}

// The random point subset is a function of the seed alone (the same with and without lines),
// differs from the longest tracks, and the matching threads do not change the result.
TEST(IncrementalReconstruction, SeededPointSubsetAndThreadsAreRepeatable) {
  std::mt19937 rng(13);
  const Scene s = MakeScene(5, 300, 30, &rng);
  std::vector<ViewFeatures> views;
  for (int v = 0; v < 5; ++v) views.push_back(Render(s, v, 0.3, &rng));
  const auto first_observations = [](const SfmResult& r) {
    std::vector<std::pair<int, int>> first;
    for (const SfmPoint& p : r.points) first.push_back(p.observations.front());
    std::sort(first.begin(), first.end());
    return first;
  };
  SfmOptions options;
  options.max_points = 60;
  options.point_subset_seed = 7;
  const SfmResult with_lines = Reconstruct(s.K, views, options);
  options.num_threads = 2;
  const SfmResult threaded = Reconstruct(s.K, views, options);
  options.use_lines = false;
  const SfmResult points_only = Reconstruct(s.K, views, options);
  options.point_subset_seed = 0;
  const SfmResult longest = Reconstruct(s.K, views, options);
  for (const SfmResult* r : {&with_lines, &threaded, &points_only, &longest}) {
    ASSERT_TRUE(r->ok) << r->message;
    EXPECT_EQ(r->stats.registered, 5);
    EXPECT_LE(r->stats.points, 60);
    EXPECT_GT(r->stats.points, 40);
  }
  EXPECT_GT(with_lines.stats.lines, 0);
  EXPECT_EQ(first_observations(with_lines), first_observations(points_only));
  EXPECT_NE(first_observations(points_only), first_observations(longest));
  ASSERT_EQ(with_lines.points.size(), threaded.points.size());
  ASSERT_EQ(with_lines.lines.size(), threaded.lines.size());
  for (int v = 0; v < 5; ++v) {
    ASSERT_TRUE(with_lines.T_w_c[v] && threaded.T_w_c[v]);
    EXPECT_EQ(with_lines.T_w_c[v]->Matrix(), threaded.T_w_c[v]->Matrix()) << "view " << v;
  }
}

// Where points are scarce a view's pose is refined with the lines too. Half of the segments of
// one view are moved 6 px across their line (descriptors intact, so they match): those
// observations must be rejected before they can pull the pose, and none reaches the result.
TEST(IncrementalReconstruction, ShiftedSegmentsOfANewViewDoNotEnter) {
  std::mt19937 rng(17);
  const Scene s = MakeScene(6, 300, 60, &rng);
  std::vector<ViewFeatures> views;
  for (int v = 0; v < 6; ++v) views.push_back(Render(s, v, 0.2, &rng));
  constexpr int kShifted = 5;
  std::vector<char> moved(views[kShifted].lines.size(), 0);
  for (int i = 0; i < views[kShifted].lines.size(); i += 2) {
    vision::Segment2d& seg = views[kShifted].lines.segments[i];
    const Eigen::Vector2d d = (seg.tail<2>() - seg.head<2>()).normalized();
    const Eigen::Vector2d n(-d.y(), d.x());
    seg.head<2>() += 6.0 * n;
    seg.tail<2>() += 6.0 * n;
    moved[i] = 1;
  }
  SfmOptions options;
  options.max_points = 50;
  options.point_subset_seed = 3;
  const SfmResult r = Reconstruct(s.K, views, options);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.stats.registered, 6);
  EXPECT_GT(r.stats.lines, 30);
  EXPECT_GT(r.stats.line_refined_registrations, 0);
  int kept_shifted = 0, kept_unshifted = 0;
  for (const SfmLine& l : r.lines) {
    for (const auto& [v, i] : l.observations) {
      if (v != kShifted) continue;
      (moved[i] ? kept_shifted : kept_unshifted) += 1;
    }
  }
  const eval::CameraSetErrors e = Compare(r.T_w_c, s.T_w_c);
  std::printf(
      "shifted segments: %d lines, kept %d shifted and %d other observations of view %d, "
      "max centre error %.2e, max rotation %.4f deg, %d line-refined registrations, %d "
      "rejected line observations\n",
      r.stats.lines, kept_shifted, kept_unshifted, kShifted, e.max_centre, e.max_rotation_deg,
      r.stats.line_refined_registrations, r.stats.rejected_line_observations);
  EXPECT_EQ(kept_shifted, 0);
  EXPECT_GT(kept_unshifted, 10);
  EXPECT_LT(e.max_centre, 0.01);       // of an 8-unit radius (50 points: 3e-3 here)
  EXPECT_LT(e.max_rotation_deg, 0.1);  // 0.053 deg here
}

TEST(IncrementalReconstruction, FailsCleanlyWithoutMatches) {
  std::mt19937 rng(9);
  const Scene s = MakeScene(3, 200, 0, &rng);
  std::vector<ViewFeatures> views(3);  // nothing detected anywhere
  const SfmResult r = Reconstruct(s.K, views);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.message.empty());
  EXPECT_EQ(r.T_w_c.size(), 3u);
  for (const auto& T : r.T_w_c) EXPECT_FALSE(T.has_value());
}

// Three neighbouring Strecha views decoded at 1/4 size (cheap under the sanitizers).
TEST(IncrementalReconstruction, StrechaThreeViews) {
  const fs::path data = fs::path(PLUCKER_SHARED_DATA_DIR) / "strecha-fountain-p11";
  if (!fs::exists(data / "images/0004.jpg")) GTEST_SKIP() << "shared data absent: " << data;
  constexpr int r = 4;
  PinholeIntrinsics K = io::ReadStrechaIntrinsics((data / "images/K.txt").string(), 3072, 2048).K;
  K.fx /= r;
  K.fy /= r;
  K.cx = (K.cx - (r - 1) / 2.0) / r;
  K.cy = (K.cy - (r - 1) / 2.0) / r;
  FeatureOptions fo;
  fo.max_keypoints = 3000;
  fo.min_line_length_px = 20;
  std::vector<ViewFeatures> views;
  std::vector<SE3d> gt;
  for (const char* name : {"0004", "0005", "0006"}) {
    const cv::Mat image =
        io::ReadGrayImage((data / "images" / (std::string(name) + ".jpg")).string(), r);
    views.push_back(ExtractFeatures(image, fo));
    gt.push_back(
        io::ReadStrechaCamera((data / "cameras" / (std::string(name) + ".jpg.camera")).string())
            .T_w_c);
  }
  SfmOptions options;
  options.min_init_angle_deg = 2.0;
  const SfmResult res = Reconstruct(K, views, options);
  ASSERT_TRUE(res.ok) << res.message;
  EXPECT_EQ(res.stats.registered, 3);
  const eval::CameraSetErrors e = Compare(res.T_w_c, gt);
  std::printf(
      "strecha 0004-0006 at 1/4 size: %d points, %d lines, point error %.3f px, line "
      "error %.3f px, max centre error %.1f mm, max rotation error %.3f deg (%.3f deg with the "
      "centres' rotation)\n",
      res.stats.points, res.stats.lines, res.stats.mean_point_error_px,
      res.stats.mean_line_error_px, 1e3 * e.max_centre, e.max_rotation_deg,
      e.max_rotation_centres_deg);
  EXPECT_GT(res.stats.points, 500);
  EXPECT_GT(res.stats.lines, 20);
  EXPECT_LT(e.max_centre, 0.02);  // metres, of a baseline of about 1 m
  EXPECT_LT(e.max_rotation_deg, 0.2);
}

}  // namespace
}  // namespace sfm
}  // namespace plucker
