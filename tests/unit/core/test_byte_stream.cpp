#include "pliant/core/byte_stream.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace pliant {
namespace {

// The message of the runtime_error that f throws ("" if none).
template <class F>
std::string runtime_error_of(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(ByteStream, ValuesAreTheirLittleEndianBytes) {
  std::vector<uint8_t> b;
  append_value<uint32_t>(b, 0x04030201u);
  append_value<int16_t>(b, -2);
  append_value<uint8_t>(b, 7);
  EXPECT_EQ(b, (std::vector<uint8_t>{1, 2, 3, 4, 0xfe, 0xff, 7}));
}

TEST(ByteStream, ArrayIsU64LengthThenValues) {
  std::vector<uint8_t> b;
  append_array(b, std::vector<uint16_t>{0x0201, 0x0403});
  EXPECT_EQ(b, (std::vector<uint8_t>{2, 0, 0, 0, 0, 0, 0, 0, 1, 2, 3, 4}));
  b.clear();
  append_array(b, std::vector<double>{});
  EXPECT_EQ(b, std::vector<uint8_t>(8, 0));
}

TEST(ByteStream, RoundTripOfValuesAndArrays) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<float> floats{1.5f, -0.0f, 3e-41f};  // a denormal too: bits, not values
  const std::vector<std::array<double, 2>> pairs{{0.0, 2.5}, {1.0, -1e300}};
  const double raw[3] = {nan, 1.0 / 3.0, -7.0};
  std::vector<uint8_t> b;
  append_value<int32_t>(b, -42);
  append_value<double>(b, 0.1);
  append_array(b, floats);
  append_array(b, pairs);
  append_doubles(b, raw, 3);
  append_bytes(b, "ab", 2);
  append_array(b, std::vector<int64_t>{});
  EXPECT_EQ(b.size(), 4 + 8 + (8 + 12) + (8 + 32) + 24 + 2 + 8);

  ByteReader r(b, "test blob");
  EXPECT_EQ(r.size(), b.size());
  EXPECT_EQ(r.get<int32_t>(), -42);
  EXPECT_EQ(r.position(), 4u);
  EXPECT_EQ(r.get<double>(), 0.1);
  const auto f = r.get_array<float>();
  ASSERT_EQ(f.size(), floats.size());
  EXPECT_EQ(std::memcmp(f.data(), floats.data(), 12), 0);
  EXPECT_EQ((r.get_array<std::array<double, 2>>()), pairs);
  double got[3];
  r.get_values(got, 3);
  EXPECT_EQ(std::memcmp(got, raw, sizeof(raw)), 0);
  char s[2];
  r.get_bytes(s, 2);
  EXPECT_EQ(std::string(s, 2), "ab");
  EXPECT_TRUE(r.get_array<int64_t>().empty());
  EXPECT_EQ(r.remaining(), 0u);
  EXPECT_EQ(r.position(), b.size());
}

TEST(ByteStream, TruncatedValueThrowsWithContextAndPosition) {
  std::vector<uint8_t> b;
  append_value<uint32_t>(b, 9);
  append_value<uint16_t>(b, 1);
  ByteReader r(b, "control checkpoint");
  r.get<uint32_t>();
  EXPECT_EQ(runtime_error_of([&] { r.get<uint32_t>(); }), "control checkpoint: truncated at byte 4 of 6");
  EXPECT_EQ(r.position(), 4u);  // nothing consumed by the failed read
  EXPECT_EQ(r.get<uint16_t>(), 1);
  EXPECT_EQ(runtime_error_of([&] { r.get<uint8_t>(); }), "control checkpoint: truncated at byte 6 of 6");
  double d[2];
  ByteReader r2(b, "x");
  EXPECT_EQ(runtime_error_of([&] { r2.get_values(d, 1); }), "x: truncated at byte 0 of 6");
}

TEST(ByteStream, ArrayLongerThanTheDataThrowsBeforeAllocating) {
  std::vector<uint8_t> b;
  append_value<uint64_t>(b, 3);  // 3 doubles declared, 2 present
  append_value<double>(b, 1.0);
  append_value<double>(b, 2.0);
  ByteReader r(b, "soft optimizer checkpoint");
  EXPECT_EQ(runtime_error_of([&] { r.get_array<double>(); }),
            "soft optimizer checkpoint: array of 3 values longer than the data at byte 8 of 24");
  ByteReader named(b, "soft optimizer checkpoint");
  EXPECT_EQ(runtime_error_of([&] { named.get_length<double>("theta"); }),
            "soft optimizer checkpoint: theta of 3 values longer than the data at byte 8 of 24");
  // A length near 2^64 must not overflow the check.
  std::vector<uint8_t> huge;
  append_value<uint64_t>(huge, std::numeric_limits<uint64_t>::max());
  ByteReader h(huge, "c");
  EXPECT_EQ(runtime_error_of([&] { h.get_array<std::array<double, 2>>(); }),
            "c: array of 18446744073709551615 values longer than the data at byte 8 of 8");
  // Exactly fitting is fine.
  ByteReader two(b, "c");
  two.get<uint64_t>();
  double got[2];
  two.get_values(got, 2);
  EXPECT_EQ(got[1], 2.0);
}

TEST(ByteStream, SetEndStopsReadingButMessagesCountTheWholeSpan) {
  const std::vector<uint8_t> b(10, 0);
  ByteReader r(b, "c");
  r.get<uint32_t>();
  r.set_end(8);
  EXPECT_EQ(r.remaining(), 4u);
  r.get<uint32_t>();
  EXPECT_EQ(runtime_error_of([&] { r.get<uint8_t>(); }), "c: truncated at byte 8 of 10");
  EXPECT_EQ(runtime_error_of([&] { r.set_end(11); }), "c: end 11 outside the data at byte 8 of 10");
  EXPECT_EQ(runtime_error_of([&] { r.set_end(7); }), "c: end 7 outside the data at byte 8 of 10");
}

TEST(ByteStream, BadPrefixesTheContext) {
  const std::vector<uint8_t> b{1, 2, 3};
  ByteReader r(b, "soft optimizer checkpoint");
  r.get<uint8_t>();
  EXPECT_EQ(runtime_error_of([&] { r.bad("CRC mismatch (damaged data)"); }),
            "soft optimizer checkpoint: CRC mismatch (damaged data) at byte 1 of 3");
}

}  // namespace
}  // namespace pliant
