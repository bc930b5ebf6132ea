// Iso-lines of a 2D scalar grid by marching squares (keyframe outlines drawn over
// the result). Cell values sit at cell centres; segments are in cell units with
// (0, 0) the grid's lower-left corner, row 0 at the bottom.
#pragma once
#include <array>
#include <vector>

namespace pliant::editor {

struct ContourSegment {
  std::array<float, 2> a, b;
};

// values: nx * ny, x-fastest. Saddles are split by the cell-average (the
// "asymptotic decider" light); the grid border counts as below the level so
// shapes touching the wall are closed.
std::vector<ContourSegment> contour_lines(const float* values, int nx, int ny, float level);

}  // namespace pliant::editor
