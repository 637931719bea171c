#include "plucker/bag/cdr.h"

#include <algorithm>
#include <cstdio>

namespace plucker {
namespace bag {
namespace {
constexpr std::size_t kHeader = 4;
}  // namespace

CdrReader::CdrReader(const std::uint8_t* data, std::size_t size) {
  if (size < kHeader)
    throw CdrError("payload of " + std::to_string(size) +
                   " bytes is shorter than the 4-byte CDR encapsulation header");
  if (data[0] != 0 || data[1] != 1) {
    const unsigned id = (data[0] << 8) | data[1];
    std::string name = "unknown";
    if (id == 0) name = "CDR big-endian";
    if (id == 2 || id == 3) name = "parameter-list CDR";
    if (id >= 6 && id <= 11) name = "XCDR2";
    char hex[8];
    std::snprintf(hex, sizeof(hex), "%02x%02x", data[0], data[1]);
    throw CdrError(std::string("encapsulation 0x") + hex + " (" + name +
                   ") is not read: only CDR little-endian (0x0001)");
  }
  data_ = data + kHeader;
  size_ = size - kHeader;
}

void CdrReader::Align(std::size_t n) {
  const std::size_t pad = (n - at_ % n) % n;
  at_ = std::min(size_, at_ + pad);
}

void CdrReader::Need(std::size_t n, const char* what) const {
  if (n > size_ - at_)
    throw CdrError(std::string("truncated: ") + what + " needs " + std::to_string(n) +
                   " bytes at offset " + std::to_string(at_) + ", " + std::to_string(size_ - at_) +
                   " left");
}

std::string CdrReader::String(const char* what) {
  const std::uint32_t n = Get<std::uint32_t>(what);
  Need(n, what);
  const char* p = reinterpret_cast<const char*>(data_ + at_);
  at_ += n;
  if (n == 0) return std::string();  // some writers give an empty string no NUL
  if (p[n - 1] != '\0')
    throw CdrError(std::string(what) + ": string of " + std::to_string(n) +
                   " bytes without its terminating NUL");
  return std::string(p, n - 1);
}

std::uint32_t CdrReader::Count(std::size_t min_element_bytes, const char* what) {
  const std::uint32_t n = Get<std::uint32_t>(what);
  if (min_element_bytes > 0 && n > (size_ - at_) / min_element_bytes)
    throw CdrError(std::string("truncated: ") + what + " has " + std::to_string(n) +
                   " elements but only " + std::to_string(size_ - at_) + " bytes are left");
  return n;
}

void CdrReader::Bytes(std::size_t n, std::vector<std::uint8_t>* out, const char* what) {
  Need(n, what);
  out->assign(data_ + at_, data_ + at_ + n);
  at_ += n;
}

CdrWriter::CdrWriter() : buffer_{0x00, 0x01, 0x00, 0x00} {}

void CdrWriter::Align(std::size_t n) {
  const std::size_t at = buffer_.size() - kHeader;
  buffer_.resize(buffer_.size() + (n - at % n) % n, 0);
}

void CdrWriter::String(const std::string& s) {
  Put<std::uint32_t>(static_cast<std::uint32_t>(s.size() + 1));
  buffer_.insert(buffer_.end(), s.begin(), s.end());
  buffer_.push_back(0);
}

void CdrWriter::Bytes(const std::vector<std::uint8_t>& b) {
  Put<std::uint32_t>(static_cast<std::uint32_t>(b.size()));
  buffer_.insert(buffer_.end(), b.begin(), b.end());
}

}  // namespace bag
}  // namespace plucker
