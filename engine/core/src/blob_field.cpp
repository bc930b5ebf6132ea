// Byte blobs as take record fields (blob_field.h).
#include "pliant/core/blob_field.h"

#include <cstring>
#include <stdexcept>

namespace pliant {

Field bytes_field(std::string name, const std::vector<uint8_t>& bytes) {
  if (bytes.size() > 4 * size_t(UINT32_MAX)) throw std::invalid_argument("bytes_field: blob too large");
  Field f{std::move(name), {uint32_t((bytes.size() + 3) / 4)}, {}};
  f.data.assign(f.shape[0], 0.0f);
  if (!bytes.empty()) std::memcpy(f.data.data(), bytes.data(), bytes.size());
  return f;
}

std::vector<uint8_t> field_bytes(const Field& f) {
  std::vector<uint8_t> b(f.data.size() * sizeof(float));
  if (!b.empty()) std::memcpy(b.data(), f.data.data(), b.size());
  return b;
}

}  // namespace pliant
