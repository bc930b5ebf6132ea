#include "render/contour.h"

#include <cstddef>

namespace pliant::editor {

std::vector<ContourSegment> contour_lines(const float* v, int nx, int ny, float level) {
  std::vector<ContourSegment> out;
  // Sample at cell centres, padded by one ring below the level.
  auto at = [&](int i, int j) -> float {
    if (i < 0 || j < 0 || i >= nx || j >= ny) return level - 1.0f;
    return v[std::size_t(j) * nx + i];
  };
  // Corner positions of the dual cell (i, j)..(i+1, j+1) in cell units.
  for (int j = -1; j < ny; ++j)
    for (int i = -1; i < nx; ++i) {
      const float c[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
      const float px[4] = {i + 0.5f, i + 1.5f, i + 1.5f, i + 0.5f};
      const float py[4] = {j + 0.5f, j + 0.5f, j + 1.5f, j + 1.5f};
      int code = 0;
      for (int k = 0; k < 4; ++k)
        if (c[k] >= level) code |= 1 << k;
      if (code == 0 || code == 15) continue;
      // Crossing on edge k (corner k to k+1).
      auto cross = [&](int k) -> std::array<float, 2> {
        const int k2 = (k + 1) % 4;
        const float d = c[k2] - c[k];
        const float t = d != 0 ? (level - c[k]) / d : 0.5f;
        return {px[k] + t * (px[k2] - px[k]), py[k] + t * (py[k2] - py[k])};
      };
      std::vector<int> edges;
      for (int k = 0; k < 4; ++k)
        if (((code >> k) & 1) != ((code >> ((k + 1) % 4)) & 1)) edges.push_back(k);
      if (edges.size() == 2) {
        out.push_back({cross(edges[0]), cross(edges[1])});
      } else if (edges.size() == 4) {
        const bool centre_in = 0.25f * (c[0] + c[1] + c[2] + c[3]) >= level;
        // Corners 0 and 2 are on one side; pair edges around the enclosed corners.
        const bool zero_in = (code & 1) != 0;
        if (zero_in == centre_in) {
          out.push_back({cross(0), cross(1)});
          out.push_back({cross(2), cross(3)});
        } else {
          out.push_back({cross(3), cross(0)});
          out.push_back({cross(1), cross(2)});
        }
      }
    }
  return out;
}

}  // namespace pliant::editor
