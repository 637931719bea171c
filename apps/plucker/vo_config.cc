#include "vo_config.h"

#include <stdexcept>

namespace plucker {
namespace app {
namespace {

using Prior = window::SlidingWindowOptions::PriorBlocks;

const std::vector<OptionSpec>& SharedSpecs() {
  static const std::vector<OptionSpec> specs = {
      {"window.size", "keyframes", "keyframes in the window", Between(2, 1000)},
      {"window.iterations", "", "solver iterations per window solve", Between(1, 1000)},
      {"window.keyframe_parallax_px", "px", "keyframe at this median parallax", AtLeast(0.0)},
      {"window.min_tracked", "", "keyframe under this many tracked landmarks", AtLeast(0)},
      {"window.min_tracked_ratio", "", "keyframe under this share of the observations tracked",
       Between(0.0, 1.0)},
      {"window.min_line_views", "keyframes", "keyframes observing a new line", Between(2, 1000)},
      {"window.two_view_line_sigma_scale", "",
       "line sigma times this while two views only see the line (1: off)", AtLeast(1.0)},
      {"window.two_view_min_plane_angle_px", "px",
       "a line from two views: its planes' angle at least this many pixels' angles (0: off)",
       AtLeast(0.0)},
      {"points.max_tracks", "", "live point tracks kept (images)", AtLeast(1)},
      {"points.min_distance_px", "px", "between point tracks (images)", AtLeast(0.0)},
      {"points.detect_below_share", "",
       "new corners only when fewer than this share of points.max_tracks survived (1: always)",
       Range{0.0, 1.0, true}},
      {"lines.max_segments", "", "longest segments kept per image (0: all)", AtLeast(0)},
      {"lines.detection_scale", "", "image scale of the segment detection", Range{0.0, 1.0, true}},
      {"lines.flow_samples", "", "points per segment followed by optical flow (0: no flow gate)",
       Between(0, 1000)},
  };
  return specs;
}

// The rows every visual pipeline shares, with one spelling and one range (vio_config.cc uses the
// same keys for its own members).
std::vector<OptionRow<VoConfig>> MakeRows() {
  OptionRows<VoConfig> t;
  t.BoolWith(
      "use_lines", kUseLinesDoc,
      [](const VoConfig& c) { return c.window.use_lines && c.frontend.use_lines; },
      [](VoConfig* c, bool on) { c->window.use_lines = c->frontend.use_lines = on; });
  t.Value(SharedVisualOption("window.size"), PLUCKER_OPTION_MEMBER(window.window_size));
  t.Value(SharedVisualOption("window.iterations"), PLUCKER_OPTION_MEMBER(window.max_iterations));
  t.Value("window.tracking_iterations", "", "iterations of the motion-only pose", Between(1, 1000),
          PLUCKER_OPTION_MEMBER(window.max_tracking_iterations));
  t.Value(SharedVisualOption("window.keyframe_parallax_px"),
          PLUCKER_OPTION_MEMBER(window.keyframe_parallax_px));
  t.Value(SharedVisualOption("window.min_tracked"), PLUCKER_OPTION_MEMBER(window.min_tracked));
  t.Value(SharedVisualOption("window.min_tracked_ratio"),
          PLUCKER_OPTION_MEMBER(window.min_tracked_ratio));
  t.Bool("window.tracked_ratio_mapped_segments",
         "min_tracked_ratio counts only the segments of mapped lines (false: all segments)",
         PLUCKER_OPTION_MEMBER(window.tracked_ratio_mapped_segments));
  t.Value("window.loss_scale", "sigma", "Huber scale of the reprojection residuals", Above(0.0),
          PLUCKER_OPTION_MEMBER(window.loss_scale));
  t.Value("window.point_sigma_px", "px", "pixel sigma of the point reprojection residuals",
          Above(0.0), PLUCKER_OPTION_MEMBER(window.point_sigma_px));
  t.Value("window.line_sigma_px", "px", "pixel sigma of the line (endpoint-to-line) residuals",
          Above(0.0), PLUCKER_OPTION_MEMBER(window.line_sigma_px));
  t.Value("window.outlier_sigmas", "sigma", "observations above this are culled", Above(0.0),
          PLUCKER_OPTION_MEMBER(window.outlier_sigmas));
  t.Bool("window.keep_marginalized_lines",
         "keep k0's line information in the prior (false: dropped, as PL-VIO)",
         PLUCKER_OPTION_MEMBER(window.keep_marginalized_lines));
  t.Bool("window.retain_line_observer_poses",
         "k0's pose kept while lines that stay have observations from it (false: those in the "
         "prior)",
         PLUCKER_OPTION_MEMBER(window.retain_line_observer_poses));
  t.Value("window.max_retained_poses", "", "retained observer poses at most", AtLeast(0),
          PLUCKER_OPTION_MEMBER(window.max_retained_poses));
  t.Bool("window.retained_overflow_into_prior",
         "lines of a retained pose beyond the maximum into the prior (false: dropped)",
         PLUCKER_OPTION_MEMBER(window.retained_overflow_into_prior));
  t.Bool("window.first_estimate_jacobians", "FEJ on the prior's blocks",
         PLUCKER_OPTION_MEMBER(window.first_estimate_jacobians));
  t.Bool("window.condition_far_lines", "lines in their anchor frame (false: the world frame)",
         PLUCKER_OPTION_MEMBER(window.condition_far_lines));
  t.BoolWith(
      "window.prior_on_poses_only", kPriorOnPosesOnlyDoc,
      [](const VoConfig& c) { return c.window.prior_blocks == Prior::kPoses; },
      [](VoConfig* c, bool on) {
        c->window.prior_blocks = on ? Prior::kPoses : Prior::kLandmarks;
      });
  t.Value("window.line_min_angle_deg", "deg", "angle between the planes of a new line",
          Between(0.0, 90.0), PLUCKER_OPTION_MEMBER(window.line_triangulation.min_plane_angle_deg));
  t.Value(SharedVisualOption("window.min_line_views"),
          PLUCKER_OPTION_MEMBER(window.min_line_views));
  t.Value(SharedVisualOption("window.two_view_line_sigma_scale"),
          PLUCKER_OPTION_MEMBER(window.two_view_line_sigma_scale));
  t.Value(SharedVisualOption("window.two_view_min_plane_angle_px"),
          PLUCKER_OPTION_MEMBER(window.two_view_min_plane_angle_px));
  t.Bool("window.recheck_two_view_lines", kRecheckTwoViewLinesDoc,
         PLUCKER_OPTION_MEMBER(window.recheck_two_view_lines));
  t.Value("window.max_new_line_rms_px", "px",
          "RMS endpoint-to-line distance of a new line (0: no test)", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(window.max_new_line_rms_px));
  t.Value("window.point_min_parallax_deg", "deg", "parallax of a new point", Between(0.0, 90.0),
          PLUCKER_OPTION_MEMBER(window.point_triangulation.min_parallax_deg));
  t.Value("window.start_scale_sigma", "",
          "relative sigma holding the start's scale until the first marginalization (0: off)",
          AtLeast(0.0), PLUCKER_OPTION_MEMBER(window.start_scale_sigma));
  t.Value("init.max_gap", "frames", "frames searched for the second view of the start", AtLeast(1),
          PLUCKER_OPTION_MEMBER(start.max_init_gap));
  t.Value("init.min_common_tracks", "", "point tracks seen in both views of a start", AtLeast(5),
          PLUCKER_OPTION_MEMBER(start.two_view.min_common_tracks));
  t.Value("init.min_inliers", "", "essential-matrix inliers of a start", AtLeast(5),
          PLUCKER_OPTION_MEMBER(start.two_view.min_inliers));
  t.Value("init.min_parallax_px", "px", "rotation-compensated parallax of a start", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(start.two_view.min_parallax_px));
  t.Value("init.min_translation_parallax_px", "px",
          "parallax of a start left after the best pure rotation (0: not tested)", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(start.two_view.min_translation_parallax_px));
  t.Value("init.min_triangulation_angle_deg", "deg",
          "median ray angle of a start's inliers (0: not tested)", Between(0.0, 90.0),
          PLUCKER_OPTION_MEMBER(start.two_view.min_triangulation_angle_deg));
  t.Value("init.max_depth_baselines", "",
          "a start's inliers nearer than this many baselines (cheirality test)", Above(0.0),
          PLUCKER_OPTION_MEMBER(start.two_view.max_depth_baselines));
  t.Bool("init.widest_pair", "start on the widest pair that passes, not the first",
         PLUCKER_OPTION_MEMBER(start.widest_init_pair));
  t.Bool("init.multi_view", "frames between the two views as keyframes of the start",
         PLUCKER_OPTION_MEMBER(start.multi_view_start));
  t.Value("init.max_chi2_z", "",
          "accept a start whose chi-square (chi2 - dof) / sqrt(2 dof) is at most this", AnyValue(),
          PLUCKER_OPTION_MEMBER(start.max_init_chi2_z));
  t.Value("init.max_tries", "", "starts tried from one first view before the best is taken",
          AtLeast(1), PLUCKER_OPTION_MEMBER(start.max_init_tries));
  t.Value("init.max_lost_frames", "frames",
          "lost frames in a row before a new start (as --max-lost)", AtLeast(1),
          PLUCKER_OPTION_MEMBER(max_lost_frames));
  t.Value(SharedVisualOption("points.max_tracks"),
          PLUCKER_OPTION_MEMBER(frontend.points.target_count));
  t.Value(SharedVisualOption("points.min_distance_px"),
          PLUCKER_OPTION_MEMBER(frontend.points.min_distance_px));
  t.Value(SharedVisualOption("points.detect_below_share"),
          PLUCKER_OPTION_MEMBER(frontend.points.detect_below_share));
  t.Value("points.ransac_threshold_px", "px", "epipolar RANSAC threshold", Above(0.0),
          PLUCKER_OPTION_MEMBER(frontend.points.ransac_threshold_px));
  t.Value(SharedVisualOption("lines.max_segments"), PLUCKER_OPTION_MEMBER(frontend.max_segments));
  t.Value("lines.min_segment_px", "px", "shorter segments are not tracked", AtLeast(0.0),
          PLUCKER_OPTION_MEMBER(frontend.min_segment_px));
  t.Value(SharedVisualOption("lines.detection_scale"),
          PLUCKER_OPTION_MEMBER(frontend.detection_scale));
  t.Value(SharedVisualOption("lines.flow_samples"),
          PLUCKER_OPTION_MEMBER(frontend.lines.flow_samples));
  t.Value("lines.max_lost_frames", "frames", "frames a line track may skip", Between(0, 1000),
          PLUCKER_OPTION_MEMBER(frontend.lines.max_lost_frames));
  return t.Take();
}

}  // namespace

const char* const kUseLinesDoc = "lines: detected, tracked and in the window";
const char* const kPriorOnPosesOnlyDoc =
    "the poses-only prior (fast) instead of the prior on the landmarks";
const char* const kRecheckTwoViewLinesDoc =
    "a two-view line triangulated again at its third keyframe (dropped if that fails)";

const OptionSpec& SharedVisualOption(const std::string& key) {
  for (const OptionSpec& s : SharedSpecs())
    if (key == s.key) return s;
  throw std::logic_error("no shared visual option '" + key + "'");
}

VoConfig FeaturesVoConfig() {
  VoConfig c;
  c.start.two_view.min_common_tracks =
      8;  // the scarce-point scenes have about 10 point tracks a frame
  c.start.two_view.min_inliers = 8;
  return c;
}

VoConfig ImageVoConfig() {
  VoConfig c;
  c.start.widest_init_pair = false;  // the start as measured on the KITTI clip: the first pair that
  c.start.multi_view_start = false;  // passes, two views
  c.start.max_init_tries = 1;
  // The start must see translation (MH_05: docs/vo.md): no depth limit of 50 baselines in the
  // cheirality count, 5 px left after the best pure rotation, 0.5 deg median ray angle.
  c.start.two_view.max_depth_baselines = 1e4;
  c.start.two_view.min_translation_parallax_px = 5.0;
  c.start.two_view.min_triangulation_angle_deg = 0.5;
  c.window.line_triangulation.min_plane_angle_deg = 10.0;
  // New points from 0.25 deg of parallax: slow flight in a deep hall (MH_05 take-off, 0.5-2 cm a
  // frame at 3-10 m) gave 1 deg too late, tracks ended first and the map ran dry (docs/vo.md).
  c.window.point_triangulation.min_parallax_deg = 0.25;
  c.window.prior_blocks = Prior::kPoses;
  c.window.keyframe_parallax_px = 20.0;
  c.window.min_tracked_ratio = 0.2;
  // The tracked ratio of the segments of mapped lines only: an image has 60 segments, hardly any
  // of them a line (the MH_05 clip: 17 lines from 610 tries, 2.7 in the window), and counting them
  // all took keyframes at other frames than without lines (MH_05 ATE 0.0289 m against 0.0257 m
  // points only, KITTI 0.0366 against 0.0259; with this 0.0265 and 0.0259: docs/results/vo.md).
  // Not for features folders: the simulated room, seed 1, went from 0.035 m to 0.35 m.
  c.window.tracked_ratio_mapped_segments = true;
  // Segments are detected at lines.detection_scale 0.5: one pixel there is two in the image.
  // Measured (docs/results/vo.md): MH_05 lines 0.0265 m with 1 px, 0.0248-0.0255 with 1.5-4 px
  // (points 0.0257); KITTI with 5 deg lines (the only setting where lines enter its window)
  // 0.0278 -> 0.0265 m.
  c.window.line_sigma_px = 2.0;
  c.frontend.points.target_count = 200;
  c.frontend.points.min_distance_px = 20.0;
  c.frontend.max_segments = 60;
  c.frontend.detection_scale = 0.5;
  c.frontend.lines.flow_samples = 3;
  return c;
}

const OptionsTable<VoConfig>& VoOptions() {
  static const OptionsTable<VoConfig> table(
      TableText{"vo",
                "apps/plucker/vo_config.cc",
                {{"window", "the sliding window, window/sliding_window_estimator.h"},
                 {"init", "the monocular start and restart, odometry/monocular_initializer.h"},
                 {"points", "point tracks of --images, vision/image_frontend.h"},
                 {"lines", "segments of --images, vision/image_frontend.h"}},
                {{"window.use_lines", "use_lines"}, {"lines.enabled", "use_lines"}}},
      MakeRows());
  return table;
}

std::string VoImageDefaultNote(const std::string& key) {
  const OptionRow<VoConfig>* row = VoOptions().Find(key);
  if (row == nullptr) return "";
  const std::string features = row->get(FeaturesVoConfig()), images = row->get(ImageVoConfig());
  return features == images ? "" : "images: " + images;
}

void ApplyVoConfigYaml(const std::string& text, const std::string& name, VoConfig* config) {
  VoOptions().Apply(text, name, config);
}

void LoadVoConfig(const std::string& path, VoConfig* config) { VoOptions().Load(path, config); }

}  // namespace app
}  // namespace plucker
