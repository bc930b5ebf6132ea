// TakeReader: indexes frames.bin incrementally while a writer may be appending.
// Only complete records with good CRCs are indexed; the scan resumes from the
// end of the last good record, so a torn tail that later completes is picked up.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "file_io.h"
#include "pliant/core/error.h"
#include "pliant/core/take.h"
#include "take_scan.h"

namespace pliant {
namespace {

std::string read_manifest_text(const std::filesystem::path& dir) {
  const auto path = dir / "take.json";
  std::string text;
  if (int err = detail::read_file_errno(path, &text); err != 0)
    throw InputError(path.string(), "", std::string("cannot read take manifest: ") + std::strerror(err));
  return text;
}

Manifest parse_manifest(const std::filesystem::path& dir, const std::string& text) {
  const auto path = dir / "take.json";
  try {
    return Manifest::from_json(nlohmann::json::parse(text));
  } catch (const InputError& e) {
    throw InputError(path.string(), e.pointer(), e.problem());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string(), "", std::string("invalid JSON: ") + e.what());
  }
}

struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

TakeReader::TakeReader(const std::filesystem::path& dir) : dir_(dir) {
  manifest_text_ = read_manifest_text(dir_);
  manifest_ = parse_manifest(dir_, manifest_text_);
  refresh();
}

size_t TakeReader::refresh() {
  // The manifest is replaced by rename, so any read sees a whole file; a
  // failure here (e.g. the take being deleted) keeps the last good manifest.
  try {
    std::string text = read_manifest_text(dir_);
    if (text != manifest_text_) {
      manifest_ = parse_manifest(dir_, text);
      manifest_text_ = std::move(text);
    }
  } catch (const std::exception&) {
  }
  Fd f;
  f.fd = ::open((dir_ / "frames.bin").c_str(), O_RDONLY | O_CLOEXEC);
  if (f.fd < 0) return 0;
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) return 0;
  const auto size = static_cast<uint64_t>(st.st_size);
  if (size < good_bytes_) {
    // Truncated underneath us (a --resume dropped a torn tail, or a new take).
    index_.clear();
    frames_.clear();
    good_bytes_ = 0;
  }
  const size_t before = index_.size();
  std::vector<uint8_t> buffer;
  good_bytes_ = detail::scan_records(f.fd, good_bytes_, size, buffer, [&](const detail::ScannedRecord& r) {
    Entry e{r.offset, r.size, static_cast<RecordKind>(r.header.kind), r.header.index, r.header.time_s};
    index_.push_back(e);
    if (e.kind != RecordKind::Frame) return;
    // The latest record wins for a repeated frame index (after --resume).
    for (size_t k = frames_.size(); k-- > 0;) {
      if (index_[frames_[k]].index == e.index) {
        frames_[k] = index_.size() - 1;
        return;
      }
    }
    frames_.push_back(index_.size() - 1);
  });
  torn_tail_ = good_bytes_ < size;
  return index_.size() - before;
}

Record TakeReader::read(size_t i) const {
  if (i >= index_.size()) throw std::out_of_range("TakeReader::read: record " + std::to_string(i) + " of " + std::to_string(index_.size()));
  const Entry& e = index_[i];
  const auto path = dir_ / "frames.bin";
  Fd f;
  f.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (f.fd < 0) throw std::runtime_error(detail::errno_message(path.string(), "open for reading", errno));
  std::vector<uint8_t> bytes(e.size);
  if (!detail::pread_all(f.fd, bytes.data(), bytes.size(), e.offset))
    throw std::runtime_error(path.string() + ": record " + std::to_string(i) + " is no longer in the file");
  bool torn = false;
  std::vector<Record> records = decode_records(bytes.data(), bytes.size(), &torn);
  if (records.size() != 1 || torn)
    throw std::runtime_error(path.string() + ": record " + std::to_string(i) + " changed on disk");
  return std::move(records[0]);
}

size_t TakeReader::frame_count() const { return frames_.size(); }

Record TakeReader::read_frame_at(size_t n) const {
  if (n >= frames_.size()) throw std::out_of_range("TakeReader::read_frame_at: frame " + std::to_string(n) + " of " + std::to_string(frames_.size()));
  return read(frames_[n]);
}

bool TakeReader::latest(RecordKind kind, Record* out) const {
  for (size_t i = index_.size(); i-- > 0;) {
    if (index_[i].kind != kind) continue;
    if (out) *out = read(i);
    return true;
  }
  return false;
}

}  // namespace pliant
