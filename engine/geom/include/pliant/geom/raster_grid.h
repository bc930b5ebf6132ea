// The grid targets are rasterised into: nx*ny (2D) or nx*ny*nz (3D) cells of size
// h, x-fastest (c = i + nx*(j + ny*k)), +y up, cell (i,j,k) spans [i h, (i+1) h] etc.
// Values are densities in 0..1. Supersampling: each cell averages ss^dim point
// samples on a regular sub-grid (anti-aliasing).
#pragma once
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace pliant::geom {

struct RasterGrid {
  int dim = 2;
  std::array<int, 3> n{1, 1, 1};
  double cell_size_m = 0.01;
  size_t cells() const { return size_t(n[0]) * n[1] * (dim == 3 ? n[2] : 1); }
  double extent_m(int axis) const { return n[axis] * cell_size_m; }
};

// A 2D similarity placement (3D: rotation about z): a target's local frame is scaled,
// rotated counter-clockwise by rotation_deg and moved to center_m.
struct Placement {
  std::array<double, 3> center_m{0, 0, 0};
  double scale = 1.0;
  double rotation_deg = 0.0;
};

// Failure to build a target. The message already names the file or input and the
// problem ("assets/masks/x.png: cannot read image: ..."); callers add the scene
// field when they turn it into an InputError.
class GeomError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace pliant::geom
