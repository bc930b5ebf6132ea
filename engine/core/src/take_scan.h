// Internal: incremental scan of frames.bin through a file descriptor, shared
// by TakeReader::refresh and TakeWriter::reopen.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "take_format.h"

namespace pliant::detail {

struct ScannedRecord {
  uint64_t offset, size;  // size includes the header
  RecordHeader header;
};

// Scans complete, valid records starting at `offset` up to `file_size`; calls
// `on_record` for each and returns the offset just past the last good one.
// Reads one record at a time with pread; `buffer` is reused between calls.
uint64_t scan_records(int fd, uint64_t offset, uint64_t file_size, std::vector<uint8_t>& buffer,
                      const std::function<void(const ScannedRecord&)>& on_record);

// pread of exactly `size` bytes; false when the file is shorter.
bool pread_all(int fd, void* data, size_t size, uint64_t offset);

}  // namespace pliant::detail
