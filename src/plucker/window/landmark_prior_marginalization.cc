// SlidingWindowOptions::PriorBlocks::kLandmarks: the oldest keyframe k0 goes into a prior on the
// landmarks it observed (marginalization_strategy_internal.h; the file comment of
// sliding_window_estimator.h), with k0's observations of the lines that stay retained at k0's pose.
#include <algorithm>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include "plucker/window/marginalization_strategy_internal.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {
namespace internal {
namespace {

using Impl = SlidingWindowEstimator::Impl;

// SlidingWindowOptions::retain_line_observer_poses applies (not in the inertial mode).
bool RetainLinePoses(const Impl& w) {
  return w.opt.use_lines && w.opt.keep_marginalized_lines && w.opt.retain_line_observer_poses &&
         !w.opt.inertial;
}

class LandmarkPrior final : public MarginalizationStrategy {
 public:
  void MarginalizeOldest(Impl& w, WindowFrameResult* result) const override;
  // The prior keeps landmarks in the reduced system: sparse.
  ceres::LinearSolverType WindowLinearSolver() const override { return ceres::SPARSE_SCHUR; }
};

void LandmarkPrior::MarginalizeOldest(Impl& w, WindowFrameResult* result) const {
  Frame* f0 = w.keyframes.front().get();
  std::set<int> points_kept, lines_kept;  // observed by a remaining keyframe
  for (std::size_t k = 1; k < w.keyframes.size(); ++k) {
    const Frame& f = *w.keyframes[k];
    for (std::size_t i = 0; i < f.input.points.size(); ++i)
      if (!f.point_outlier[i]) points_kept.insert(f.input.points[i].point_id);
    for (std::size_t i = 0; i < f.input.segments.size(); ++i)
      if (!f.segment_outlier[i]) lines_kept.insert(f.input.segments[i].line_id);
  }
  std::vector<ResidualSpec> residuals;
  w.AppendFrameResiduals(f0, true, w.opt.use_lines && w.opt.keep_marginalized_lines, &residuals);
  w.UseExtrinsicBlock(&residuals);  // the extrinsic stays: k0's information on it enters the prior
  // Retained poses: k0's observations of the lines that stay are kept as they are, and k0's
  // pose with them (not eliminated); the retained observations of the lines that leave now
  // join the marginalization, and a retained pose left without observations leaves with them.
  std::unique_ptr<RetainedPose> k0_retained;
  std::set<int> lines_leaving;
  std::vector<const RetainedPose*> retained_out;  // retained poses that leave now
  if (RetainLinePoses(w)) {
    std::vector<ResidualSpec> rest;
    for (ResidualSpec& r : residuals) {
      const bool kept_line = !r.is_point && r.frame == f0 &&
                             lines_kept.count(f0->input.segments[r.observation].line_id);
      if (!kept_line) {
        rest.push_back(std::move(r));
        continue;
      }
      if (r.right) continue;  // stereo: a retained pose holds left observations only (dropped)
      if (!k0_retained) k0_retained = std::make_unique<RetainedPose>();
      k0_retained->segments.push_back(f0->input.segments[r.observation]);
      ++result->held_line_observations;
    }
    residuals.swap(rest);
    for (const auto& [id, l] : w.lines)
      if (!lines_kept.count(id)) lines_leaving.insert(id);
    // A retained pose leaves when it observes no line that stays, or, beyond
    // max_retained_poses, the oldest leave: their observations of the lines that stay are
    // dropped (or, retained_overflow_into_prior, enter the prior with the lines at their
    // estimates of that moment); those of the lines that leave are marginalized with them.
    const int over = static_cast<int>(w.retained.size()) + (k0_retained ? 1 : 0) -
                     std::max(w.opt.max_retained_poses, 0);
    for (std::size_t i = 0; i < w.retained.size(); ++i) {
      const RetainedPose* rp = w.retained[i].get();
      const bool observes = std::any_of(
          rp->segments.begin(), rp->segments.end(), [&](const sensor::SegmentObservation& seg) {
            return w.lines.count(seg.line_id) && !lines_leaving.count(seg.line_id);
          });
      const bool leaves = !observes || static_cast<int>(i) < over;
      if (leaves) retained_out.push_back(rp);
      const bool all = leaves && w.opt.retained_overflow_into_prior;
      if (leaves && !all) {
        for (const sensor::SegmentObservation& seg : rp->segments)
          if (w.lines.count(seg.line_id) && !lines_leaving.count(seg.line_id))
            ++result->dropped_retained_line_observations;
      }
      w.AppendRetainedResiduals(&residuals, all ? nullptr : &lines_leaving, rp);
    }
  }
  if (w.opt.inertial) {
    w.AppendInertialResiduals(0, &residuals);  // the first keyframe's priors
    w.AppendInertialResiduals(1, &residuals);  // the IMU factor to the successor (and its priors)
  }
  if (w.opt.use_lines && !w.opt.keep_marginalized_lines) {
    for (std::size_t i = 0; i < f0->input.segments.size(); ++i)
      if (!f0->segment_outlier[i] && w.lines.count(f0->input.segments[i].line_id))
        ++result->dropped_line_observations;
  }
  // Drop residuals that cannot be evaluated.
  residuals.erase(std::remove_if(residuals.begin(), residuals.end(),
                                 [](const ResidualSpec& r) {
                                   std::vector<const double*> params(r.blocks.begin(),
                                                                     r.blocks.end());
                                   std::vector<double> res(r.cost->num_residuals());
                                   return !r.cost->Evaluate(params.data(), res.data(), nullptr);
                                 }),
                  residuals.end());
  if (w.prior) {
    ResidualSpec r;
    r.cost.reset(w.prior->CreateCostFunction());
    r.robust = false;
    r.blocks = w.prior_blocks;
    residuals.push_back(std::move(r));
  }
  // Blocks touched, and the ones to remove.
  std::vector<double*> touched;
  for (const ResidualSpec& r : residuals)
    for (double* b : r.blocks)
      if (std::find(touched.begin(), touched.end(), b) == touched.end()) touched.push_back(b);
  std::vector<double*> remove;
  std::vector<int> remove_points, remove_lines;
  for (const auto& [id, p] : w.points) {
    if (points_kept.count(id)) continue;
    remove_points.push_back(id);
    if (std::find(touched.begin(), touched.end(), p->p) != touched.end()) remove.push_back(p->p);
  }
  for (const auto& [id, l] : w.lines) {
    if (lines_kept.count(id)) continue;
    remove_lines.push_back(id);
    if (std::find(touched.begin(), touched.end(), l->block) != touched.end())
      remove.push_back(l->block);
  }
  const bool pose_touched = std::find(touched.begin(), touched.end(), f0->pose) != touched.end();
  if (pose_touched && !k0_retained) remove.push_back(f0->pose);
  for (const RetainedPose* rp : retained_out)
    if (std::find(touched.begin(), touched.end(), rp->pose) != touched.end())
      remove.push_back(const_cast<double*>(rp->pose));
  for (double* b : {f0->v, f0->bias}) {
    if (std::find(touched.begin(), touched.end(), b) != touched.end()) remove.push_back(b);
  }

  std::unique_ptr<MarginalizationPrior> next;
  std::vector<double*> next_blocks;
  if (pose_touched) {
    // Linearise at the first estimates (FEJ): a scratch copy of every block.
    std::vector<std::vector<double>> scratch(touched.size());
    std::unordered_map<double*, double*> to_scratch;
    std::unordered_map<const double*, double*> to_real;
    std::vector<MarginalizationBlock> blocks;
    for (std::size_t i = 0; i < touched.size(); ++i) {
      const BlockKind kind = w.KindOf(touched[i]);
      const int n = w.AmbientSize(kind);
      const auto it = w.fe.find(touched[i]);
      if (w.opt.first_estimate_jacobians && it != w.fe.end()) {
        scratch[i] = it->second;
      } else {
        scratch[i].assign(touched[i], touched[i] + n);
      }
      to_scratch[touched[i]] = scratch[i].data();
      to_real[scratch[i].data()] = touched[i];
      blocks.push_back({scratch[i].data(), n, w.ManifoldOf(kind)});
    }
    std::vector<MarginalizationResidual> mres;
    for (const ResidualSpec& r : residuals) {
      MarginalizationResidual m;
      m.cost = r.cost.get();
      m.loss = r.robust ? w.loss.get() : nullptr;
      for (double* b : r.blocks) m.blocks.push_back(to_scratch[b]);
      mres.push_back(std::move(m));
    }
    std::vector<double*> mremove;
    for (double* b : remove) mremove.push_back(to_scratch[b]);
    try {
      next = std::make_unique<MarginalizationPrior>(
          MarginalizationPrior::Build(blocks, mres, mremove, w.opt.marginalization));
      for (const MarginalizationBlock& b : next->KeptBlocks())
        next_blocks.push_back(to_real[b.values]);
    } catch (const std::invalid_argument&) {
      next.reset();
      result->marginalization_failed = true;
    }
  }
  w.InstallPrior(std::move(next), next_blocks, result);
  w.retained.erase(std::remove_if(w.retained.begin(), w.retained.end(),
                                  [&](const std::unique_ptr<RetainedPose>& rp) {
                                    return std::find(retained_out.begin(), retained_out.end(),
                                                     rp.get()) != retained_out.end();
                                  }),
                   w.retained.end());
  if (k0_retained) {
    // k0's pose block moves to the retained storage (the prior and FEJ refer to it there).
    std::copy(f0->pose, f0->pose + 7, k0_retained->pose);
    for (double*& b : w.prior_blocks)
      if (b == f0->pose) b = k0_retained->pose;
    const auto it = w.fe.find(f0->pose);
    if (it != w.fe.end()) {
      w.fe[k0_retained->pose] = it->second;
      w.fe.erase(f0->pose);
    }
    w.retained.push_back(std::move(k0_retained));
  }
  w.DropOldestKeyframe(remove_points, remove_lines, result);
}

}  // namespace

std::unique_ptr<MarginalizationStrategy> MakeLandmarkPrior() {
  return std::make_unique<LandmarkPrior>();
}

}  // namespace internal
}  // namespace window
}  // namespace plucker
