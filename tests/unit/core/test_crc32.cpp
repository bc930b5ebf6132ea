#include "pliant/core/crc32.h"

#include <gtest/gtest.h>

#include <string>

namespace pliant {
namespace {

uint32_t crc_of(const std::string& s, uint32_t crc = 0) { return crc32(s.data(), s.size(), crc); }

TEST(Crc32, KnownVectors) {
  EXPECT_EQ(crc_of("123456789"), 0xCBF43926u);  // the standard check value
  EXPECT_EQ(crc_of(""), 0u);
  EXPECT_EQ(crc_of("a"), 0xE8B7BE43u);
  EXPECT_EQ(crc_of("The quick brown fox jumps over the lazy dog"), 0x414FA339u);
}

TEST(Crc32, ChainsLikeZlib) {
  const std::string a = "The quick brown fox ", b = "jumps over the lazy dog";
  EXPECT_EQ(crc_of(b, crc_of(a)), crc_of(a + b));
}

// Bit-at-a-time definition of the same CRC: the slow second method.
uint32_t crc_bitwise(const std::string& s) {
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : s) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

TEST(Crc32, MatchesBitwiseDefinitionForEveryLengthAndAlignment) {
  std::string s;
  uint32_t x = 12345;
  for (int i = 0; i < 300; ++i) s += static_cast<char>((x = x * 1103515245u + 12345u) >> 24);
  for (size_t start = 0; start < 9; ++start)
    for (size_t len = 0; start + len <= s.size(); len += 7) {
      const std::string part = s.substr(start, len);
      ASSERT_EQ(crc_of(part), crc_bitwise(part)) << start << "+" << len;
    }
}

TEST(Crc32, DetectsEverySingleBitFlip) {
  std::string s = "frames.bin payload";
  const uint32_t good = crc_of(s);
  for (size_t i = 0; i < s.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      std::string t = s;
      t[i] = static_cast<char>(t[i] ^ (1 << bit));
      EXPECT_NE(crc_of(t), good) << i << ":" << bit;
    }
}

}  // namespace
}  // namespace pliant
