#include "commands.h"

namespace plucker {
namespace app {

// Placeholder until the module lands; the owner replaces this file.
void RegisterSimLidar(CLI::App& sim, int* exit_code) { (void)sim; (void)exit_code; }

}  // namespace app
}  // namespace plucker
