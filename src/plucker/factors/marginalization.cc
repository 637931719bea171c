#include "plucker/factors/marginalization.h"

#include "plucker/factors/robust_loss.h"

#include <ceres/dynamic_autodiff_cost_function.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include "plucker/factors/line_manifold.h"
#include "plucker/factors/pose_manifold.h"
#include "plucker/geometry/so3.h"

namespace plucker {

namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

enum class Kind { kEuclidean, kPose, kLine };

Kind KindOf(const MarginalizationBlock& b) {
  if (b.manifold == nullptr) return Kind::kEuclidean;
  if (dynamic_cast<const PoseManifold*>(b.manifold) && b.ambient_size == 7) return Kind::kPose;
  if (dynamic_cast<const LineManifold*>(b.manifold) && b.ambient_size == 6) return Kind::kLine;
  throw std::invalid_argument(
      "MarginalizationPrior: unsupported manifold (Euclidean, PoseManifold, LineManifold)");
}

int TangentSize(const MarginalizationBlock& b) {
  return b.manifold ? b.manifold->TangentSize() : b.ambient_size;
}

// Minus(y, x0) for the supported kinds, templated for the autodiff twin (the same expressions as
// the manifolds' Minus).
template <typename T>
void MinusT(Kind kind, int ambient, const T* y, const double* x0, T* out) {
  if (kind == Kind::kEuclidean) {
    for (int i = 0; i < ambient; ++i) out[i] = y[i] - T(x0[i]);
    return;
  }
  const Eigen::Quaternion<T> q_y = Eigen::Quaternion<T>(y[3], y[0], y[1], y[2]).normalized();
  const Eigen::Quaternion<T> q_0 =
      Eigen::Quaternion<T>(T(x0[3]), T(x0[0]), T(x0[1]), T(x0[2])).normalized();
  const Vector3<T> w = LogUnitQuaternion<T>(q_0.conjugate() * q_y);
  for (int i = 0; i < 3; ++i) out[i] = w(i);
  if (kind == Kind::kPose) {
    for (int i = 0; i < 3; ++i) out[3 + i] = y[4 + i] - T(x0[4 + i]);
    return;
  }
  using std::atan2;
  using std::sqrt;
  const T n_y = sqrt(y[4] * y[4] + y[5] * y[5]);
  const double n_0 = std::sqrt(x0[4] * x0[4] + x0[5] * x0[5]);
  const T a0 = T(x0[4] / n_0), a1 = T(x0[5] / n_0), b0 = y[4] / n_y, b1 = y[5] / n_y;
  out[3] = atan2(a0 * b1 - a1 * b0, a0 * b0 + a1 * b1);
}

// d Minus(y, x0) / d y (ambient): D(y, x0) * MinusJacobian(y), with D = Jr^-1 of the rotation
// part (the quaternion's Log moves by Jr^-1(w) delta when y moves by Exp(delta)) and identity on
// the rest (translation, angle).
// Empty when y is not a usable block value.
RowMajorMatrix MinusAmbientJacobian(Kind kind, int ambient, const double* y, const double* x0) {
  if (kind == Kind::kEuclidean) return RowMajorMatrix::Identity(ambient, ambient);
  const int t = kind == Kind::kPose ? 6 : 4;
  RowMajorMatrix minus_jacobian(t, ambient);
  const bool ok = kind == Kind::kPose ? PoseManifold().MinusJacobian(y, minus_jacobian.data())
                                      : LineManifold().MinusJacobian(y, minus_jacobian.data());
  if (!ok) return RowMajorMatrix();
  Eigen::VectorXd dx(t);
  MinusT<double>(kind, ambient, y, x0, dx.data());
  Eigen::MatrixXd D = Eigen::MatrixXd::Identity(t, t);
  D.topLeftCorner<3, 3>() = RightJacobianInverseSO3(dx.head<3>());
  return D * minus_jacobian;
}

// Symmetric eigen-decomposition with small eigenvalues (relative to the largest) dropped.
struct Spectrum {
  Eigen::VectorXd values;   // kept eigenvalues
  Eigen::MatrixXd vectors;  // their eigenvectors (columns)
};

Spectrum PositivePart(const Eigen::MatrixXd& H, double floor) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (H + H.transpose()));
  const double largest = es.eigenvalues().size() ? es.eigenvalues().maxCoeff() : 0.0;
  std::vector<int> keep;
  for (int i = 0; i < es.eigenvalues().size(); ++i)
    if (es.eigenvalues()(i) > floor * largest && es.eigenvalues()(i) > 0.0) keep.push_back(i);
  Spectrum s;
  s.values.resize(static_cast<int>(keep.size()));
  s.vectors.resize(H.rows(), static_cast<int>(keep.size()));
  for (std::size_t j = 0; j < keep.size(); ++j) {
    s.values(j) = es.eigenvalues()(keep[j]);
    s.vectors.col(j) = es.eigenvectors().col(keep[j]);
  }
  return s;
}

// The prior's residual: r_p + J_p [Minus(x_k, x0_k)]_k.
// Self-contained (no pointer into the caller's blocks or manifolds).
struct PriorData {
  std::vector<Kind> kinds;
  std::vector<MarginalizationBlock> blocks;  // ambient sizes only: values and manifold cleared
  std::vector<std::vector<double>> x0;
  std::vector<int> offsets;  // tangent offset of each block in J_p's columns
  Eigen::MatrixXd J;
  Eigen::VectorXd r;
};

class PriorFactor final : public ceres::CostFunction {
 public:
  explicit PriorFactor(std::shared_ptr<const PriorData> d) : d_(std::move(d)) {
    set_num_residuals(static_cast<int>(d_->r.size()));
    for (const MarginalizationBlock& b : d_->blocks)
      mutable_parameter_block_sizes()->push_back(b.ambient_size);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const PriorData& d = *d_;
    Eigen::VectorXd dx(d.J.cols());
    for (std::size_t k = 0; k < d.blocks.size(); ++k) {
      for (int i = 0; i < d.blocks[k].ambient_size; ++i)
        if (!std::isfinite(parameters[k][i])) return false;
      MinusT<double>(d.kinds[k], d.blocks[k].ambient_size, parameters[k], d.x0[k].data(),
                     dx.data() + d.offsets[k]);
    }
    Eigen::Map<Eigen::VectorXd>(residuals, d.r.size()) = d.r + d.J * dx;
    if (!jacobians) return true;
    for (std::size_t k = 0; k < d.blocks.size(); ++k) {
      if (!jacobians[k]) continue;
      const int ambient = d.blocks[k].ambient_size;
      const RowMajorMatrix D =
          MinusAmbientJacobian(d.kinds[k], ambient, parameters[k], d.x0[k].data());
      if (D.size() == 0) return false;
      Eigen::Map<RowMajorMatrix>(jacobians[k], d.r.size(), ambient) =
          d.J.middleCols(d.offsets[k], D.rows()) * D;
    }
    return true;
  }

 private:
  std::shared_ptr<const PriorData> d_;
};

struct PriorResidualT {
  std::shared_ptr<const PriorData> d;
  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    Eigen::Matrix<T, Eigen::Dynamic, 1> dx(d->J.cols());
    for (std::size_t k = 0; k < d->blocks.size(); ++k) {
      MinusT<T>(d->kinds[k], d->blocks[k].ambient_size, parameters[k], d->x0[k].data(),
                dx.data() + d->offsets[k]);
    }
    const Eigen::Matrix<T, Eigen::Dynamic, 1> r = d->r.cast<T>() + d->J.cast<T>() * dx;
    for (int i = 0; i < r.size(); ++i) residuals[i] = r(i);
    return true;
  }
};

// A prior that keeps no block (everything was marginalized) has no cost function.
void RequireBlocks(const std::vector<MarginalizationBlock>& kept) {
  if (kept.empty()) {
    throw std::logic_error(
        "MarginalizationPrior: the prior keeps no block (everything was "
        "marginalized): there is no cost function to add");
  }
}

std::shared_ptr<PriorData> MakePriorData(const std::vector<MarginalizationBlock>& kept,
                                         const std::vector<std::vector<double>>& x0,
                                         const Eigen::MatrixXd& J, const Eigen::VectorXd& r) {
  auto d = std::make_shared<PriorData>();
  d->x0 = x0;
  d->J = J;
  d->r = r;
  int offset = 0;
  for (const MarginalizationBlock& b : kept) {
    d->blocks.push_back({nullptr, b.ambient_size, nullptr});
    d->kinds.push_back(KindOf(b));
    d->offsets.push_back(offset);
    offset += TangentSize(b);
  }
  return d;
}

// One residual block linearised in the tangent coordinates of its blocks (columns at `cols`).
struct LinearisedResidual {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;  // rows x (sum of the tangents of its blocks)
  std::vector<int> block_index;
};

LinearisedResidual Linearise(const MarginalizationResidual& res,
                             const std::vector<MarginalizationBlock>& blocks,
                             const std::map<const double*, int>& index_of) {
  const ceres::CostFunction& f = *res.cost;
  const std::vector<int32_t>& sizes = f.parameter_block_sizes();
  if (sizes.size() != res.blocks.size()) {
    throw std::invalid_argument("MarginalizationPrior: residual with the wrong number of blocks");
  }
  LinearisedResidual out;
  int tangent_cols = 0;
  for (double* p : res.blocks) {
    const auto it = index_of.find(p);
    if (it == index_of.end()) {
      throw std::invalid_argument("MarginalizationPrior: residual references an undeclared block");
    }
    out.block_index.push_back(it->second);
    tangent_cols += TangentSize(blocks[it->second]);
  }
  const int rows = f.num_residuals();
  std::vector<RowMajorMatrix> ambient(sizes.size());
  std::vector<double*> jac(sizes.size());
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    ambient[k].resize(rows, sizes[k]);
    jac[k] = ambient[k].data();
  }
  out.r.resize(rows);
  std::vector<const double*> params(res.blocks.begin(), res.blocks.end());
  if (!f.Evaluate(params.data(), out.r.data(), jac.data()) || !out.r.allFinite()) {
    throw std::invalid_argument("MarginalizationPrior: a residual block failed to evaluate");
  }
  out.J.resize(rows, tangent_cols);
  int col = 0;
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    const MarginalizationBlock& b = blocks[out.block_index[k]];
    const int t = TangentSize(b);
    if (b.manifold) {
      RowMajorMatrix plus(b.ambient_size, t);
      b.manifold->PlusJacobian(b.values, plus.data());
      out.J.middleCols(col, t) = ambient[k] * plus;
    } else {
      out.J.middleCols(col, t) = ambient[k];
    }
    col += t;
  }
  if (!out.J.allFinite()) {
    throw std::invalid_argument("MarginalizationPrior: non-finite Jacobian");
  }
  if (res.loss) ApplyRobustLoss(*res.loss, out.r, out.J);
  return out;
}

}  // namespace

MarginalizationPrior MarginalizationPrior::Build(
    const std::vector<MarginalizationBlock>& blocks,
    const std::vector<MarginalizationResidual>& residuals, const std::vector<double*>& marginalize,
    const MarginalizationOptions& options) {
  // Order: marginalized blocks first, then kept ones (in the order declared).
  std::vector<int> order;
  std::vector<bool> is_marginalized(blocks.size(), false);
  std::map<const double*, int> declared;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    KindOf(blocks[i]);  // throws for an unsupported manifold
    declared[blocks[i].values] = static_cast<int>(i);
  }
  for (double* p : marginalize) {
    const auto it = declared.find(p);
    if (it == declared.end()) {
      throw std::invalid_argument("MarginalizationPrior: marginalized block not declared");
    }
    is_marginalized[it->second] = true;
  }
  std::vector<LinearisedResidual> lin;
  std::vector<bool> used(blocks.size(), false);
  for (const MarginalizationResidual& res : residuals) {
    lin.push_back(Linearise(res, blocks, declared));
    for (int b : lin.back().block_index) used[b] = true;
  }
  for (std::size_t i = 0; i < blocks.size(); ++i)
    if (is_marginalized[i]) order.push_back(static_cast<int>(i));
  const int m_blocks = static_cast<int>(order.size());
  for (std::size_t i = 0; i < blocks.size(); ++i)
    if (!is_marginalized[i] && used[i]) order.push_back(static_cast<int>(i));
  for (int i = 0; i < m_blocks; ++i) {
    if (!used[order[i]]) {
      throw std::invalid_argument("MarginalizationPrior: a marginalized block has no residual");
    }
  }
  std::vector<int> offset(blocks.size(), -1);
  int n = 0, m = 0;
  for (int k = 0; k < static_cast<int>(order.size()); ++k) {
    offset[order[k]] = n;
    n += TangentSize(blocks[order[k]]);
    if (k + 1 == m_blocks) m = n;
  }
  // H = J^T J and g = J^T r, accumulated per residual block.
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
  for (const LinearisedResidual& l : lin) {
    std::vector<int> cols;
    for (int b : l.block_index)
      for (int t = 0; t < TangentSize(blocks[b]); ++t) cols.push_back(offset[b] + t);
    const Eigen::MatrixXd JtJ = l.J.transpose() * l.J;
    const Eigen::VectorXd Jtr = l.J.transpose() * l.r;
    for (std::size_t a = 0; a < cols.size(); ++a) {
      g(cols[a]) += Jtr(a);
      for (std::size_t c = 0; c < cols.size(); ++c) H(cols[a], cols[c]) += JtJ(a, c);
    }
  }
  // Schur complement onto the kept blocks, with pseudo-inverses.
  const int k = n - m;
  MarginalizationPrior prior;
  prior.stats_.residual_blocks = static_cast<int>(residuals.size());
  prior.stats_.marginalized_dimension = m;
  prior.stats_.kept_dimension = k;
  if (k == 0) return prior;  // everything marginalized: an empty prior (rank 0)
  // Nothing marginalized (m = 0): the prior is the linearisation of the residuals itself.
  Eigen::MatrixXd H_mm_inv = Eigen::MatrixXd::Zero(m, m);
  if (m > 0) {
    const Spectrum mm = PositivePart(H.topLeftCorner(m, m), options.eigenvalue_floor);
    H_mm_inv = mm.vectors * mm.values.cwiseInverse().asDiagonal() * mm.vectors.transpose();
  }
  const Eigen::MatrixXd H_km = H.bottomLeftCorner(k, m);
  const Eigen::MatrixXd H_star = H.bottomRightCorner(k, k) - H_km * H_mm_inv * H_km.transpose();
  const Eigen::VectorXd g_star = g.tail(k) - H_km * (H_mm_inv * g.head(m));
  const Spectrum kk = PositivePart(H_star, options.eigenvalue_floor);

  for (int i = m_blocks; i < static_cast<int>(order.size()); ++i) {
    const MarginalizationBlock& b = blocks[order[i]];
    prior.kept_.push_back(b);
    prior.x0_.emplace_back(b.values, b.values + b.ambient_size);
  }
  prior.J_ = kk.values.cwiseSqrt().asDiagonal() * kk.vectors.transpose();
  prior.r_ = kk.values.cwiseSqrt().cwiseInverse().asDiagonal() * (kk.vectors.transpose() * g_star);
  prior.stats_.prior_rank = static_cast<int>(kk.values.size());
  return prior;
}

ceres::CostFunction* MarginalizationPrior::CreateCostFunction() const {
  RequireBlocks(kept_);
  return new PriorFactor(MakePriorData(kept_, x0_, J_, r_));
}

ceres::CostFunction* MarginalizationPrior::CreateAutoDiffCostFunction() const {
  RequireBlocks(kept_);
  auto* f = new ceres::DynamicAutoDiffCostFunction<PriorResidualT, 8>(
      new PriorResidualT{MakePriorData(kept_, x0_, J_, r_)});
  for (const MarginalizationBlock& b : kept_) f->AddParameterBlock(b.ambient_size);
  f->SetNumResiduals(static_cast<int>(r_.size()));
  return f;
}

}  // namespace plucker
