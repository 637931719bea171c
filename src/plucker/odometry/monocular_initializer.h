// The start of monocular odometry (a map from images alone): for a first view a and the later
// frames a + 1 .. a + max_init_gap,
//   two-view    the essential matrix of the point tracks of a and b
//   (window/two_view_initialization.h),
//               for every b; scale |t_ab| = 1, or chained to the previous map's speed;
//   order       the widest pair first (widest_init_pair), else the pairs in frame order;
//   multi-view  the frames between a and b (at most window_size - 3, evenly spaced) localised
//               against the two-view map join one window solve of all of them (multi_view_start);
//   accept      the first start whose solve passes a chi-square test, (chi2 - dof) / sqrt(2 dof)
//               <= max_init_chi2_z; after max_init_tries starts, the one with the smallest.
// Pure computation on the frames given (no I/O, no clock).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "plucker/geometry/camera.h"
#include "plucker/geometry/se3.h"
#include "plucker/window/sliding_window_estimator.h"
#include "plucker/window/two_view_initialization.h"

namespace plucker {
namespace odometry {

struct MonocularStartOptions {
  window::TwoViewOptions two_view;  // the two-view test of a start's pair
  int max_init_gap = 30;            // frames searched for the second view of a two-view start
  bool widest_init_pair = true;     // from a first view, the widest second view that passes first
  bool multi_view_start = true;     // the frames between the two views join the start's solve
  // A start is accepted when its solve passes the chi-square test: (chi2 - dof) / sqrt(2 dof) of
  // its whitened residuals at most this (2.33: 1 % of the starts that fit at the noise level
  // refused); after max_init_tries pairs of one first view, the one with the smallest.
  double max_init_chi2_z = 2.33;
  int max_init_tries = 30;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// Where a new map is put: the first map at the identity with |t_ab| = 1; a later one at the pose
// predicted for its first view, |t_ab| = step_length x (frame gap of the pair).
struct StartFrame {
  SE3d T_w_a;
  std::optional<double> step_length;  // distance per frame of the previous map's last frames
  int frame = 0;                      // the sequence's number of the first view (messages)
};

struct MonocularStart {
  std::unique_ptr<window::SlidingWindowEstimator> estimator;  // initialised on the keyframes
  std::vector<int> keyframes;  // indices into the frames given, oldest first (a, ..., b)
  window::InitializationResult init;
  std::optional<double> baseline;  // |t_ab| when chained
  int tries = 0;                   // starts solved for this first view
  // (chi2 - dof) / sqrt(2 dof) of the start's whitened residuals (chi2 = 2 cost), about N(0, 1)
  // for a start that fits at the noise level.
  double chi2_z = 0.0;
};

// Frames [0, size) of a buffer: the first view and the later frames that have arrived.
struct FrameSpan {
  const window::FrameInput* data = nullptr;
  int size = 0;
  const window::FrameInput& operator[](int k) const { return data[k]; }
};

// The start search of one first view, fed as its later frames arrive: each new frame's pair is
// tested at once (and, pairs in order, tried at once: an accepted start ends the search); the
// widest-first order waits for all max_init_gap later frames. Same starts as a search run on all
// frames at once.
class StartSearch {
 public:
  // frames[0]: the first view; frames[1 ..]: the later frames so far (those after
  // max_init_gap ignored). final: no more frames will come. Returns true when the search is
  // decided: Take() then gives the start, or nullopt (the reason, the last pair's, in *message).
  bool Advance(const PinholeIntrinsics& K, const window::SlidingWindowOptions& window_options,
               const MonocularStartOptions& options, const FrameSpan& frames,
               const StartFrame& where, bool final, std::string* message);
  std::optional<MonocularStart> Take();

 private:
  bool Consider(const PinholeIntrinsics& K, const window::SlidingWindowOptions& window_options,
                const MonocularStartOptions& options, const FrameSpan& frames, int j,
                const window::TwoViewResult& tv, const StartFrame& where, std::string* message);

  int next_ = 1;  // the next second view to test
  int tries_ = 0;
  std::vector<std::pair<int, window::TwoViewResult>> candidates_;  // widest first: the passed
  std::optional<MonocularStart> best_;
};

SE3d InterpolatePose(const SE3d& a, const SE3d& b, double s);

}  // namespace odometry
}  // namespace plucker
