// Encoding and decoding of frames.bin records (byte layout in take.h).
// Decoding treats its input as hostile: every length is checked against the
// bytes that remain before anything is allocated (the fuzzers depend on it).
#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "pliant/core/crc32.h"
#include "take_format.h"

static_assert(std::endian::native == std::endian::little,
              "frames.bin is little-endian; add byte swapping for big-endian hosts");

namespace pliant {
namespace {

template <class T>
void put(std::vector<uint8_t>& out, T v) {
  const size_t at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &v, sizeof(T));
}

template <class T>
T get(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

}  // namespace

const Field* Record::find(std::string_view name) const {
  for (const auto& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

std::vector<uint8_t> encode_record(const Record& r) {
  std::vector<uint8_t> payload;
  size_t bytes = 4;
  for (const auto& f : r.fields) bytes += 4 + f.name.size() + 4 * f.shape.size() + 4 * f.data.size();
  payload.reserve(bytes);
  put<uint32_t>(payload, static_cast<uint32_t>(r.fields.size()));
  for (const auto& f : r.fields) {
    if (f.name.size() > std::numeric_limits<uint16_t>::max())
      throw std::invalid_argument("take record field name longer than 65535 bytes");
    if (f.shape.size() > detail::kMaxDims)
      throw std::invalid_argument("take record field \"" + f.name + "\" has more than 8 dimensions");
    uint64_t count = 1;
    for (uint32_t d : f.shape) count *= d;
    if (count != f.data.size())
      throw std::invalid_argument("take record field \"" + f.name + "\": data size " +
                                  std::to_string(f.data.size()) + " != product of shape " +
                                  std::to_string(count));
    put<uint16_t>(payload, static_cast<uint16_t>(f.name.size()));
    payload.insert(payload.end(), f.name.begin(), f.name.end());
    payload.push_back(detail::kDtypeF32);
    payload.push_back(static_cast<uint8_t>(f.shape.size()));
    for (uint32_t d : f.shape) put<uint32_t>(payload, d);
    const auto* v = reinterpret_cast<const uint8_t*>(f.data.data());
    payload.insert(payload.end(), v, v + 4 * f.data.size());
  }

  std::vector<uint8_t> out;
  out.reserve(kRecordHeaderSize + payload.size());
  put<uint32_t>(out, detail::kRecordMagic);
  put<uint16_t>(out, detail::kRecordVersion);
  put<uint16_t>(out, static_cast<uint16_t>(r.kind));
  put<int32_t>(out, r.index);
  put<uint32_t>(out, 0);
  put<double>(out, r.time_s);
  put<uint64_t>(out, payload.size());
  put<uint32_t>(out, crc32(payload.data(), payload.size()));
  put<uint32_t>(out, crc32(out.data(), 36));
  out.insert(out.end(), payload.begin(), payload.end());
  return out;
}

namespace detail {

bool decode_header(const uint8_t* b, RecordHeader* h) {
  if (get<uint32_t>(b) != kRecordMagic) return false;
  if (get<uint16_t>(b + 4) != kRecordVersion) return false;
  if (get<uint32_t>(b + 12) != 0) return false;
  if (get<uint32_t>(b + 36) != crc32(b, 36)) return false;
  h->kind = get<uint16_t>(b + 6);
  h->index = get<int32_t>(b + 8);
  h->time_s = get<double>(b + 16);
  h->payload_size = get<uint64_t>(b + 24);
  h->payload_crc = get<uint32_t>(b + 32);
  return true;
}

bool decode_payload(const uint8_t* p, size_t size, std::vector<Field>* fields) {
  size_t pos = 0;
  auto remaining = [&] { return size - pos; };
  if (remaining() < 4) return false;
  uint32_t count = get<uint32_t>(p);
  pos += 4;
  // Every field takes at least 4 bytes (name length, dtype, ndim).
  if (count > remaining() / 4) return false;
  if (fields) {
    fields->clear();
    fields->reserve(std::min<uint32_t>(count, 64));  // grows with real fields only
  }
  for (uint32_t i = 0; i < count; ++i) {
    if (remaining() < 2) return false;
    uint16_t name_len = get<uint16_t>(p + pos);
    pos += 2;
    if (remaining() < size_t(name_len) + 2) return false;
    const char* name = reinterpret_cast<const char*>(p + pos);
    pos += name_len;
    uint8_t dtype = p[pos], ndim = p[pos + 1];
    pos += 2;
    if (dtype != kDtypeF32 || ndim > kMaxDims) return false;
    if (remaining() < 4 * size_t(ndim)) return false;
    uint32_t dims[kMaxDims];
    uint64_t count_values = 1;
    for (uint8_t d = 0; d < ndim; ++d) {
      dims[d] = get<uint32_t>(p + pos + 4 * d);
      if (__builtin_mul_overflow(count_values, uint64_t(dims[d]), &count_values)) return false;
    }
    pos += 4 * size_t(ndim);
    if (count_values > remaining() / 4) return false;
    if (fields) {
      Field f;
      f.name.assign(name, name_len);
      f.shape.assign(dims, dims + ndim);
      f.data.resize(count_values);
      if (count_values) std::memcpy(f.data.data(), p + pos, 4 * count_values);
      fields->push_back(std::move(f));
    }
    pos += 4 * count_values;
  }
  return pos == size;
}

size_t check_record(const uint8_t* bytes, size_t avail, RecordHeader* h) {
  if (avail < kRecordHeaderSize) return 0;
  if (!decode_header(bytes, h)) return 0;
  if (h->payload_size > avail - kRecordHeaderSize) return 0;
  const uint8_t* payload = bytes + kRecordHeaderSize;
  const size_t size = static_cast<size_t>(h->payload_size);
  if (crc32(payload, size) != h->payload_crc) return 0;
  if (!decode_payload(payload, size, nullptr)) return 0;
  return kRecordHeaderSize + size;
}

}  // namespace detail

std::vector<Record> decode_records(const uint8_t* data, size_t size, bool* torn,
                                   uint64_t* good_bytes) {
  std::vector<Record> out;
  size_t pos = 0;
  while (pos < size) {
    detail::RecordHeader h;
    size_t n = detail::check_record(data + pos, size - pos, &h);
    if (n == 0) break;
    Record r;
    r.kind = static_cast<RecordKind>(h.kind);
    r.index = h.index;
    r.time_s = h.time_s;
    detail::decode_payload(data + pos + kRecordHeaderSize, n - kRecordHeaderSize, &r.fields);
    out.push_back(std::move(r));
    pos += n;
  }
  if (torn) *torn = pos < size;
  if (good_bytes) *good_bytes = pos;
  return out;
}

}  // namespace pliant
