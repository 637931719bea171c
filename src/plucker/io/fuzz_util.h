// Helpers shared by the libFuzzer targets (io/*_fuzz.cc) and by io/fuzz_test.cc, which runs the
// same entry points over the seed corpus plus random mutations in every ordinary (sanitizer)
// build. Not part of the library API.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace plucker {
namespace io {
namespace fuzz {

// Aborts (a crash the fuzzer reports) when an invariant of a parsed result is violated.
inline void Check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
    std::abort();
  }
}

// Timestamps a reader accepted must be finite and non-decreasing.
inline void CheckTimes(const std::vector<double>& times) {
  for (std::size_t i = 0; i < times.size(); ++i) {
    Check(std::isfinite(times[i]), "non-finite time");
    Check(i == 0 || times[i] >= times[i - 1], "decreasing time");
  }
}

// One random mutation: bit flip, byte set, insert, erase, truncate, duplicate a span, or
// replace a digit run by an extreme number.
inline std::string Mutate(std::string s, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng() % n); };
  static const char* kNumbers[] = {"nan",        "-inf", "1e308", "-1e-320",
                                   "4294967296", "-1",   "0",     "99999999999999999999",
                                   "0x10",       ""};
  switch (rng() % 7) {
    case 0:
      if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1u << (rng() % 8));
      break;
    case 1:
      if (!s.empty()) s[pick(s.size())] = static_cast<char>(rng() & 0xFF);
      break;
    case 2:
      s.insert(pick(s.size() + 1), 1, static_cast<char>(rng() & 0xFF));
      break;
    case 3:
      if (!s.empty()) s.erase(pick(s.size()), 1 + pick(8));
      break;
    case 4:
      s.resize(pick(s.size() + 1));
      break;
    case 5: {
      const std::size_t a = pick(s.size() + 1), n = pick(64);
      s.insert(pick(s.size() + 1), s.substr(a, n));
      break;
    }
    default: {
      const std::size_t p = s.find_first_of("0123456789", pick(s.size() + 1));
      if (p == std::string::npos) break;
      const std::size_t e = s.find_first_not_of("0123456789.", p);
      s.replace(p, (e == std::string::npos ? s.size() : e) - p, kNumbers[rng() % 10]);
    }
  }
  return s;
}

// When the environment variable PLUCKER_FUZZ_WRITE_SEEDS names a folder, writes the seeds there
// (seed_0, seed_1, ...): scripts/fuzz.sh builds its starting corpus this way.
inline void WriteSeedsFromEnv(const char* prefix, const std::vector<std::string>& seeds) {
  const char* dir = std::getenv("PLUCKER_FUZZ_WRITE_SEEDS");
  if (!dir || !*dir) return;
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    const std::string path = std::string(dir) + "/" + prefix + "_seed_" + std::to_string(i);
    if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
      std::fwrite(seeds[i].data(), 1, seeds[i].size(), f);
      std::fclose(f);
    }
  }
}

}  // namespace fuzz
}  // namespace io
}  // namespace plucker

// The libFuzzer entry points of one target (built with PLUCKER_LIBFUZZER): the seeds written on
// request, then `one_input` (a function in plucker::io::fuzz) on every input.
#ifdef PLUCKER_LIBFUZZER
#define PLUCKER_FUZZ_TARGET(prefix, seeds, one_input)                                 \
  extern "C" int LLVMFuzzerInitialize(int*, char***) {                                \
    plucker::io::fuzz::WriteSeedsFromEnv(prefix, plucker::io::fuzz::seeds());         \
    return 0;                                                                         \
  }                                                                                   \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    return plucker::io::fuzz::one_input(data, size);                                  \
  }
#else
#define PLUCKER_FUZZ_TARGET(prefix, seeds, one_input)
#endif
