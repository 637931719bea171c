#include "plucker/bag/cdr.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

namespace plucker {
namespace bag {
namespace {

std::string ErrorOf(const std::vector<std::uint8_t>& bytes) {
  try {
    CdrReader r(bytes.data(), bytes.size());
    r.Get<double>("x");
  } catch (const CdrError& e) {
    return e.what();
  }
  return "";
}

// A hand-built payload: header 00 01 00 00, uint8 7, (3 pad), string "abcd" (length 5 with the
// NUL), (3 pad: offset 13 -> 16), float64 0.5, uint16 9, int32 -3 after 2 pad.
std::vector<std::uint8_t> HandBuilt() {
  std::vector<std::uint8_t> b = {0x00, 0x01, 0x00, 0x00, 7, 0, 0, 0, 5,    0,    0,    0,
                                 'a',  'b',  'c',  'd',  0, 0, 0, 0, 0,    0,    0,    0,
                                 0,    0,    0,    0,    9, 0, 0, 0, 0xfd, 0xff, 0xff, 0xff};
  const double half = 0.5;
  std::memcpy(b.data() + 20, &half, 8);
  return b;
}

TEST(Cdr, AlignsEachPrimitiveToItsSizeFromThePayloadStart) {
  const std::vector<std::uint8_t> b = HandBuilt();
  CdrReader r(b.data(), b.size());
  EXPECT_EQ(r.Get<std::uint8_t>("a"), 7);
  EXPECT_EQ(r.String("s"), "abcd");
  EXPECT_EQ(r.offset(), 13u);
  EXPECT_EQ(r.Get<double>("d"), 0.5);  // 8-aligned: offset 16, not 13 or 20
  EXPECT_EQ(r.offset(), 24u);
  EXPECT_EQ(r.Get<std::uint16_t>("u"), 9);
  EXPECT_EQ(r.Get<std::int32_t>("i"), -3);  // 4-aligned: offset 28
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(Cdr, WriterMatchesTheHandBuiltBytes) {
  CdrWriter w;
  w.Put<std::uint8_t>(7);
  w.String("abcd");
  w.Put<double>(0.5);
  w.Put<std::uint16_t>(9);
  w.Put<std::int32_t>(-3);
  EXPECT_EQ(w.buffer(), HandBuilt());
}

TEST(Cdr, OddLengthStringsKeepTheAlignment) {
  for (std::size_t n = 0; n < 12; ++n) {
    CdrWriter w;
    const std::string s(n, 'x');
    w.String(s);
    w.Put<double>(1.25 + n);
    w.String(s + "y");
    w.Put<std::uint32_t>(static_cast<std::uint32_t>(n));
    // 4 + n + 1 bytes, then padding to a multiple of 8 before the double.
    EXPECT_EQ(w.buffer().size() - 4, (4 + n + 1 + 7) / 8 * 8 + 8 + (4 + n + 2 + 3) / 4 * 4 + 4);
    CdrReader r(w.buffer().data(), w.buffer().size());
    EXPECT_EQ(r.String("s"), s);
    EXPECT_EQ(r.Get<double>("d"), 1.25 + n);
    EXPECT_EQ(r.String("s2"), s + "y");
    EXPECT_EQ(r.Get<std::uint32_t>("n"), n);
  }
}

TEST(Cdr, RefusesOtherEncapsulationsByName) {
  EXPECT_NE(ErrorOf({0x00, 0x00, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}).find("0x0000 (CDR big-endian)"),
            std::string::npos);
  EXPECT_NE(ErrorOf({0x00, 0x03, 0, 0}).find("parameter-list"), std::string::npos);
  EXPECT_NE(ErrorOf({0x00, 0x07, 0, 0}).find("XCDR2"), std::string::npos);
  EXPECT_NE(ErrorOf({0x00, 0x01}).find("shorter than the 4-byte"), std::string::npos);
}

TEST(Cdr, TruncationAndBadLengthsAreErrorsNotReads) {
  const std::vector<std::uint8_t> b = HandBuilt();
  for (std::size_t n = 4; n < b.size(); ++n) {  // every cut gives an error, never a read past
    const std::vector<std::uint8_t> cut(b.begin(), b.begin() + n);
    CdrReader r(cut.data(), cut.size());
    EXPECT_THROW(
        {
          r.Get<std::uint8_t>("a");
          r.String("s");
          r.Get<double>("d");
          r.Get<std::uint16_t>("u");
          r.Get<std::int32_t>("i");
        },
        CdrError)
        << n;
  }
  std::vector<std::uint8_t> huge = {0x00, 0x01, 0, 0, 0xff, 0xff, 0xff, 0x7f, 1, 2};
  CdrReader r(huge.data(), huge.size());
  try {
    r.Count(1, "data");
    FAIL();
  } catch (const CdrError& e) {
    EXPECT_NE(std::string(e.what()).find("data has 2147483647 elements but only 2 bytes"),
              std::string::npos)
        << e.what();
  }
  std::vector<std::uint8_t> no_nul = {0x00, 0x01, 0, 0, 2, 0, 0, 0, 'a', 'b'};
  CdrReader s(no_nul.data(), no_nul.size());
  EXPECT_THROW(s.String("frame_id"), CdrError);
}

}  // namespace
}  // namespace bag
}  // namespace plucker
