// Little-endian scalars as declared by PCD/PLY headers (size in bytes; type F float, U unsigned,
// I signed), read as double. Shared by the PCD and PLY readers.
#pragma once

#include <cstdint>
#include <cstring>

namespace plucker {
namespace io {

inline double LoadLittleEndianScalar(const unsigned char* p, int size, char type) {
  std::uint64_t u = 0;
  for (int i = 0; i < size; ++i) u |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  if (type == 'F') {
    if (size == 4) {
      const std::uint32_t u32 = static_cast<std::uint32_t>(u);
      float f;
      std::memcpy(&f, &u32, 4);
      return f;
    }
    double d;
    std::memcpy(&d, &u, 8);
    return d;
  }
  if (type == 'U') return static_cast<double>(u);
  // Signed: sign-extend.
  if (size < 8 && (u >> (8 * size - 1)) & 1u) u |= ~std::uint64_t{0} << (8 * size);
  std::int64_t s;
  std::memcpy(&s, &u, 8);
  return static_cast<double>(s);
}

}  // namespace io
}  // namespace plucker
