// The four initialisation entry points: two or N keyframes at known camera poses (visual) or at
// known body states (inertial), then the common start: triangulate, solve, check.
#include <stdexcept>
#include <string>

#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {

using internal::Frame;

// The tail of every initialisation: the keyframes are in place.
InitializationResult SlidingWindowEstimator::Impl::StartWindow(int min_landmarks) {
  InitializationResult result;
  // Newest first; with two keyframes only the newest finds tracks seen twice.
  for (auto it = keyframes.rbegin(); it != keyframes.rend(); ++it)
    Triangulate(**it, &result.points, &result.lines);
  if (result.points + result.lines < min_landmarks) {
    Clear();
    return result;
  }
  WindowFrameResult solve;
  SolveWindow(&solve);
  result.iterations = solve.window_iterations;
  result.final_cost = solve.final_cost;
  result.residuals = solve.residuals;
  result.points = static_cast<int>(points.size());
  result.lines = static_cast<int>(lines.size());
  result.T_w_a = keyframes.front()->T_w_c();
  result.T_w_b = keyframes.back()->T_w_c();
  result.ok = result.points + result.lines >= min_landmarks;
  if (!result.ok) {
    Clear();
    return result;
  }
  // One keyframe (a stereo start): no motion yet.
  prev_T_w_c = keyframes[keyframes.size() > 1 ? keyframes.size() - 2 : 0]->T_w_c();
  last_T_w_c = result.T_w_b;
  last_time = keyframes.back()->input.time;
  peak_turn_rate_deg_s = 0.0;
  return result;
}

InitializationResult SlidingWindowEstimator::Initialize(const FrameInput& a, const SE3d& T_w_a,
                                                        const FrameInput& b, const SE3d& T_w_b,
                                                        int min_landmarks) {
  Impl& m = *impl_;
  m.Clear();
  for (const auto& [input, T_w_c] : {std::make_pair(&a, T_w_a), std::make_pair(&b, T_w_b)}) {
    m.keyframes.push_back(m.MakeFrame(*input, T_w_c));
    m.RememberObservations(m.keyframes.back()->input);
  }
  return m.StartWindow(min_landmarks);
}

InitializationResult SlidingWindowEstimator::Initialize(const std::vector<FrameInput>& frames,
                                                        const std::vector<SE3d>& T_w_c,
                                                        int min_landmarks) {
  Impl& m = *impl_;
  if (m.opt.inertial) throw std::logic_error("Initialize: use InitializeInertial (inertial mode)");
  if (frames.size() != T_w_c.size() || frames.size() < 2 ||
      static_cast<int>(frames.size()) > m.opt.window_size) {
    throw std::invalid_argument("Initialize: " + std::to_string(frames.size()) + " frames and " +
                                std::to_string(T_w_c.size()) +
                                " poses (2 to window_size of each needed)");
  }
  m.Clear();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    m.keyframes.push_back(m.MakeFrame(frames[k], T_w_c[k]));
    m.RememberObservations(m.keyframes.back()->input);
  }
  return m.StartWindow(min_landmarks);
}

InitializationResult SlidingWindowEstimator::InitializeInertial(const FrameInput& a,
                                                                const sensor::BodyState& state_a,
                                                                const FrameInput& b,
                                                                const sensor::BodyState& state_b,
                                                                int min_landmarks) {
  return InitializeInertial(std::vector<FrameInput>{a, b},
                            std::vector<sensor::BodyState>{state_a, state_b}, min_landmarks);
}

InitializationResult SlidingWindowEstimator::InitializeInertial(
    const std::vector<FrameInput>& frames, const std::vector<sensor::BodyState>& states,
    int min_landmarks) {
  Impl& m = *impl_;
  if (!m.opt.inertial) throw std::logic_error("InitializeInertial: not in the inertial mode");
  if (frames.size() != states.size() || frames.size() < 2 ||
      static_cast<int>(frames.size()) > m.opt.window_size) {
    throw std::invalid_argument("InitializeInertial: " + std::to_string(frames.size()) +
                                " frames and " + std::to_string(states.size()) +
                                " states (2 to window_size of each needed)");
  }
  std::vector<std::unique_ptr<ImuPreintegration>> imu;
  for (std::size_t k = 1; k < frames.size(); ++k) {
    imu.push_back(std::make_unique<ImuPreintegration>(
        m.Preintegrate(frames[k - 1].time, frames[k].time, states[k - 1].bias)));
  }
  m.Clear();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    m.keyframes.push_back(m.MakeFrame(frames[k], states[k].T_w_b * m.T_b_c));
    m.RememberObservations(m.keyframes.back()->input);
    m.keyframes.back()->SetState(states[k]);
    m.keyframes.back()->input.stationary =
        m.BelievedStationary(frames[k].stationary, states[k].v_w);
    if (k > 0) m.keyframes.back()->imu_from_previous = std::move(imu[k - 1]);
  }
  Frame& fa = *m.keyframes.front();
  fa.state_prior = true;
  std::copy(fa.v, fa.v + 3, fa.v_prior);
  std::copy(fa.bias, fa.bias + 6, fa.bias_prior);
  const InitializationResult result = m.StartWindow(min_landmarks);
  if (result.ok) m.PruneImu();
  return result;
}

}  // namespace window
}  // namespace plucker
