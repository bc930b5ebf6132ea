#include "synthetic_frames.h"

#include <algorithm>
#include <cmath>

namespace pliant::test {

Field gaussian_blob_2d(int nx, int ny, float cx, float cy, float sigma, float peak) {
  Field f{"density", {uint32_t(ny), uint32_t(nx)}, std::vector<float>(size_t(nx) * ny)};
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const float dx = i - cx, dy = j - cy;
      f.data[size_t(j) * nx + i] = peak * std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
    }
  return f;
}

Field vortex_velocity_2d(int nx, int ny, float cx, float cy) {
  Field f{"velocity", {uint32_t(ny), uint32_t(nx), 2}, std::vector<float>(size_t(nx) * ny * 2)};
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      f.data[(size_t(j) * nx + i) * 2 + 0] = -(j - cy);
      f.data[(size_t(j) * nx + i) * 2 + 1] = i - cx;
    }
  return f;
}

Field sphere_3d(int n, float radius_cells) {
  const float c = 0.5f * (n - 1);
  return sphere_3d_at(n, radius_cells, c, c, c);
}

Field sphere_3d_at(int n, float radius_cells, float cx, float cy, float cz) {
  Field f{"density", {uint32_t(n), uint32_t(n), uint32_t(n)}, std::vector<float>(size_t(n) * n * n)};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const float r = std::sqrt((i - cx) * (i - cx) + (j - cy) * (j - cy) + (k - cz) * (k - cz));
        f.data[(size_t(k) * n + j) * n + i] = std::clamp(radius_cells - r + 0.5f, 0.0f, 1.0f);
      }
  return f;
}

Field uniform_density(std::vector<uint32_t> shape, float value) {
  size_t n = 1;
  for (uint32_t d : shape) n *= d;
  return Field{"density", std::move(shape), std::vector<float>(n, value)};
}

Record frame_of(std::vector<Field> fields) {
  Record r;
  r.fields = std::move(fields);
  return r;
}

}  // namespace pliant::test
