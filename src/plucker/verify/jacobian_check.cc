#include "plucker/verify/jacobian_check.h"

#include <algorithm>
#include <iomanip>
#include <limits>
#include <sstream>

namespace plucker {
namespace verify {

double JacobianError(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& reference) {
  if (analytic.rows() != reference.rows() || analytic.cols() != reference.cols()) {
    return std::numeric_limits<double>::infinity();
  }
  if (!analytic.allFinite() || !reference.allFinite()) {
    return std::numeric_limits<double>::infinity();
  }
  return (analytic - reference).norm() / std::max(reference.norm(), 1.0);
}

Eigen::MatrixXd NumericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x, double h) {
  const Eigen::VectorXd y0 = f(x);
  Eigen::MatrixXd J(y0.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    J.col(i) = (f(xp) - f(xm)) / (2.0 * h);
  }
  return J;
}

Eigen::MatrixXd RiddersJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x, double h0, int levels) {
  constexpr double kShrink = 2.0, kSafe = 2.0;
  Eigen::MatrixXd J;
  for (int i = 0; i < x.size(); ++i) {
    const auto central = [&](double h) {
      Eigen::VectorXd xp = x, xm = x;
      xp(i) += h;
      xm(i) -= h;
      return Eigen::VectorXd((f(xp) - f(xm)) / (2.0 * h));
    };
    // tableau[k][j]: step h0 / kShrink^k, extrapolated j times.
    std::vector<std::vector<Eigen::VectorXd>> tableau(levels);
    Eigen::VectorXd best = central(h0);
    tableau[0].push_back(best);
    double best_error = std::numeric_limits<double>::infinity(), h = h0;
    for (int k = 1; k < levels; ++k) {
      h /= kShrink;
      tableau[k].push_back(central(h));
      double factor = kShrink * kShrink;
      for (int j = 1; j <= k; ++j, factor *= kShrink * kShrink) {
        tableau[k].push_back((factor * tableau[k][j - 1] - tableau[k - 1][j - 1]) / (factor - 1));
        const double error = std::max((tableau[k][j] - tableau[k][j - 1]).norm(),
                                      (tableau[k][j] - tableau[k - 1][j - 1]).norm());
        if (error <= best_error) {
          best_error = error;
          best = tableau[k][j];
        }
      }
      if ((tableau[k][k] - tableau[k - 1][k - 1]).norm() >= kSafe * best_error) break;
    }
    if (i == 0) J.resize(best.size(), x.size());
    J.col(i) = best;
  }
  return J;
}

std::string JacobianCheckStats::WorstErrors() const {
  std::ostringstream os;
  os << std::scientific << std::setprecision(2) << "autodiff " << worst_autodiff << ", numeric "
     << worst_numeric;
  return os.str();
}

void JacobianCheckStats::Add(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& autodiff,
                             const Eigen::MatrixXd& numeric, const std::string& what) {
  ++samples;
  const double ea = JacobianError(analytic, autodiff);
  const double en = JacobianError(analytic, numeric);
  worst_autodiff = std::max(worst_autodiff, ea);
  worst_numeric = std::max(worst_numeric, en);
  if (!(ea <= autodiff_tolerance) || !(en <= numeric_tolerance)) {
    if (failures == 0) {
      std::ostringstream os;
      os << name << " sample " << samples << (what.empty() ? "" : " (" + what + ")")
         << ": err vs autodiff " << ea << ", vs numeric " << en << "\nanalytic:\n"
         << analytic << "\nautodiff:\n"
         << autodiff << "\nnumeric:\n"
         << numeric;
      first_failure = os.str();
    }
    ++failures;
  }
}

std::vector<NamedJacobianCheck> AllJacobianChecks() {
  std::vector<NamedJacobianCheck> all = GeometryJacobianChecks();
  for (auto& c : FactorJacobianChecks()) all.push_back(std::move(c));
  return all;
}

JacobianCheckRun RunJacobianChecks(const std::vector<NamedJacobianCheck>& checks,
                                   const std::string& filter, int expected_checks,
                                   const JacobianCheckOptions& options) {
  JacobianCheckRun result;
  std::ostringstream error;
  for (const auto& check : checks) {
    if (check.name.find(filter) == std::string::npos) continue;
    result.stats.push_back(check.run(options));
    const JacobianCheckStats& s = result.stats.back();
    if (s.samples < options.samples) {
      error << check.name << ": " << s.samples << " samples, expected >= " << options.samples
            << "\n";
    } else if (!s.passed()) {
      error << s.first_failure << "\n";
    }
  }
  if (static_cast<int>(result.stats.size()) != expected_checks) {
    error << "filter '" << filter << "' selected " << result.stats.size() << " checks, expected "
          << expected_checks << "\n";
  }
  result.error = error.str();
  return result;
}

}  // namespace verify
}  // namespace plucker
