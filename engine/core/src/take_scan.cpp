#include "take_scan.h"

#include <unistd.h>

#include <cerrno>

namespace pliant::detail {

bool pread_all(int fd, void* data, size_t size, uint64_t offset) {
  auto* p = static_cast<uint8_t*>(data);
  while (size > 0) {
    ssize_t n = ::pread(fd, p, size, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<size_t>(n);
    offset += static_cast<uint64_t>(n);
  }
  return true;
}

uint64_t scan_records(int fd, uint64_t offset, uint64_t file_size, std::vector<uint8_t>& buffer,
                      const std::function<void(const ScannedRecord&)>& on_record) {
  while (file_size - offset >= kRecordHeaderSize) {
    uint8_t head[kRecordHeaderSize];
    if (!pread_all(fd, head, sizeof head, offset)) break;
    RecordHeader h;
    if (!decode_header(head, &h)) break;
    // A payload that runs past the end is (still) incomplete: stop, don't allocate.
    if (h.payload_size > file_size - offset - kRecordHeaderSize) break;
    const size_t total = kRecordHeaderSize + static_cast<size_t>(h.payload_size);
    buffer.resize(total);
    if (!pread_all(fd, buffer.data(), total, offset)) break;
    if (check_record(buffer.data(), total, &h) != total) break;
    on_record(ScannedRecord{offset, total, h});
    offset += total;
  }
  return offset;
}

}  // namespace pliant::detail
