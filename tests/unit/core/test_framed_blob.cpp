// framed_blob.h: the header's bytes, the tag round trip, and each damage named with
// its byte (the messages soft's optimizer and spacetime checkpoints report).
#include "pliant/core/framed_blob.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "pliant/core/crc32.h"

namespace pliant {
namespace {

constexpr uint32_t kMagic = 0x54534554;  // "TEST"

std::vector<uint8_t> sample_blob() {
  std::vector<uint8_t> b = framed_blob_start(kMagic, 3, 0xabcdef01u);
  append_value<double>(b, 2.5);
  append_array(b, std::vector<int32_t>{7, -8, 9});
  framed_blob_finish(b);
  return b;
}

// The message of opening `bytes` ("" if it opens), after reading the body.
std::string open_error(const std::vector<uint8_t>& bytes, uint32_t* tag = nullptr) {
  try {
    ByteReader r(bytes, "test blob");
    const uint32_t t = framed_blob_open(bytes, r, kMagic, 3, "test state");
    EXPECT_EQ(r.get<double>(), 2.5);
    EXPECT_EQ(r.get_array<int32_t>(), (std::vector<int32_t>{7, -8, 9}));
    EXPECT_EQ(r.remaining(), 0u);
    if (tag) *tag = t;
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(FramedBlob, HeaderHoldsMagicVersionBodySizeCrcAndTag) {
  const std::vector<uint8_t> b = sample_blob();
  ASSERT_EQ(b.size(), kFramedBlobHeaderBytes + 8 + 8 + 12);
  ByteReader r(b, "test blob");
  EXPECT_EQ(r.get<uint32_t>(), kMagic);
  EXPECT_EQ(r.get<uint32_t>(), 3u);
  EXPECT_EQ(r.get<uint64_t>(), 28u);
  EXPECT_EQ(r.get<uint32_t>(), crc32(b.data() + kFramedBlobHeaderBytes, 28));
  EXPECT_EQ(r.get<uint32_t>(), 0xabcdef01u);
}

TEST(FramedBlob, OpensWithItsTagAndUpToThreeBytesOfPadding) {
  std::vector<uint8_t> b = sample_blob();
  for (int pad = 0; pad <= 3; ++pad) {
    uint32_t tag = 0;
    EXPECT_EQ(open_error(b, &tag), "") << pad;
    EXPECT_EQ(tag, 0xabcdef01u);
    b.push_back(0);
  }
  EXPECT_EQ(open_error(b), "test blob: trailing bytes at byte 24 of 56");
}

TEST(FramedBlob, EachDamageIsNamedWithItsByte) {
  const std::vector<uint8_t> good = sample_blob();
  std::vector<uint8_t> b = good;
  b[0] ^= 1;
  EXPECT_EQ(open_error(b), "test blob: not a test state (bad magic) at byte 4 of 52");
  b = good;
  b[4] = 4;
  EXPECT_EQ(open_error(b), "test blob: unsupported version 4 at byte 8 of 52");
  b = good;
  b.resize(40);
  EXPECT_EQ(open_error(b), "test blob: truncated: the body has 16 of its 28 bytes at byte 24 of 40");
  b = good;
  b.push_back(1);
  EXPECT_EQ(open_error(b), "test blob: trailing bytes at byte 24 of 53");
  b = good;
  b[30] ^= 0x10;
  EXPECT_EQ(open_error(b), "test blob: CRC mismatch (damaged data) at byte 24 of 52");
  b = good;
  b.resize(10);
  EXPECT_EQ(open_error(b), "test blob: truncated at byte 8 of 10");
}

}  // namespace
}  // namespace pliant
