#include "plucker/verify/checks.h"

namespace plucker {
namespace verify {

// Placeholder until the module lands; the owner replaces this file.
std::vector<NamedJacobianCheck> LineFactorJacobianChecks() { return {}; }

}  // namespace verify
}  // namespace plucker
