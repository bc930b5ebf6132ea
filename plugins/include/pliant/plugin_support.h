/* Small helpers for exporter plugins written in C++ (header-only, so plugins
 * stay single shared libraries with no Pliant library to link). The ABI itself
 * is plugin.h. */
#pragma once
#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "pliant/plugin.h"

/* The symbols the host looks up (dlsym) must be C names with default
 * visibility; every plugin also exports the ABI version it was built against. */
#define PLIANT_PLUGIN_EXPORT extern "C" __attribute__((visibility("default")))
#define PLIANT_PLUGIN_DECLARE_API_VERSION() \
  PLIANT_PLUGIN_EXPORT const uint32_t pliant_plugin_api_version = PLIANT_PLUGIN_API_VERSION

namespace pliant_plugin {

/* Registers one exporter (no user pointer: plugins keep their state in statics). */
inline int register_exporter(PliantRegistry* registry, const char* name, const char* description,
                             const char* extension, decltype(PliantExporter::begin) begin,
                             decltype(PliantExporter::frame) frame, decltype(PliantExporter::end) end) {
  PliantExporter e{};
  e.name = name;
  e.description = description;
  e.extension = extension;
  e.begin = begin;
  e.frame = frame;
  e.end = end;
  return registry->register_exporter(registry->host_data, &e);
}

/* Formats the error the host shows (it names the plugin and the frame) into
 * err and returns 1, the ABI's failure code. */
inline int fail(char* err, size_t err_size, const char* fmt, ...) {
  if (err && err_size) {
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(err, err_size, fmt, args);
    va_end(args);
  }
  return 1;
}

/* Creates the exporter's output folder (and parents); 0, or 1 with the reason in err. */
inline int create_output_dir(const char* out_dir, char* err, size_t err_size) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec || !std::filesystem::is_directory(out_dir))
    return fail(err, err_size, "cannot create directory %s: %s", out_dir,
                ec ? ec.message().c_str() : "a file of that name exists");
  return 0;
}

/* The frame's field called name, or null. */
inline const PliantField* find_field(const PliantFrame* frame, const char* name) {
  for (uint32_t i = 0; i < frame->field_count; ++i)
    if (std::strcmp(frame->fields[i].name, name) == 0) return &frame->fields[i];
  return nullptr;
}

/* Writes `path` through `path`.tmp and a rename, so a reader (or a crash)
 * never leaves half a file under the real name. write(FILE*) returns false
 * when a write failed; the temporary file is removed on any failure. */
template <class Write>
int write_file_atomically(const std::filesystem::path& path, Write&& write, char* err, size_t err_size) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return fail(err, err_size, "cannot write %s: %s", tmp.c_str(), std::strerror(errno));
  errno = 0;
  bool ok = write(f);
  ok = std::fflush(f) == 0 && ok;
  const int saved_errno = errno;
  ok = std::fclose(f) == 0 && ok;
  if (!ok) {
    std::remove(tmp.c_str());
    return fail(err, err_size, "cannot write %s: %s", path.c_str(),
                saved_errno ? std::strerror(saved_errno) : "encoding or write failed");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    return fail(err, err_size, "cannot rename %s: %s", tmp.c_str(), std::strerror(errno));
  }
  return 0;
}

}  // namespace pliant_plugin
