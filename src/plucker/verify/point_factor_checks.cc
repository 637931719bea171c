#include "plucker/verify/checks.h"

namespace plucker {
namespace verify {

// Placeholder until the module lands; the owner replaces this file.
std::vector<NamedJacobianCheck> PointFactorJacobianChecks() { return {}; }

}  // namespace verify
}  // namespace plucker
