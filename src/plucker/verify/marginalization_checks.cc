// Jacobian check of the marginalization prior (factors/marginalization.h): analytic vs the
// autodiff twin (ambient, 1e-9) and central differences through the manifolds (tangent, 1e-6).
// Each sample marginalizes the first camera and the first point of a random small visual problem
// (3 cameras, 5 points, 2 lines) and evaluates the prior on the kept cameras, points and lines
// moved away from the linearisation point by tangent steps of up to 0.5.
// Curated first samples: 0 at the linearisation point, 1 rotations moved by nearly pi,
// 2 tiny steps (1e-9).
#include <string>
#include <vector>

#include "plucker/factors/line_reprojection_factor.h"
#include "plucker/factors/point_reprojection_factor.h"
#include "plucker/verify/checks.h"
#include "plucker/verify/cost_function_check.h"
#include "plucker/verify/marginalization_problem.h"

namespace plucker {
namespace verify {

namespace {

Eigen::Vector2d Project(const PinholeIntrinsics& K, const SE3d& T_w_c, const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p_c = T_w_c.Inverse() * p_w;
  return K.ToPixel<double>(p_c.head<2>() / p_c.z());
}

Eigen::Vector3d PointAhead(Rng& rng) {
  return Eigen::Vector3d(Uniform(rng, -2, 2), Uniform(rng, -1.5, 1.5), Uniform(rng, 4, 8));
}

double StepScale(int i) { return i == 0 ? 0.0 : i == 2 ? 1e-9 : 0.5; }

Eigen::VectorXd RandomVectorX(Rng& rng, int n, double scale) {
  Eigen::VectorXd v(n);
  for (int k = 0; k < n; ++k) v(k) = Uniform(rng, -scale, scale);
  return v;
}

}  // namespace

std::vector<MarginalizationResidual> MarginalizationProblem::ResidualsOf(
    const std::vector<double*>& blocks_to_remove) const {
  std::vector<MarginalizationResidual> out;
  for (const MarginalizationResidual& r : residuals) {
    bool touches = false;
    for (double* b : r.blocks)
      for (double* m : blocks_to_remove) touches |= b == m;
    if (touches) out.push_back(r);
  }
  return out;
}

std::unique_ptr<MarginalizationProblem> MakeMarginalizationProblem(Rng& rng, int num_poses,
                                                                   int num_points, int num_lines) {
  auto p = std::make_unique<MarginalizationProblem>();
  const PinholeIntrinsics K{500.0, 500.0, 320.0, 240.0};
  const Eigen::Matrix2d S = Eigen::Matrix2d::Identity() * 2.0;  // 0.5 px
  std::vector<SE3d> cams;
  for (int c = 0; c < num_poses; ++c) {
    cams.emplace_back(ExpSO3<double>(RandomVector(rng, 0.05)),
                      Eigen::Vector3d(0.5 * c, 0.0, 0.0) + RandomVector(rng, 0.05));
    p->poses.emplace_back(7);
    cams.back().ToParameters(p->poses.back().data());
  }
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < num_points; ++i) {
    pts.push_back(PointAhead(rng));
    p->points.emplace_back(pts.back().data(), pts.back().data() + 3);
  }
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segs;
  for (int i = 0; i < num_lines; ++i) {
    segs.emplace_back(PointAhead(rng), PointAhead(rng));
    const Line6d L = LineFromPoints(segs.back().first, segs.back().second);
    p->lines.emplace_back(6);
    OrthonormalFromPlucker(L)->ToParameters(p->lines.back().data());
  }
  for (auto& v : p->poses) p->blocks.push_back({v.data(), 7, &p->pose_manifold});
  for (auto& v : p->points) p->blocks.push_back({v.data(), 3, nullptr});
  for (auto& v : p->lines) p->blocks.push_back({v.data(), 6, &p->line_manifold});
  auto noise = [&] { return Eigen::Vector2d(RandomVector(rng, 0.5).head<2>()); };
  for (int c = 0; c < num_poses; ++c) {
    for (int i = 0; i < num_points; ++i) {
      p->costs.emplace_back(
          PointReprojectionFactor::Create(K, Project(K, cams[c], pts[i]) + noise(), S));
      p->residuals.push_back(
          {p->costs.back().get(), nullptr, {p->poses[c].data(), p->points[i].data()}});
    }
    for (int i = 0; i < num_lines; ++i) {
      p->costs.emplace_back(
          LineReprojectionFactor::Create(K, Project(K, cams[c], segs[i].first) + noise(),
                                         Project(K, cams[c], segs[i].second) + noise(), S));
      p->residuals.push_back(
          {p->costs.back().get(), nullptr, {p->poses[c].data(), p->lines[i].data()}});
    }
  }
  return p;
}

std::vector<NamedJacobianCheck> MarginalizationJacobianChecks() {
  const std::string name = "factor.marginalization.Prior";
  return {{name, [name](const JacobianCheckOptions& o) {
             const PoseManifold pose;
             const LineManifold line;
             return RunCostFunctionCheck(name, 501, o, [&](Rng& rng, int i) {
               const auto problem = MakeMarginalizationProblem(rng, 3, 5, 2);
               const std::vector<double*> removed = {problem->poses[0].data(),
                                                     problem->points[0].data()};
               const MarginalizationPrior prior = MarginalizationPrior::Build(
                   problem->blocks, problem->ResidualsOf(removed), removed);
               CostFunctionSample c;
               c.analytic.reset(prior.CreateCostFunction());
               c.autodiff.reset(prior.CreateAutoDiffCostFunction());
               for (const MarginalizationBlock& b : prior.KeptBlocks()) {
                 Eigen::VectorXd x(b.ambient_size);
                 if (!b.manifold) {
                   x = Eigen::Map<const Eigen::VectorXd>(b.values, b.ambient_size) +
                       RandomVectorX(rng, b.ambient_size, StepScale(i));
                   c.manifolds.push_back(nullptr);
                 } else {
                   Eigen::VectorXd delta =
                       RandomVectorX(rng, b.manifold->TangentSize(), StepScale(i));
                   if (i == 1) delta.head<3>() = RandomUnitVector(rng) * (M_PI - 1e-3);
                   b.manifold->Plus(b.values, delta.data(), x.data());
                   c.manifolds.push_back(
                       b.ambient_size == 7 ? static_cast<const ceres::Manifold*>(&pose) : &line);
                 }
                 c.x.push_back(x);
               }
               c.residual_scale = 1.0 + prior.Residual().norm();
               c.what = i == 0   ? "at the linearisation point"
                        : i == 1 ? "rotations moved by nearly pi"
                        : i == 2 ? "tiny steps"
                                 : "random steps";
               return c;
             });
           }}};
}

}  // namespace verify
}  // namespace plucker
