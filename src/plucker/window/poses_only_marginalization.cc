// SlidingWindowOptions::PriorBlocks::kPoses (the DSO pattern): the landmarks of the oldest
// keyframe k0 whose track has ended are eliminated one by one into small priors on their
// observers' poses, then k0's blocks from those; the prior lives on poses (and, inertial,
// velocities and biases) only (marginalization_strategy_internal.h).
#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "plucker/window/marginalization_strategy_internal.h"
#include "plucker/window/window_internal.h"

namespace plucker {
namespace window {
namespace internal {
namespace {

using Impl = SlidingWindowEstimator::Impl;

// The tracks whose landmark went into a poses-only prior with all its window observations:
// retired (never triangulated again), or with retire_marginalized_tracks = false those
// observations are marked used (outliers) so that the track can start a new landmark from
// later keyframes only (a revisited scene point of a features folder, whose ids are scene ids)
// without counting them twice.
void ConsumeTracks(Impl& w, const std::vector<int>& point_ids, const std::vector<int>& line_ids) {
  if (w.opt.retire_marginalized_tracks) {
    w.retired_points.insert(point_ids.begin(), point_ids.end());
    w.retired_lines.insert(line_ids.begin(), line_ids.end());
    return;
  }
  const std::set<int> pset(point_ids.begin(), point_ids.end());
  const std::set<int> lset(line_ids.begin(), line_ids.end());
  for (auto& f : w.keyframes) {
    for (std::size_t i = 0; i < f->input.points.size(); ++i)
      if (pset.count(f->input.points[i].point_id)) f->point_outlier[i] = 1;
    for (std::size_t i = 0; i < f->input.segments.size(); ++i)
      if (lset.count(f->input.segments[i].line_id)) f->segment_outlier[i] = 1;
  }
}

class PosesOnlyPrior final : public MarginalizationStrategy {
 public:
  void MarginalizeOldest(Impl& w, WindowFrameResult* result) const override;
  // Every landmark is eliminated and the reduced system (poses, and velocities and biases in the
  // inertial mode) is small: dense, its Cholesky factorization costs less than SuiteSparse's
  // symbolic work (corridor, 600 frames: the linear solver 2.5 s -> 1.2 s over the run, the same
  // trajectory).
  ceres::LinearSolverType WindowLinearSolver() const override { return ceres::DENSE_SCHUR; }
};

// PriorBlocks::kPoses: see the option. Landmarks of k0 whose track has ended are eliminated one
// by one into small priors on their observers' poses (at the first estimates), then k0's pose
// is eliminated from those, its pose prior and the previous prior.
void PosesOnlyPrior::MarginalizeOldest(Impl& w, WindowFrameResult* result) const {
  Frame* f0 = w.keyframes.front().get();
  const Frame* newest = w.keyframes.back().get();
  std::set<int> points_newest, lines_newest, points_kept, lines_kept;
  for (std::size_t k = 1; k < w.keyframes.size(); ++k) {
    const Frame& f = *w.keyframes[k];
    const bool is_newest = &f == newest;
    for (std::size_t i = 0; i < f.input.points.size(); ++i) {
      if (f.point_outlier[i]) continue;
      points_kept.insert(f.input.points[i].point_id);
      if (is_newest) points_newest.insert(f.input.points[i].point_id);
    }
    for (std::size_t i = 0; i < f.input.segments.size(); ++i) {
      if (f.segment_outlier[i]) continue;
      lines_kept.insert(f.input.segments[i].line_id);
      if (is_newest) lines_newest.insert(f.input.segments[i].line_id);
    }
  }
  // Landmarks leaving the window: observed by no remaining keyframe, or by k0 and no longer
  // tracked by the newest keyframe.
  std::set<const double*> leaving;
  std::vector<int> remove_points, remove_lines, retire_point, retire_line;
  for (std::size_t i = 0; i < f0->input.points.size(); ++i) {
    const int id = f0->input.points[i].point_id;
    if (f0->point_outlier[i] || !w.points.count(id)) continue;
    if (points_newest.count(id)) {
      ++result->dropped_point_observations;
    } else {
      leaving.insert(w.points[id]->p);
      retire_point.push_back(id);
    }
  }
  for (std::size_t i = 0; i < f0->input.segments.size(); ++i) {
    const int id = f0->input.segments[i].line_id;
    if (f0->segment_outlier[i] || !w.lines.count(id)) continue;
    if (lines_newest.count(id) || !w.opt.keep_marginalized_lines) {
      ++result->dropped_line_observations;
    } else {
      leaving.insert(w.lines[id]->block);
      retire_line.push_back(id);
    }
  }
  for (const auto& [id, p] : w.points)
    if (!points_kept.count(id) || leaving.count(p->p)) remove_points.push_back(id);
  for (const auto& [id, l] : w.lines)
    if (!lines_kept.count(id) || leaving.count(l->block)) remove_lines.push_back(id);

  // Every window residual of the leaving landmarks, grouped by landmark.
  std::vector<ResidualSpec> all;
  for (auto& f : w.keyframes) w.AppendFrameResiduals(f.get(), true, w.opt.use_lines, &all);
  w.UseExtrinsicBlock(&all);  // the landmark is the last block
  // In the order of first observation (not of the addresses: the run is deterministic).
  std::vector<std::pair<const double*, std::vector<ResidualSpec*>>> by_landmark;
  std::map<const double*, std::size_t> landmark_index;
  for (ResidualSpec& r : all) {
    if (r.frame == nullptr || !leaving.count(r.blocks.back())) continue;
    std::vector<const double*> params(r.blocks.begin(), r.blocks.end());
    double res[2];
    if (!r.cost->Evaluate(params.data(), res, nullptr)) continue;
    const auto [it, added] = landmark_index.emplace(r.blocks.back(), by_landmark.size());
    if (added) by_landmark.push_back({r.blocks.back(), {}});
    by_landmark[it->second].second.push_back(&r);
  }
  // Scratch copies of the keyframe blocks (poses; velocities and biases in the inertial mode)
  // at their first estimates (FEJ), else their current values.
  std::map<double*, std::vector<double>> scratch;
  std::map<double*, BlockKind> scratch_kind;
  auto scratch_of = [&](double* block) {
    auto it = scratch.find(block);
    if (it != scratch.end()) return it->second.data();
    const BlockKind kind = w.KindOf(block);
    const auto fe_it = w.fe.find(block);
    std::vector<double> v = w.opt.first_estimate_jacobians && fe_it != w.fe.end()
                                ? fe_it->second
                                : std::vector<double>(block, block + w.AmbientSize(kind));
    scratch_kind[block] = kind;
    return scratch.emplace(block, std::move(v)).first->second.data();
  };
  std::map<const double*, double*> to_real;
  std::vector<std::unique_ptr<MarginalizationPrior>> landmark_priors;
  for (auto& [landmark, list] : by_landmark) {
    const BlockKind kind = w.KindOf(landmark);
    const int n = w.AmbientSize(kind);
    std::vector<double> lm(landmark, landmark + n);
    std::vector<MarginalizationBlock> blocks = {{lm.data(), n, w.ManifoldOf(kind)}};
    std::vector<MarginalizationResidual> mres;
    for (ResidualSpec* r : list) {
      MarginalizationResidual m{r->cost.get(), w.loss.get(), {}};
      // The pose (and the extrinsic, the time offset).
      for (std::size_t b = 0; b + 1 < r->blocks.size(); ++b) {
        double* pose = scratch_of(r->blocks[b]);
        to_real[pose] = r->blocks[b];
        const BlockKind k = scratch_kind.at(r->blocks[b]);
        if (std::none_of(blocks.begin(), blocks.end(),
                         [&](const MarginalizationBlock& x) { return x.values == pose; }))
          blocks.push_back({pose, w.AmbientSize(k), w.ManifoldOf(k)});
        m.blocks.push_back(pose);
      }
      m.blocks.push_back(lm.data());
      mres.push_back(std::move(m));
    }
    try {
      auto p = std::make_unique<MarginalizationPrior>(
          MarginalizationPrior::Build(blocks, mres, {lm.data()}, w.opt.marginalization));
      if (p->Statistics().prior_rank > 0) landmark_priors.push_back(std::move(p));
    } catch (const std::invalid_argument&) {
      // Its information is lost; the landmark leaves anyway.
    }
  }
  // k0's pose out of the landmark priors, its pose prior and the previous prior.
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<MarginalizationResidual> mres;
  for (const auto& p : landmark_priors) {
    costs.emplace_back(p->CreateCostFunction());
    MarginalizationResidual m{costs.back().get(), nullptr, {}};
    for (const MarginalizationBlock& b : p->KeptBlocks()) m.blocks.push_back(b.values);
    mres.push_back(std::move(m));
  }
  // k0's pose prior; inertial: its state priors and the IMU (and zero-motion) factor to its
  // successor, so that the successor's pose, velocity and bias keep what they said.
  std::vector<ResidualSpec> own;
  w.AppendFrameResiduals(f0, false, false, &own);
  if (w.opt.inertial) {
    w.AppendInertialResiduals(0, &own);
    w.AppendInertialResiduals(1, &own);
  }
  if (w.prior) {
    ResidualSpec r;
    r.cost.reset(w.prior->CreateCostFunction());
    r.blocks = w.prior_blocks;
    own.push_back(std::move(r));
  }
  for (ResidualSpec& r : own) {
    MarginalizationResidual m{r.cost.get(), nullptr, {}};
    for (double* b : r.blocks) {
      double* s = scratch_of(b);
      to_real[s] = b;
      m.blocks.push_back(s);
    }
    mres.push_back(std::move(m));
  }
  std::vector<MarginalizationBlock> blocks;
  for (const auto& f : w.keyframes) {  // oldest first (deterministic order)
    for (double* real : {f->pose, f->v, f->bias}) {
      if (!scratch.count(real)) continue;
      const BlockKind kind = scratch_kind.at(real);
      blocks.push_back({scratch.at(real).data(), w.AmbientSize(kind), w.ManifoldOf(kind)});
    }
  }
  if (scratch.count(w.extrinsic))
    blocks.push_back({scratch.at(w.extrinsic).data(), 7, &w.pose_manifold});
  if (scratch.count(w.time_offset))
    blocks.push_back({scratch.at(w.time_offset).data(), 1, nullptr});
  std::unique_ptr<MarginalizationPrior> next;
  std::vector<double*> next_blocks;
  // k0's blocks that a residual touches are removed. Only k0 touched (e.g. every leaving
  // landmark was seen by k0 alone): nothing remains for a prior to constrain.
  std::vector<double*> f0_scratch;
  for (double* b : {f0->pose, f0->v, f0->bias})
    if (scratch.count(b)) f0_scratch.push_back(scratch.at(b).data());
  const bool others = std::any_of(mres.begin(), mres.end(), [&](const MarginalizationResidual& m) {
    return std::any_of(m.blocks.begin(), m.blocks.end(), [&](double* b) {
      return std::find(f0_scratch.begin(), f0_scratch.end(), b) == f0_scratch.end();
    });
  });
  if (!f0_scratch.empty() && others) {
    try {
      next = std::make_unique<MarginalizationPrior>(
          MarginalizationPrior::Build(blocks, mres, f0_scratch, w.opt.marginalization));
      for (const MarginalizationBlock& b : next->KeptBlocks())
        next_blocks.push_back(to_real.at(b.values));
    } catch (const std::invalid_argument&) {
      next.reset();
      result->marginalization_failed = true;
    }
  }
  w.InstallPrior(std::move(next), next_blocks, result);
  ConsumeTracks(w, retire_point, retire_line);
  w.DropOldestKeyframe(remove_points, remove_lines, result);
}

}  // namespace

std::unique_ptr<MarginalizationStrategy> MakePosesOnlyPrior() {
  return std::make_unique<PosesOnlyPrior>();
}

}  // namespace internal
}  // namespace window
}  // namespace plucker
