#include "plucker/verify/cost_function_check.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace plucker {
namespace verify {

namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd Concatenate(const std::vector<Eigen::MatrixXd>& blocks) {
  Eigen::Index cols = 0;
  for (const auto& b : blocks) cols += b.cols();
  Eigen::MatrixXd out(blocks.empty() ? 0 : blocks[0].rows(), cols);
  Eigen::Index c = 0;
  for (const auto& b : blocks) {
    out.middleCols(c, b.cols()) = b;
    c += b.cols();
  }
  return out;
}

// x[i] boxplus delta_i for every block (Euclidean addition without a manifold).
bool PlusAll(const std::vector<const ceres::Manifold*>& manifolds,
             const std::vector<Eigen::VectorXd>& x, const Eigen::VectorXd& delta,
             std::vector<Eigen::VectorXd>* out) {
  *out = x;
  Eigen::Index offset = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const ceres::Manifold* m = manifolds[i];
    const int tangent = m ? m->TangentSize() : static_cast<int>(x[i].size());
    if (m) {
      if (!m->Plus(x[i].data(), delta.data() + offset, (*out)[i].data())) return false;
    } else {
      (*out)[i] = x[i] + delta.segment(offset, tangent);
    }
    offset += tangent;
  }
  return true;
}

// One sample of RunCostFunctionCheck.
void AddCostFunctionSample(const CostFunctionSample& sample, const JacobianCheckOptions& o,
                           JacobianCheckStats* stats) {
  const std::vector<Eigen::VectorXd>& x = sample.x;
  const std::vector<const ceres::Manifold*>& manifolds = sample.manifolds;
  const std::string& what = sample.what;
  const Eigen::MatrixXd nan = Eigen::MatrixXd::Constant(1, 1, std::nan(""));
  Eigen::VectorXd r_an, r_ad;
  std::vector<Eigen::MatrixXd> J_an, J_ad;
  const bool ok = EvaluateCostFunction(*sample.analytic, x, &r_an, &J_an);
  const bool ok_ad = EvaluateCostFunction(*sample.autodiff, x, &r_ad, &J_ad);
  if (o.factor_sample_observer)
    o.factor_sample_observer(
        {what, sample.inputs, x, ok, r_an, ok ? J_an : std::vector<Eigen::MatrixXd>{}});
  if (!ok || !ok_ad || sample.expect_refusal) {
    if (!ok && !ok_ad && sample.expect_refusal) {
      ++stats->skipped;  // the expected guard, refused by both
    } else {
      stats->Add(nan, nan, nan,
                 what + ": refusal mismatch (analytic " + (ok ? "evaluates" : "refuses") +
                     ", autodiff " + (ok_ad ? "evaluates" : "refuses") + ", expected " +
                     (sample.expect_refusal ? "refusal" : "evaluation") + ")");
    }
    return;
  }

  // Tangent Jacobians: ambient * PlusJacobian (MinusJacobian * PlusJacobian = I).
  std::vector<Eigen::MatrixXd> J_tan;
  std::vector<double> step;  // per tangent coordinate
  for (size_t i = 0; i < x.size(); ++i) {
    const ceres::Manifold* m = manifolds[i];
    if (!m) {
      J_tan.push_back(J_an[i]);
    } else {
      RowMajorMatrix P(m->AmbientSize(), m->TangentSize());
      if (!m->PlusJacobian(x[i].data(), P.data())) {
        return stats->Add(nan, nan, nan, what + ": PlusJacobian refuses");
      }
      J_tan.push_back(J_an[i] * P);
    }
    step.resize(step.size() + J_tan.back().cols(), sample.steps.empty() ? 1e-6 : sample.steps[i]);
  }
  // Ridders' differences in the scaled delta (coordinate j in units of h_j), from 100 h_j down to
  // h_j, divided by h_j. 100 h_j moves a point 10 m away by 1 mm: a coarser start steps over the
  // kink of a point-to-edge distance for points a few mm from the edge.
  const Eigen::Map<const Eigen::VectorXd> h(step.data(), step.size());
  bool plus_ok = true;
  Eigen::MatrixXd J_num = RiddersJacobian(
      [&](const Eigen::VectorXd& delta) {
        std::vector<Eigen::VectorXd> xp;
        Eigen::VectorXd r;
        if (!PlusAll(manifolds, x, h.cwiseProduct(delta), &xp) ||
            !EvaluateCostFunction(*sample.analytic, xp, &r, nullptr)) {
          plus_ok = false;
          return Eigen::VectorXd(Eigen::VectorXd::Zero(r_an.size()));
        }
        return r;
      },
      Eigen::VectorXd::Zero(h.size()), 100.0, 8);
  if (!plus_ok) return stats->Add(nan, nan, nan, what + ": refuses a differencing step");
  J_num *= h.cwiseInverse().asDiagonal();

  const Eigen::MatrixXd A = Concatenate(J_an), B = Concatenate(J_ad), T = Concatenate(J_tan);
  const double residual_err = (r_an - r_ad).norm() / std::max(r_ad.norm(), sample.residual_scale);
  const double ea = std::max(JacobianError(A, B), residual_err);
  const double en = JacobianError(T, J_num);
  ++stats->samples;
  stats->worst_autodiff = std::max(stats->worst_autodiff, ea);
  stats->worst_numeric = std::max(stats->worst_numeric, en);
  if (!(ea <= stats->autodiff_tolerance) || !(en <= stats->numeric_tolerance)) {
    if (stats->failures == 0) {
      std::ostringstream os;
      os << stats->name << " sample " << stats->samples << (what.empty() ? "" : " (" + what + ")")
         << ": err vs autodiff " << ea << " (residual " << residual_err << "), vs numeric " << en
         << "\nanalytic ambient:\n"
         << A << "\nautodiff ambient:\n"
         << B << "\nanalytic tangent:\n"
         << T << "\nnumeric tangent:\n"
         << J_num;
      stats->first_failure = os.str();
    }
    ++stats->failures;
  }
}

}  // namespace

bool EvaluateCostFunction(const ceres::CostFunction& f, const std::vector<Eigen::VectorXd>& x,
                          Eigen::VectorXd* residual, std::vector<Eigen::MatrixXd>* jacobians) {
  const int rows = f.num_residuals();
  const auto& sizes = f.parameter_block_sizes();
  std::vector<const double*> params;
  for (const auto& b : x) params.push_back(b.data());
  residual->resize(rows);
  std::vector<RowMajorMatrix> storage;
  std::vector<double*> jac_ptrs;
  if (jacobians) {
    for (int s : sizes) storage.emplace_back(rows, s);
    for (auto& m : storage) jac_ptrs.push_back(m.data());
  }
  if (!f.Evaluate(params.data(), residual->data(), jacobians ? jac_ptrs.data() : nullptr)) {
    return false;
  }
  if (!residual->allFinite()) return false;
  if (jacobians) {
    jacobians->clear();
    for (const auto& m : storage) {
      if (!m.allFinite()) return false;
      jacobians->push_back(m);
    }
  }
  return true;
}

JacobianCheckStats RunCostFunctionCheck(const std::string& name, std::uint64_t seed_offset,
                                        const JacobianCheckOptions& o,
                                        const std::function<CostFunctionSample(Rng&, int)>& make) {
  JacobianCheckStats stats;
  stats.name = name;
  Rng rng(o.seed + seed_offset);
  for (int i = 0; stats.samples < o.samples && stats.skipped <= o.samples; ++i) {
    AddCostFunctionSample(make(rng, i), o, &stats);
  }
  return stats;
}

}  // namespace verify
}  // namespace plucker
