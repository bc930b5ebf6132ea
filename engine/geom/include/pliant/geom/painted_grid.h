// A keyframe painted in the editor, stored inline in the scene so a saved and
// reopened scene gives the same keyframe bit for bit:
//   {"type": "painted", "size": [w, h(, d)], "data": "<base64 of run-length bytes>"}
// The grid covers the whole domain; cells are x-fastest with row 0 at the BOTTOM
// (+y up, the simulation's convention), values 0..255 meaning density 0..1.
// Run-length bytes: pairs (run length - 1, value), runs of at most 256 cells.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pliant/geom/raster_grid.h"

namespace pliant::geom {

struct PaintedGrid {
  int dim = 2;
  std::array<int, 3> n{0, 0, 1};
  std::vector<uint8_t> value;  // n[0]*n[1]*n[2] cells, x-fastest
  size_t cells() const { return size_t(n[0]) * n[1] * n[2]; }
};

std::string encode_painted(const PaintedGrid& g);
// Throws GeomError ("painted data: ...") on bad base64, a run past the end, or too
// few cells.
PaintedGrid decode_painted(const std::string& data, int dim, const std::array<int, 3>& n);

// Resamples the painted grid onto `grid` (cell centres, multilinear, clamped at
// the borders); equal sizes copy exactly.
std::vector<float> raster_painted(const RasterGrid& grid, const PaintedGrid& painted);

// Base64 (RFC 4648, with padding). decode throws GeomError on bad characters.
std::string base64_encode(const std::vector<uint8_t>& bytes);
std::vector<uint8_t> base64_decode(const std::string& text);

}  // namespace pliant::geom
