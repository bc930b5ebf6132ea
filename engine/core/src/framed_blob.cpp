#include "pliant/core/framed_blob.h"

#include <cstring>
#include <string>

#include "pliant/core/crc32.h"

namespace pliant {

std::vector<uint8_t> framed_blob_start(uint32_t magic, uint32_t version, uint32_t tag, size_t body_bytes_hint) {
  std::vector<uint8_t> b;
  b.reserve(kFramedBlobHeaderBytes + body_bytes_hint);
  append_value(b, magic);
  append_value(b, version);
  append_value<uint64_t>(b, 0);  // body bytes, set by framed_blob_finish
  append_value<uint32_t>(b, 0);  // CRC, the same
  append_value(b, tag);
  return b;
}

void framed_blob_finish(std::vector<uint8_t>& b) {
  const uint64_t body = b.size() - kFramedBlobHeaderBytes;
  const uint32_t crc = crc32(b.data() + kFramedBlobHeaderBytes, body);
  std::memcpy(b.data() + 8, &body, 8);
  std::memcpy(b.data() + 16, &crc, 4);
}

uint32_t framed_blob_open(std::span<const uint8_t> bytes, ByteReader& r, uint32_t magic, uint32_t version,
                          const char* what) {
  if (r.get<uint32_t>() != magic) r.bad(std::string("not a ") + what + " (bad magic)");
  const uint32_t v = r.get<uint32_t>();
  if (v != version) r.bad("unsupported version " + std::to_string(v));
  const uint64_t body = r.get<uint64_t>();
  const uint32_t crc = r.get<uint32_t>();
  const uint32_t tag = r.get<uint32_t>();
  const size_t have = bytes.size() - kFramedBlobHeaderBytes;
  if (body > have)
    r.bad("truncated: the body has " + std::to_string(have) + " of its " + std::to_string(body) + " bytes");
  if (have - body > 3) r.bad("trailing bytes");
  for (size_t i = kFramedBlobHeaderBytes + body; i < bytes.size(); ++i)
    if (bytes[i] != 0) r.bad("trailing bytes");
  r.set_end(kFramedBlobHeaderBytes + body);
  if (crc32(bytes.data() + kFramedBlobHeaderBytes, body) != crc) r.bad("CRC mismatch (damaged data)");
  return tag;
}

}  // namespace pliant
