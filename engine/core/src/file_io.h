// Small POSIX file helpers shared by scene saving and the take writer/reader.
#pragma once
#include <filesystem>
#include <string>

namespace pliant::detail {

// Reads a whole file into *out; returns 0 or the errno of the failure.
int read_file_errno(const std::filesystem::path& path, std::string* out);
// Reads a whole file; throws std::runtime_error naming the file on failure.
std::string read_file(const std::filesystem::path& path);
// Writes `bytes` to a temp file in the same directory, fsyncs it, renames it
// over `path` and fsyncs the directory, so readers see the old or the new file.
void write_file_atomic(const std::filesystem::path& path, const std::string& bytes);
// fsync of a directory (makes a create/rename durable).
void fsync_dir(const std::filesystem::path& dir);
// Writes all bytes to fd, looping on partial writes and EINTR; throws a
// std::runtime_error naming `label` (disk full gets its own wording).
void write_all(int fd, const void* data, size_t size, const std::string& label);
// "No space left on device" style text for errno, with the label.
std::string errno_message(const std::string& label, const std::string& action, int err);

}  // namespace pliant::detail
