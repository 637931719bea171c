#include "plucker/verify/checks.h"

namespace plucker {
namespace verify {

namespace {
void Append(std::vector<NamedJacobianCheck>* all, std::vector<NamedJacobianCheck> more) {
  for (auto& c : more) all->push_back(std::move(c));
}
}  // namespace

std::vector<NamedJacobianCheck> GeometryJacobianChecks() {
  std::vector<NamedJacobianCheck> all = SE3JacobianChecks();
  Append(&all, LineJacobianChecks());
  Append(&all, ProjectionJacobianChecks());
  Append(&all, CameraJacobianChecks());
  return all;
}

std::vector<NamedJacobianCheck> FactorJacobianChecks() {
  std::vector<NamedJacobianCheck> all = LineFactorJacobianChecks();
  Append(&all, PointFactorJacobianChecks());
  Append(&all, LidarFactorJacobianChecks());
  Append(&all, ImuFactorJacobianChecks());
  Append(&all, MarginalizationJacobianChecks());
  return all;
}

}  // namespace verify
}  // namespace plucker
