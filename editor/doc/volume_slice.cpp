#include "doc/volume_slice.h"

#include <algorithm>
#include <cstddef>

namespace pliant::editor {

const char* slice_axis_name(SliceAxis a) {
  return a == SliceAxis::XZ ? "XZ" : a == SliceAxis::YZ ? "YZ" : "XY";
}

const char* slice_normal_name(SliceAxis a) { return a == SliceAxis::XZ ? "y" : a == SliceAxis::YZ ? "x" : "z"; }

int slice_normal_index(SliceAxis a) { return a == SliceAxis::XZ ? 1 : a == SliceAxis::YZ ? 0 : 2; }

int slice_count(const std::array<int, 3>& n, SliceAxis a) { return n[slice_normal_index(a)]; }

std::array<int, 2> slice_size(const std::array<int, 3>& n, SliceAxis a) {
  switch (a) {
    case SliceAxis::XZ: return {n[0], n[2]};
    case SliceAxis::YZ: return {n[2], n[1]};
    default: return {n[0], n[1]};
  }
}

std::array<int, 3> slice_to_voxel(const std::array<int, 3>& n, SliceAxis a, int k, int u, int v) {
  switch (a) {
    case SliceAxis::XZ: return {u, k, n[2] - 1 - v};  // top view: +z (towards the front camera) at the bottom
    case SliceAxis::YZ: return {k, v, n[2] - 1 - u};  // right view: +z on the left
    default: return {u, v, k};
  }
}

std::array<int, 3> voxel_to_slice(const std::array<int, 3>& n, SliceAxis a, int x, int y, int z) {
  switch (a) {
    case SliceAxis::XZ: return {y, x, n[2] - 1 - z};
    case SliceAxis::YZ: return {x, n[2] - 1 - z, y};
    default: return {z, x, y};
  }
}

namespace {
inline size_t voxel_index(const std::array<int, 3>& n, const std::array<int, 3>& p) {
  return size_t(p[0]) + size_t(n[0]) * (size_t(p[1]) + size_t(n[1]) * size_t(p[2]));
}
}  // namespace

geom::PaintedGrid volume_slice(const geom::PaintedGrid& vol, SliceAxis a, int k) {
  const auto wh = slice_size(vol.n, a);
  geom::PaintedGrid g;
  g.dim = 2;
  g.n = {wh[0], wh[1], 1};
  g.value.assign(size_t(wh[0]) * wh[1], 0);
  if (k < 0 || k >= slice_count(vol.n, a) || vol.value.size() != vol.cells()) return g;
  for (int v = 0; v < wh[1]; ++v)
    for (int u = 0; u < wh[0]; ++u)
      g.value[size_t(v) * wh[0] + u] = vol.value[voxel_index(vol.n, slice_to_voxel(vol.n, a, k, u, v))];
  return g;
}

void set_volume_slice(geom::PaintedGrid& vol, SliceAxis a, int k, const geom::PaintedGrid& slice) {
  const auto wh = slice_size(vol.n, a);
  if (k < 0 || k >= slice_count(vol.n, a) || slice.value.size() != size_t(wh[0]) * wh[1] ||
      vol.value.size() != vol.cells())
    return;
  for (int v = 0; v < wh[1]; ++v)
    for (int u = 0; u < wh[0]; ++u)
      vol.value[voxel_index(vol.n, slice_to_voxel(vol.n, a, k, u, v))] = slice.value[size_t(v) * wh[0] + u];
}

std::array<std::array<float, 3>, 4> slice_outline(const std::array<int, 3>& n, SliceAxis a, int k,
                                                  const std::array<float, 3>& e) {
  const int na = slice_normal_index(a), a0 = na == 0 ? 1 : 0, a1 = na == 2 ? 1 : 2;
  const float f = (k + 0.5f) / float(std::max(1, n[na])) - 0.5f;
  const float cu[4] = {-0.5f, 0.5f, 0.5f, -0.5f}, cv[4] = {-0.5f, -0.5f, 0.5f, 0.5f};
  std::array<std::array<float, 3>, 4> out{};
  for (int i = 0; i < 4; ++i) {
    out[i][na] = f * e[na];
    out[i][a0] = cu[i] * e[a0];
    out[i][a1] = cv[i] * e[a1];
  }
  return out;
}

}  // namespace pliant::editor
