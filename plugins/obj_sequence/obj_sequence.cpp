// Pliant plugin: exporter "obj" writes OUT/frame_NNNNN.obj (NNNNN = the frame
// index) for takes with a "vertices" field [nverts, 3] (metres), e.g. soft
// characters. Soft takes store "triangles" [ntris, 3] (vertex indices as f32)
// in frame 0 only, so the triangles of the first frame that has them are kept
// for the frames after it. A frame without triangles before any was seen is an
// error (an OBJ of bare points would not open as a mesh in most tools).
//
// Files are written through a temporary name and renamed, so a reader never
// sees half a file. Only the C ABI header is used from Pliant; the state is a
// static struct: one export at a time per process.
#include <cerrno>
#include <cmath>
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

struct ObjExport {
  std::filesystem::path out_dir;
  std::vector<uint32_t> triangles;  // 3 per triangle, 0-based
  bool have_triangles = false;
};
ObjExport g_export;

int obj_begin(void*, const char* out_dir, const char*, uint32_t, char* err, size_t err_size) {
  g_export = ObjExport{};
  g_export.out_dir = out_dir;
  return pliant_plugin::create_output_dir(out_dir, err, err_size);
}

// Keeps the frame's triangles after checking every index is a vertex.
int take_triangles(const PliantField& t, size_t nverts, int frame, char* err, size_t err_size) {
  if (t.ndim != 2 || t.shape[1] != 3)
    return fail(err, err_size, "frame %d: \"triangles\" must have shape [ntris, 3]", frame);
  const size_t n = size_t(t.shape[0]) * 3;
  std::vector<uint32_t> tris(n);
  for (size_t i = 0; i < n; ++i) {
    const float v = t.data[i];
    if (!(v >= 0.0f) || v >= float(nverts) || v != std::floor(v))
      return fail(err, err_size, "frame %d: triangle %zu has vertex index %g, not in [0, %zu)", frame, i / 3,
                  double(v), nverts);
    tris[i] = uint32_t(v);
  }
  g_export.triangles = std::move(tris);
  g_export.have_triangles = true;
  return 0;
}

int obj_frame(void*, const PliantFrame* frame, char* err, size_t err_size) {
  const int index = int(frame->index);
  if (index < 0) return fail(err, err_size, "negative frame index %d", index);
  const PliantField* v = find_field(frame, "vertices");
  if (!v) return fail(err, err_size, "frame %d has no \"vertices\" field (not a soft take?)", index);
  if (v->ndim != 2 || v->shape[1] != 3)
    return fail(err, err_size, "frame %d: \"vertices\" must have shape [nverts, 3]", index);
  const size_t nverts = v->shape[0];
  if (const PliantField* t = find_field(frame, "triangles"))
    if (take_triangles(*t, nverts, index, err, err_size)) return 1;
  if (!g_export.have_triangles)
    return fail(err, err_size, "frame %d: no \"triangles\" in this or an earlier frame (export from frame 0)",
                index);
  for (uint32_t i : g_export.triangles)
    if (i >= nverts)
      return fail(err, err_size, "frame %d has %zu vertices, fewer than frame 0's triangles use", index, nverts);

  char name[32];
  std::snprintf(name, sizeof name, "frame_%05d.obj", index);
  const std::filesystem::path path = g_export.out_dir / name;
  return write_file_atomically(
      path,
      [&](std::FILE* f) {
        bool ok = std::fprintf(f, "# Pliant take frame %d, t = %.6f s, units: metres\n", index, frame->time_s) > 0;
        for (size_t i = 0; i < nverts && ok; ++i)
          ok = std::fprintf(f, "v %.7g %.7g %.7g\n", double(v->data[3 * i]), double(v->data[3 * i + 1]),
                            double(v->data[3 * i + 2])) > 0;
        const auto& t = g_export.triangles;
        for (size_t i = 0; i + 2 < t.size() && ok; i += 3)  // OBJ indices are 1-based
          ok = std::fprintf(f, "f %u %u %u\n", t[i] + 1, t[i + 1] + 1, t[i + 2] + 1) > 0;
        return ok;
      },
      err, err_size);
}

int obj_end(void*, char*, size_t) {
  g_export = ObjExport{};
  return 0;
}

}  // namespace

PLIANT_PLUGIN_EXPORT int pliant_plugin_load(const PliantHost*, PliantRegistry* registry) {
  return pliant_plugin::register_exporter(
      registry, "obj",
      "Wavefront OBJ per frame of a mesh take (soft characters: vertices + triangles)",
      ".obj", obj_begin, obj_frame, obj_end);
}
