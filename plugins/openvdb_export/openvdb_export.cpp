// Pliant plugin: exporter "vdb" writes OUT/frame_NNNNN.vdb (NNNNN = the frame
// index) from each frame's "density" field as an OpenVDB FloatGrid named
// "density", for renderers and compositors (Houdini, Blender) to read.
//
//   3D density [nz, ny, nx] -> voxel (i, j, k) = cell (x = i, y = j, z = k);
//   2D density [ny, nx]     -> one slice at k = 0.
//   The voxel size is 1/max(nx, ny, nz), so the domain spans [0, 1] along its
//   longest side (a take carries no cell size in its frames). Cells below 1e-4
//   are the background (0) and stay inactive: the grid is sparse. NaN -> 0.
//
// Only the C ABI header is used from Pliant; OpenVDB is linked by this plugin alone.
#include <openvdb/openvdb.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <string>

#include "pliant/plugin.h"
#include "pliant/plugin_support.h"

PLIANT_PLUGIN_DECLARE_API_VERSION();

namespace {

using pliant_plugin::fail;
using pliant_plugin::find_field;

constexpr float kBackgroundBelow = 1e-4f;

std::filesystem::path g_out_dir;

int vdb_begin(void*, const char* out_dir, const char*, uint32_t, char* err, size_t err_size) {
  openvdb::initialize();
  g_out_dir = out_dir;
  return pliant_plugin::create_output_dir(out_dir, err, err_size);
}

int vdb_frame(void*, const PliantFrame* frame, char* err, size_t err_size) {
  const PliantField* density = nullptr;
  for (uint32_t i = 0; i < frame->field_count; ++i)
    if (std::string(frame->fields[i].name) == "density") density = &frame->fields[i];
  if (!density) return fail(err, err_size, "frame %d has no \"density\" field", int(frame->index));
  int nx = 0, ny = 0, nz = 1;
  if (density->ndim == 3) {
    nz = int(density->shape[0]), ny = int(density->shape[1]), nx = int(density->shape[2]);
  } else if (density->ndim == 2) {
    ny = int(density->shape[0]), nx = int(density->shape[1]);
  } else {
    return fail(err, err_size, "frame %d: density has %u dimensions (expected 2 or 3)", int(frame->index),
                unsigned(density->ndim));
  }
  try {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    const double voxel = 1.0 / std::max(nx, std::max(ny, nz));
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    openvdb::FloatGrid::Accessor acc = grid->getAccessor();
    const float* d = density->data;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const float v = d[(size_t(k) * ny + j) * nx + i];
          if (std::isfinite(v) && v >= kBackgroundBelow) acc.setValue(openvdb::Coord(i, j, k), v);
        }
    grid->insertMeta("pliant_frame", openvdb::Int32Metadata(frame->index));
    grid->insertMeta("pliant_time_s", openvdb::DoubleMetadata(frame->time_s));
    char name[64];
    std::snprintf(name, sizeof name, "frame_%05d.vdb", int(frame->index));
    openvdb::io::File file((g_out_dir / name).string());
    openvdb::GridPtrVec grids{grid};
    file.write(grids);
    file.close();
  } catch (const std::exception& e) {
    return fail(err, err_size, "frame %d: OpenVDB: %s", int(frame->index), e.what());
  }
  return 0;
}

int vdb_end(void*, char*, size_t) { return 0; }

}  // namespace

PLIANT_PLUGIN_EXPORT int pliant_plugin_load(const PliantHost*, PliantRegistry* registry) {
  return pliant_plugin::register_exporter(
      registry, "vdb",
      "density frames as OpenVDB FloatGrids (frame_NNNNN.vdb, grid \"density\")",
      ".vdb", vdb_begin, vdb_frame, vdb_end);
}
