// TakeWriter: append-only frames.bin plus an atomically replaced take.json.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <chrono>
#include <stdexcept>

#include "file_io.h"
#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/core/version.h"
#include "take_scan.h"

namespace pliant {
namespace {

double unix_now() {
  using namespace std::chrono;
  return duration<double>(system_clock::now().time_since_epoch()).count();
}

// Read-write: reopen() scans the existing records through the same descriptor.
int open_frames(const std::filesystem::path& path, int extra_flags) {
  int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC | extra_flags, 0644);
  if (fd < 0) throw std::runtime_error(detail::errno_message(path.string(), "open for writing", errno));
  return fd;
}

}  // namespace

TakeWriter TakeWriter::create(const std::filesystem::path& dir, Manifest manifest) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create take directory: " + ec.message());
  TakeWriter w;
  w.dir_ = dir;
  w.manifest_ = std::move(manifest);
  w.manifest_.status = "running";
  w.manifest_.error.clear();
  w.manifest_.frames_written = 0;
  if (w.manifest_.engine_version.empty()) w.manifest_.engine_version = kEngineVersion;
  w.manifest_.started_unix_s = unix_now();
  w.fd_ = open_frames(dir / "frames.bin", O_TRUNC);
  w.write_manifest();  // also fsyncs the directory, making frames.bin durable
  return w;
}

TakeWriter TakeWriter::reopen(const std::filesystem::path& dir) {
  const auto manifest_path = dir / "take.json";
  std::string text;
  if (int err = detail::read_file_errno(manifest_path, &text); err != 0)
    throw InputError(manifest_path.string(), "", std::string("cannot read take manifest: ") + std::strerror(err));
  TakeWriter w;
  w.dir_ = dir;
  try {
    w.manifest_ = Manifest::from_json(nlohmann::json::parse(text));
  } catch (const InputError& e) {
    throw InputError(manifest_path.string(), e.pointer(), e.problem());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(manifest_path.string(), "", std::string("invalid JSON: ") + e.what());
  }
  w.fd_ = open_frames(dir / "frames.bin", 0);
  struct stat st {};
  if (::fstat(w.fd_, &st) != 0) throw std::runtime_error(detail::errno_message((dir / "frames.bin").string(), "stat", errno));
  std::vector<uint8_t> buffer;
  int frames = 0;
  uint64_t good = detail::scan_records(w.fd_, 0, static_cast<uint64_t>(st.st_size), buffer,
                                       [&](const detail::ScannedRecord& r) {
                                         if (r.header.kind == uint16_t(RecordKind::Frame)) ++frames;
                                       });
  // Drop the torn tail so new records follow the last good one.
  if (good < static_cast<uint64_t>(st.st_size) && ::ftruncate(w.fd_, static_cast<off_t>(good)) != 0)
    throw std::runtime_error(detail::errno_message((dir / "frames.bin").string(), "truncate", errno));
  w.manifest_.frames_written = frames;
  w.manifest_.status = "running";
  w.manifest_.error.clear();
  w.write_manifest();
  return w;
}

TakeWriter::TakeWriter(TakeWriter&& o) noexcept
    : dir_(std::move(o.dir_)), manifest_(std::move(o.manifest_)), fd_(o.fd_) {
  o.fd_ = -1;
}

TakeWriter& TakeWriter::operator=(TakeWriter&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    dir_ = std::move(o.dir_);
    manifest_ = std::move(o.manifest_);
    fd_ = o.fd_;
    o.fd_ = -1;
  }
  return *this;
}

TakeWriter::~TakeWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void TakeWriter::append(const Record& r) {
  if (fd_ < 0) throw std::logic_error("TakeWriter::append on a closed take");
  const std::vector<uint8_t> bytes = encode_record(r);
  const auto path = dir_ / "frames.bin";
  struct stat st {};
  const bool have_size = ::fstat(fd_, &st) == 0;
  try {
    detail::write_all(fd_, bytes.data(), bytes.size(), path.string());
  } catch (...) {
    // Leave no half record behind (a reader would ignore it anyway).
    if (have_size) (void)!::ftruncate(fd_, st.st_size);
    throw;
  }
  if (r.kind == RecordKind::Frame) ++manifest_.frames_written;
}

void TakeWriter::write_manifest() {
  manifest_.updated_unix_s = unix_now();
  save_json_atomic(dir_ / "take.json", manifest_.to_json());
}

void TakeWriter::finish(const std::string& status, const std::string& error) {
  if (fd_ >= 0 && ::fsync(fd_) != 0 && errno != EINVAL)
    throw std::runtime_error(detail::errno_message((dir_ / "frames.bin").string(), "fsync", errno));
  manifest_.status = status;
  manifest_.error = error;
  write_manifest();
}

}  // namespace pliant
