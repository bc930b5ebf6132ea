#include "file_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace pliant::detail {

std::string errno_message(const std::string& label, const std::string& action, int err) {
  if (err == ENOSPC) return label + ": disk full while trying to " + action;
  if (err == EDQUOT) return label + ": disk quota exceeded while trying to " + action;
  return label + ": cannot " + action + ": " + std::strerror(err);
}

int read_file_errno(const std::filesystem::path& path, std::string* out) {
  out->clear();
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  char buf[1 << 16];
  for (;;) {
    ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0) {
      if (errno == EINTR) continue;
      int err = errno;
      ::close(fd);
      return err;
    }
    if (n == 0) break;
    out->append(buf, static_cast<size_t>(n));
  }
  ::close(fd);
  return 0;
}

std::string read_file(const std::filesystem::path& path) {
  std::string out;
  if (int err = read_file_errno(path, &out); err != 0)
    throw std::runtime_error(errno_message(path.string(), "read", err));
  return out;
}

void write_all(int fd, const void* data, size_t size, const std::string& label) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    ssize_t n = ::write(fd, p, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(errno_message(label, "write", errno));
    }
    if (n == 0) throw std::runtime_error(errno_message(label, "write", ENOSPC));
    p += n;
    size -= static_cast<size_t>(n);
  }
}

void fsync_dir(const std::filesystem::path& dir) {
  std::filesystem::path d = dir.empty() ? std::filesystem::path(".") : dir;
  int fd = ::open(d.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // best effort: some file systems refuse directory fds
  ::fsync(fd);
  ::close(fd);
}

void write_file_atomic(const std::filesystem::path& path, const std::string& bytes) {
  const std::string label = path.string();
  std::filesystem::path dir = path.parent_path();
  std::filesystem::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(errno_message(tmp.string(), "create", errno));
  try {
    write_all(fd, bytes.data(), bytes.size(), tmp.string());
    if (::fsync(fd) != 0) throw std::runtime_error(errno_message(tmp.string(), "fsync", errno));
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    int err = errno;
    ::unlink(tmp.c_str());
    throw std::runtime_error(errno_message(label, "replace", err));
  }
  fsync_dir(dir);
}

}  // namespace pliant::detail
