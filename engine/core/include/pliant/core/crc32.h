#pragma once
#include <cstddef>
#include <cstdint>

namespace pliant {
// CRC-32 (IEEE 802.3, reflected, poly 0xEDB88320), as zlib's crc32().
uint32_t crc32(const void* data, size_t size, uint32_t crc = 0);
}  // namespace pliant
