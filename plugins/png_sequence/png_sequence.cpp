// Example Pliant plugin: exporter "png" writes OUT/frame_NNNNN.png (NNNNN = the
// frame index) from each frame's "density" field, as 8-bit greyscale.
//
//   2D density [ny, nx]: one pixel per cell, value v = density.
//   3D density [nz, ny, nx]: projection along z, v = sum over z of density.
//   grey = round(255 * clamp(v / scale, 0, 1)), NaN -> 0, with a fixed scale
//   per take (so brightness means the same in every frame): 1 in 2D (density 1,
//   the initial-density value, is white) and max(1, nz / 4) in 3D (a column of
//   density 1 through a quarter of the depth is white).
//   Rows are flipped so +y is up in the image.
//
// Only the C ABI header is used from Pliant. The exporter keeps its state in a
// static struct: one export at a time per process.
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
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

struct PngExport {
  std::filesystem::path out_dir;
  std::vector<float> projected;     // 3D projection scratch
  std::vector<unsigned char> grey;  // one image
};
PngExport g_export;

int png_begin(void*, const char* out_dir, const char*, uint32_t, char* err, size_t err_size) {
  g_export.out_dir = out_dir;
  return pliant_plugin::create_output_dir(out_dir, err, err_size);
}

// stb calls this with chunks of the encoded file; errors are remembered.
struct FileSink {
  std::FILE* f;
  bool ok;
};
void write_chunk(void* context, void* data, int size) {
  auto* sink = static_cast<FileSink*>(context);
  if (sink->ok && std::fwrite(data, 1, size_t(size), sink->f) != size_t(size)) sink->ok = false;
}

int write_png(const std::filesystem::path& path, int w, int h, const unsigned char* pixels,
              char* err, size_t err_size) {
  return write_file_atomically(
      path,
      [&](std::FILE* f) {
        FileSink sink{f, true};
        return stbi_write_png_to_func(&write_chunk, &sink, w, h, 1, pixels, w) != 0 && sink.ok;
      },
      err, err_size);
}

int png_frame(void*, const PliantFrame* frame, char* err, size_t err_size) {
  const PliantField* d = find_field(frame, "density");
  if (!d) return fail(err, err_size, "frame %d has no \"density\" field", int(frame->index));
  if (frame->index < 0) return fail(err, err_size, "negative frame index %d", int(frame->index));
  if (d->ndim != 2 && d->ndim != 3) {
    return fail(err, err_size, "frame %d: \"density\" has %u dimensions, expected 2 or 3",
                int(frame->index), unsigned(d->ndim));
  }
  const size_t nz = d->ndim == 3 ? d->shape[0] : 1;
  const size_t ny = d->shape[d->ndim - 2], nx = d->shape[d->ndim - 1];
  if (nx == 0 || ny == 0 || nz == 0) {
    return fail(err, err_size, "frame %d: \"density\" is empty", int(frame->index));
  }
  const float* v = d->data;
  double scale = 1.0;
  if (d->ndim == 3) {
    g_export.projected.assign(nx * ny, 0.0f);
    for (size_t k = 0; k < nz; ++k) {
      for (size_t i = 0; i < nx * ny; ++i) g_export.projected[i] += d->data[k * nx * ny + i];
    }
    v = g_export.projected.data();
    scale = std::max(1.0, double(nz) / 4.0);
  }
  g_export.grey.resize(nx * ny);
  for (size_t row = 0; row < ny; ++row) {
    const float* src = v + (ny - 1 - row) * nx;  // +y up
    for (size_t x = 0; x < nx; ++x) {
      double g = double(src[x]) / scale;
      g = std::isnan(g) ? 0.0 : std::clamp(g, 0.0, 1.0);
      g_export.grey[row * nx + x] = static_cast<unsigned char>(std::lround(g * 255.0));
    }
  }
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05d.png", int(frame->index));
  return write_png(g_export.out_dir / name, int(nx), int(ny), g_export.grey.data(), err,
                   err_size);
}

int png_end(void*, char*, size_t) {
  g_export = PngExport{};
  return 0;
}

}  // namespace

PLIANT_PLUGIN_EXPORT int pliant_plugin_load(const PliantHost*, PliantRegistry* registry) {
  return pliant_plugin::register_exporter(
      registry, "png",
      "PNG image sequence of the density (greyscale, 3D projected along z)",
      ".png", png_begin, png_frame, png_end);
}
