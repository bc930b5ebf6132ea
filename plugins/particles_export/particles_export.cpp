// Pliant plugin: exporter "particles" writes OUT/particles_NNNNN.ply (NNNNN = the
// frame index) from each liquid frame's "particles" [n, dim] (metres, world) and
// "speed" [n] (m/s) fields: a binary little-endian PLY point cloud with float
// properties x, y, z, speed (2D takes: z = 0; no speed field: speed = 0), the
// format Blender, Houdini and MeshLab import as points. Files are written under
// a temporary name and renamed, so a reader never sees half a frame.
//
// Only the C ABI header is used from Pliant; one export at a time per process.
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "pliant/plugin.h"
#include "pliant/plugin_support.h"

PLIANT_PLUGIN_DECLARE_API_VERSION();

namespace {

using pliant_plugin::fail;
using pliant_plugin::find_field;
using pliant_plugin::write_file_atomically;

struct ParticlesExport {
  std::filesystem::path out_dir;
  std::vector<float> rows;  // x y z speed per particle
};
ParticlesExport g_export;

bool little_endian() {
  const uint32_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

int particles_begin(void*, const char* out_dir, const char*, uint32_t, char* err, size_t err_size) {
  if (!little_endian()) return fail(err, err_size, "particles export needs a little-endian machine");
  g_export.out_dir = out_dir;
  return pliant_plugin::create_output_dir(out_dir, err, err_size);
}

int particles_frame(void*, const PliantFrame* frame, char* err, size_t err_size) {
  const PliantField* p = find_field(frame, "particles");
  if (!p) return fail(err, err_size, "frame %d has no \"particles\" field (not a liquid take?)", int(frame->index));
  if (frame->index < 0) return fail(err, err_size, "negative frame index %d", int(frame->index));
  if (p->ndim != 2 || (p->shape[1] != 2 && p->shape[1] != 3))
    return fail(err, err_size, "frame %d: \"particles\" must be [n, 2] or [n, 3]", int(frame->index));
  const size_t n = p->shape[0], dim = p->shape[1];
  const PliantField* s = find_field(frame, "speed");
  const bool has_speed = s && s->ndim == 1 && s->shape[0] == n;
  g_export.rows.resize(4 * n);
  for (size_t i = 0; i < n; ++i) {
    g_export.rows[4 * i] = p->data[dim * i];
    g_export.rows[4 * i + 1] = p->data[dim * i + 1];
    g_export.rows[4 * i + 2] = dim == 3 ? p->data[dim * i + 2] : 0.0f;
    g_export.rows[4 * i + 3] = has_speed ? s->data[i] : 0.0f;
  }
  char name[40];
  std::snprintf(name, sizeof name, "particles_%05d.ply", int(frame->index));
  const std::filesystem::path path = g_export.out_dir / name;
  return write_file_atomically(
      path,
      [&](std::FILE* f) {
        const bool ok = std::fprintf(f,
                                     "ply\nformat binary_little_endian 1.0\ncomment pliant liquid frame %d time %.9g s\n"
                                     "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n"
                                     "property float speed\nend_header\n",
                                     int(frame->index), frame->time_s, n) > 0;
        return ok && std::fwrite(g_export.rows.data(), sizeof(float), g_export.rows.size(), f) ==
                         g_export.rows.size();
      },
      err, err_size);
}

int particles_end(void*, char*, size_t) {
  g_export = ParticlesExport{};
  return 0;
}

}  // namespace

PLIANT_PLUGIN_EXPORT int pliant_plugin_load(const PliantHost*, PliantRegistry* registry) {
  return pliant_plugin::register_exporter(
      registry, "particles",
      "liquid particles per frame as PLY point clouds (x y z speed, binary little-endian)",
      ".ply", particles_begin, particles_frame, particles_end);
}
