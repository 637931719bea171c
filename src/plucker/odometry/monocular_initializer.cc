#include "plucker/odometry/monocular_initializer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace plucker {
namespace odometry {
namespace {

using window::FrameInput;
using window::SlidingWindowEstimator;

std::string PairName(int a, int j) {
  return "frames " + std::to_string(a) + "-" + std::to_string(a + j);
}

// The multi-view start: the frames between the two views a = frames[0] and b = frames[b] (at
// most window_size - 3 of them, evenly spaced), localised against the two-view map, become
// keyframes, and one window solve of all of them with their points and lines replaces the two-view
// map (with few points, two views leave the relative pose poorly conditioned and lines constrain
// nothing; three or more views of the lines do). Keeps the two-view map when fewer than one frame
// localises or the solve fails.
void MultiViewStart(const PinholeIntrinsics& K, const window::SlidingWindowOptions& options,
                    const FrameSpan& frames, MonocularStart* s) {
  const int a = s->keyframes[0], b = s->keyframes[1];
  const std::vector<SE3d> ab = s->estimator->KeyframePoses();
  const int between = std::min(b - a - 1, options.window_size - 3);
  if (between < 1) return;
  std::vector<int> kf = {a};
  std::vector<FrameInput> kf_frames = {frames[a]};
  std::vector<SE3d> kf_poses = {ab.front()};
  for (int k = 1; k <= between; ++k) {
    const int m = a + static_cast<int>(std::lround(double(k) * (b - a) / (between + 1)));
    if (m <= kf.back() || m >= b) continue;
    const SE3d guess = InterpolatePose(ab.front(), ab.back(), double(m - a) / double(b - a));
    const std::optional<SE3d> T = s->estimator->Localize(frames[m], guess);
    if (!T) continue;
    kf.push_back(m);
    kf_frames.push_back(frames[m]);
    kf_poses.push_back(*T);
  }
  if (kf.size() < 2) return;
  kf.push_back(b);
  kf_frames.push_back(frames[b]);
  kf_poses.push_back(ab.back());
  auto multi = std::make_unique<SlidingWindowEstimator>(K, options);
  const window::InitializationResult init = multi->Initialize(kf_frames, kf_poses);
  if (!init.ok) return;
  s->estimator = std::move(multi);
  s->init = init;
  s->keyframes = kf;
}

// One start on the pair (0, j): the two-view map, then (multi_view_start) the multi-view solve.
std::optional<MonocularStart> TryStart(const PinholeIntrinsics& K,
                                       const window::SlidingWindowOptions& window_options,
                                       const MonocularStartOptions& options,
                                       const FrameSpan& frames, int j,
                                       const window::TwoViewResult& tv, const StartFrame& where,
                                       std::string* message) {
  MonocularStart s;
  if (where.step_length) s.baseline = *where.step_length * j;
  SE3d T_a_b = tv.T_b_a.Inverse();
  if (s.baseline) T_a_b = SE3d(T_a_b.rotation(), T_a_b.translation() * *s.baseline);
  s.estimator = std::make_unique<SlidingWindowEstimator>(K, window_options);
  s.init = s.estimator->Initialize(frames[0], where.T_w_a, frames[j], where.T_w_a * T_a_b);
  if (!s.init.ok) {
    *message = PairName(where.frame, j) + ": too few landmarks triangulated";
    return std::nullopt;
  }
  s.keyframes = {0, j};
  if (options.multi_view_start) MultiViewStart(K, window_options, frames, &s);
  // Degrees of freedom: 2 per residual block, less 6 per pose but the held first, 3 per point,
  // 4 per line and 1 for the free scale.
  const int kf = static_cast<int>(s.keyframes.size());
  const int dof = 2 * s.init.residuals - (6 * (kf - 1) - 1 + 3 * s.init.points + 4 * s.init.lines);
  s.chi2_z = dof > 0 ? (2.0 * s.init.final_cost - dof) / std::sqrt(2.0 * dof)
                     : std::numeric_limits<double>::infinity();
  return s;
}

}  // namespace

void MonocularStartOptions::Check() const {
  if (max_init_gap < 1) throw std::invalid_argument("MonocularStartOptions: max_init_gap < 1");
  if (max_init_tries < 1) throw std::invalid_argument("MonocularStartOptions: max_init_tries < 1");
  if (!(max_init_chi2_z == max_init_chi2_z))
    throw std::invalid_argument("MonocularStartOptions: max_init_chi2_z is NaN");
}

SE3d InterpolatePose(const SE3d& a, const SE3d& b, double s) {
  return SE3d(a.rotation().slerp(s, b.rotation()),
              (1.0 - s) * a.translation() + s * b.translation());
}

bool StartSearch::Consider(const PinholeIntrinsics& K,
                           const window::SlidingWindowOptions& window_options,
                           const MonocularStartOptions& options, const FrameSpan& frames, int j,
                           const window::TwoViewResult& tv, const StartFrame& where,
                           std::string* message) {
  // Accept the first start whose solve fits at the noise level; after max_init_tries, the best.
  std::optional<MonocularStart> start =
      TryStart(K, window_options, options, frames, j, tv, where, message);
  if (!start) return false;
  ++tries_;
  if (!best_ || start->chi2_z < best_->chi2_z) best_ = std::move(start);
  return best_->chi2_z <= options.max_init_chi2_z || tries_ >= options.max_init_tries;
}

bool StartSearch::Advance(const PinholeIntrinsics& K,
                          const window::SlidingWindowOptions& window_options,
                          const MonocularStartOptions& options, const FrameSpan& frames,
                          const StartFrame& where, bool final, std::string* message) {
  // The widest pair first (all pairs tested, then tried from the widest): under forward motion
  // with few points, short pairs' five-point solutions are often wrong (docs/vo.md, "The start
  // with scarce points"). Else the pairs in order, each tried as soon as it passes.
  for (; next_ < frames.size && next_ <= options.max_init_gap; ++next_) {
    const int j = next_;
    window::TwoViewResult tv =
        window::InitializeTwoView(K, frames[0].points, frames[j].points, options.two_view);
    if (!tv.ok) {
      *message = PairName(where.frame, j) + ": " + tv.message;
      continue;
    }
    if (options.widest_init_pair) {
      candidates_.emplace_back(j, std::move(tv));
    } else if (Consider(K, window_options, options, frames, j, tv, where, message)) {
      ++next_;
      return true;
    }
  }
  if (!final && next_ <= options.max_init_gap) return false;
  for (auto c = candidates_.rbegin(); c != candidates_.rend(); ++c)
    if (Consider(K, window_options, options, frames, c->first, c->second, where, message)) break;
  return true;
}

std::optional<MonocularStart> StartSearch::Take() {
  if (best_) best_->tries = tries_;
  std::optional<MonocularStart> best = std::move(best_);
  *this = StartSearch();
  return best;
}

}  // namespace odometry
}  // namespace plucker
