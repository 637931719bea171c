#include "plucker/verify/cost_function_check.h"

#include <algorithm>
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

bool AddCostFunctionSample(const ceres::CostFunction& analytic, const ceres::CostFunction& autodiff,
                           const std::vector<const ceres::Manifold*>& manifolds,
                           const std::vector<Eigen::VectorXd>& x, JacobianCheckStats* stats,
                           const std::string& what, double h) {
  Eigen::VectorXd r_an, r_ad;
  std::vector<Eigen::MatrixXd> J_an, J_ad;
  if (!EvaluateCostFunction(analytic, x, &r_an, &J_an)) return false;
  if (!EvaluateCostFunction(autodiff, x, &r_ad, &J_ad)) return false;

  // Tangent Jacobians: ambient * PlusJacobian (MinusJacobian * PlusJacobian = I).
  std::vector<Eigen::MatrixXd> J_tan;
  Eigen::Index tangent_size = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const ceres::Manifold* m = manifolds[i];
    if (!m) {
      J_tan.push_back(J_an[i]);
    } else {
      RowMajorMatrix P(m->AmbientSize(), m->TangentSize());
      if (!m->PlusJacobian(x[i].data(), P.data())) return false;
      J_tan.push_back(J_an[i] * P);
    }
    tangent_size += J_tan.back().cols();
  }
  bool plus_ok = true;
  const Eigen::MatrixXd J_num = NumericJacobian(
      [&](const Eigen::VectorXd& delta) {
        std::vector<Eigen::VectorXd> xp;
        Eigen::VectorXd r;
        if (!PlusAll(manifolds, x, delta, &xp) ||
            !EvaluateCostFunction(analytic, xp, &r, nullptr)) {
          plus_ok = false;
          return Eigen::VectorXd(Eigen::VectorXd::Constant(r_an.size(), 0.0));
        }
        return r;
      },
      Eigen::VectorXd::Zero(tangent_size), h);
  if (!plus_ok) return false;

  const Eigen::MatrixXd A = Concatenate(J_an), B = Concatenate(J_ad), T = Concatenate(J_tan);
  const double residual_err = (r_an - r_ad).norm() / std::max(r_ad.norm(), 1.0);
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
  return true;
}

}  // namespace verify
}  // namespace plucker
