/* Pliant plugin ABI (C, versioned). A plugin is a shared library exporting
 *
 *   int pliant_plugin_load(const PliantHost* host, PliantRegistry* registry);
 *   extern const uint32_t pliant_plugin_api_version;   // = PLIANT_PLUGIN_API_VERSION
 *
 * The host dlopen()s every library in plugins/ beside its binary and in each
 * folder of $PLIANT_PLUGIN_PATH (':'-separated), refuses a library whose
 * pliant_plugin_api_version differs from its own with a clear message, and
 * keeps running when a plugin fails to load. pliant_plugin_load returns 0 on
 * success. Plugins register exporters (and later objective terms and
 * keyframe-shape generators) through the registry's function pointers.
 * Strings and arrays passed in are owned by the host and valid only during
 * the call. */
#ifndef PLIANT_PLUGIN_H
#define PLIANT_PLUGIN_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PLIANT_PLUGIN_API_VERSION 1u

/* A read-only view of one frame field (see take.h: shape is slowest-first). */
typedef struct PliantField {
  const char* name;
  const uint32_t* shape;
  uint32_t ndim;
  const float* data;
} PliantField;

typedef struct PliantFrame {
  int32_t index;
  double time_s;
  const PliantField* fields;
  uint32_t field_count;
} PliantFrame;

typedef struct PliantHost {
  uint32_t api_version;
  const char* engine_version;
  /* level: "info", "warn" or "error". */
  void (*log)(const char* level, const char* message);
} PliantHost;

/* An exporter writes a take's frames somewhere. begin/frame/end are called in
 * that order; each returns 0 on success or nonzero with a message written
 * into err (at most err_size bytes, NUL-terminated). */
typedef struct PliantExporter {
  const char* name;        /* e.g. "png" (used by `pliant export --format`) */
  const char* description; /* one line for --help and the editor's menu */
  const char* extension;   /* of the files it writes, e.g. ".png" */
  void* user;
  int (*begin)(void* user, const char* out_dir, const char* take_dir, uint32_t frame_count,
               char* err, size_t err_size);
  int (*frame)(void* user, const PliantFrame* frame, char* err, size_t err_size);
  int (*end)(void* user, char* err, size_t err_size);
} PliantExporter;

typedef struct PliantRegistry {
  uint32_t api_version;
  void* host_data;
  /* Copies *exporter (the strings must stay valid while the plugin is loaded). */
  int (*register_exporter)(void* host_data, const PliantExporter* exporter);
} PliantRegistry;

typedef int (*PliantPluginLoadFn)(const PliantHost* host, PliantRegistry* registry);

#ifdef __cplusplus
}
#endif

#endif /* PLIANT_PLUGIN_H */
