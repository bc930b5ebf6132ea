// Byte blobs in take records: a solver's versioned binary state (e.g. a checkpoint)
// stored as one field whose f32 values hold the bytes (memcpy, zero-padded to a
// multiple of 4). Records keep field values bit for bit, so the bytes come back
// exactly; field_bytes returns all 4 x data.size() bytes, the padding included, so
// the blob's own format must say where it ends (and may accept up to 3 zero bytes).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pliant/core/take.h"

namespace pliant {

Field bytes_field(std::string name, const std::vector<uint8_t>& bytes);
std::vector<uint8_t> field_bytes(const Field& f);

}  // namespace pliant
