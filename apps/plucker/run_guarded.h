// The error boundary of every subcommand: its body runs inside RunGuarded, which turns any
// exception into "plucker <name>: error: <what>" on stderr (after flushing what stdout holds)
// and exit code 1. The body's return value is the exit code; a body returning void means 0.
#pragma once

#include <cstdio>
#include <exception>
#include <iostream>
#include <type_traits>

namespace plucker {
namespace app {

template <typename Body>
void RunGuarded(const char* name, int* exit_code, Body&& body) {
  try {
    if constexpr (std::is_void_v<decltype(body())>) {
      body();
      *exit_code = 0;
    } else {
      *exit_code = body();
    }
  } catch (const std::exception& e) {
    std::cout.flush();
    std::fflush(stdout);
    std::cerr << "plucker " << name << ": error: " << e.what() << "\n";
    *exit_code = 1;
  }
}

}  // namespace app
}  // namespace plucker
