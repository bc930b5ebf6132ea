/* Small helpers for exporter plugins written in C++ (header-only, so plugins
 * stay single shared libraries with no Pliant library to link). The ABI itself
 * is plugin.h. */
#pragma once
#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <cstring>

#include "pliant/plugin.h"

namespace pliant_plugin {

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

/* The frame's field called name, or null. */
inline const PliantField* find_field(const PliantFrame* frame, const char* name) {
  for (uint32_t i = 0; i < frame->field_count; ++i)
    if (std::strcmp(frame->fields[i].name, name) == 0) return &frame->fields[i];
  return nullptr;
}

}  // namespace pliant_plugin
