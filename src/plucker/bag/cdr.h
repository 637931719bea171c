// CDR (XCDR1, little-endian) as ROS 2 serialises messages into a rosbag2 `.db3`: a 4-byte
// encapsulation header (0x00 0x01 = CDR little-endian, then 2 option bytes), then the fields,
// each primitive aligned to its size (8 for 64-bit types) relative to the first byte after the
// header; strings are a uint32 length (with the terminating NUL) and the bytes; sequences a
// uint32 count and the elements. Plain bytes in, plain values out: no ROS types.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace plucker {
namespace bag {

class CdrError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CdrReader {
 public:
  // Checks the encapsulation header: a big-endian (0x00 0x00), parameter-list or XCDR2 payload
  // and one shorter than the header are refused (CdrError naming the encapsulation).
  CdrReader(const std::uint8_t* data, std::size_t size);

  template <typename T>
  T Get(const char* what) {
    static_assert(std::is_arithmetic<T>::value, "primitive");
    Align(sizeof(T));
    Need(sizeof(T), what);
    T v;
    std::memcpy(&v, data_ + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::string String(const char* what);
  // A sequence's element count, checked against the bytes left (each element takes at least
  // min_element_bytes), so that a corrupt count fails here instead of allocating.
  std::uint32_t Count(std::size_t min_element_bytes, const char* what);
  void Bytes(std::size_t n, std::vector<std::uint8_t>* out, const char* what);
  std::size_t offset() const { return at_; }  // bytes read after the encapsulation header
  std::size_t remaining() const { return size_ - at_; }

 private:
  void Align(std::size_t n);
  void Need(std::size_t n, const char* what) const;
  const std::uint8_t* data_;  // after the encapsulation header
  std::size_t size_ = 0, at_ = 0;
};

class CdrWriter {
 public:
  CdrWriter();  // writes the CDR little-endian encapsulation header
  template <typename T>
  void Put(T v) {
    static_assert(std::is_arithmetic<T>::value, "primitive");
    Align(sizeof(T));
    const std::size_t at = buffer_.size();
    buffer_.resize(at + sizeof(T));
    std::memcpy(buffer_.data() + at, &v, sizeof(T));
  }
  void String(const std::string& s);
  void Bytes(const std::vector<std::uint8_t>& b);  // uint8[]: count, then the bytes
  const std::vector<std::uint8_t>& buffer() const { return buffer_; }

 private:
  void Align(std::size_t n);
  std::vector<std::uint8_t> buffer_;
};

}  // namespace bag
}  // namespace plucker
