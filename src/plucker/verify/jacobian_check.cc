#include "plucker/verify/jacobian_check.h"

#include <algorithm>
#include <iomanip>
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
