// Checkpoint blobs that carry their own integrity check (soft's "PLSO" optimizer and
// "PLST" spacetime states), written and read with byte_stream.h:
//   header  u32 magic  u32 version  u64 body bytes  u32 CRC32 of the body
//           u32 tag (the caller's, e.g. a hash of the scene the state belongs to)
//   body    the caller's bytes
// Up to 3 zero bytes may follow the body (a take field's padding to 4 bytes).
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "pliant/core/byte_stream.h"

namespace pliant {

constexpr size_t kFramedBlobHeaderBytes = 24;

// A blob holding only the header; append the body, then framed_blob_finish.
std::vector<uint8_t> framed_blob_start(uint32_t magic, uint32_t version, uint32_t tag, size_t body_bytes_hint = 0);
// Writes the body's size and CRC into the header.
void framed_blob_finish(std::vector<uint8_t>& blob);

// Reads and checks the header of `bytes` through r (a reader over the same bytes, at
// its start): magic ("not a <what> (bad magic)"), version ("unsupported version V"),
// the body's length ("truncated: ..."), what follows it ("trailing bytes"), the CRC
// ("CRC mismatch (damaged data)"), each by r.bad. Returns the tag and leaves r at the
// body's start with its end at the body's end.
uint32_t framed_blob_open(std::span<const uint8_t> bytes, ByteReader& r, uint32_t magic, uint32_t version,
                          const char* what);

}  // namespace pliant
