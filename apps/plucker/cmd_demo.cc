#include "commands.h"

namespace plucker {
namespace app {

// Placeholder until the module lands; the owner replaces this file.
void RegisterDemo(CLI::App& app, int* exit_code) { (void)app; (void)exit_code; }

}  // namespace app
}  // namespace plucker
