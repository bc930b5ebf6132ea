// Internal: the frames.bin record layout of take.h, split into a header
// check and a payload check so the reader can index records without decoding.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "pliant/core/take.h"

namespace pliant::detail {

inline constexpr uint32_t kRecordMagic = 0x52464c50u;  // "PLFR"
inline constexpr uint16_t kRecordVersion = 1;
inline constexpr uint8_t kDtypeF32 = 1;
inline constexpr uint8_t kMaxDims = 8;

struct RecordHeader {
  uint16_t kind = 0;
  int32_t index = 0;
  double time_s = 0;
  uint64_t payload_size = 0;
  uint32_t payload_crc = 0;
};

// Decodes and checks (magic, version, reserved, header CRC) the 40-byte header.
bool decode_header(const uint8_t* bytes, RecordHeader* out);
// True when `payload` is a well-formed field list filling exactly `size` bytes.
// With `fields` non-null, also decodes into it. Allocation is bounded by `size`.
bool decode_payload(const uint8_t* payload, size_t size, std::vector<Field>* fields);
// Whole record check of bytes [0, avail): returns the record's total size, or 0
// when the bytes do not start with a complete, valid record.
size_t check_record(const uint8_t* bytes, size_t avail, RecordHeader* header);

}  // namespace pliant::detail
