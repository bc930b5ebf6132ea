// Little-endian byte streams (byte_stream.h).
#include "pliant/core/byte_stream.h"

#include <stdexcept>
#include <utility>

namespace pliant {

void append_bytes(std::vector<uint8_t>& out, const void* data, size_t size) {
  if (size == 0) return;
  const size_t at = out.size();
  out.resize(at + size);
  std::memcpy(out.data() + at, data, size);
}

ByteReader::ByteReader(std::span<const uint8_t> bytes, std::string context)
    : bytes_(bytes), context_(std::move(context)), end_(bytes.size()) {}

void ByteReader::set_end(size_t end) {
  if (end < pos_ || end > bytes_.size()) bad("end " + std::to_string(end) + " outside the data");
  end_ = end;
}

void ByteReader::bad(const std::string& what) const {
  throw std::runtime_error(context_ + ": " + what + " at byte " + std::to_string(pos_) + " of " +
                           std::to_string(bytes_.size()));
}

void ByteReader::bad_length(const char* what, uint64_t n) const {
  bad(std::string(what) + " of " + std::to_string(n) + " values longer than the data");
}

void ByteReader::get_bytes(void* out, size_t size) {
  if (size > remaining()) bad("truncated");
  if (size) std::memcpy(out, bytes_.data() + pos_, size);
  pos_ += size;
}

}  // namespace pliant
