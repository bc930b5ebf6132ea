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

// A similarity placement: a target's local frame is scaled, rotated by rotation_deg
// counter-clockwise (right-handed) about rotation_axis and moved to center_m. The
// axis defaults to +z (the 2D rotation); 3D targets may turn about any axis, so any
// 3D orientation is one (axis, angle) pair. Rasterisers sample through the inverse:
// q = R^T (x - center) / scale.
struct Placement {
  std::array<double, 3> center_m{0, 0, 0};
  double scale = 1.0;
  double rotation_deg = 0.0;
  std::array<double, 3> rotation_axis{0, 0, 1};  // any length > 0; normalised on use
};

// Row-major rotation matrix of the placement (Rodrigues' formula); throws GeomError
// for a zero axis. local -> world: w = R q.
using Rotation3 = std::array<std::array<double, 3>, 3>;
Rotation3 placement_rotation(const Placement& p);

// Composing placements (src/placement_compose.cpp; the editor's gizmo turns a placed
// target about a slice's normal). The rotation by deg about axis (Rodrigues, as
// placement_rotation), the product a b (b first), and the axis-angle of a rotation
// matrix through its unit quaternion (Shepperd's method, stable at 180 degrees):
// unit axis, deg in [0, 180]; the identity gives +z and 0.
Rotation3 rotation_about(const std::array<double, 3>& axis, double deg);
Rotation3 rotation_product(const Rotation3& a, const Rotation3& b);
struct AxisAngle {
  std::array<double, 3> axis{0, 0, 1};
  double deg = 0.0;
};
AxisAngle axis_angle_of(const Rotation3& R);
// p turned by deg about a world axis through its centre (R' = R_axis R). When p is
// unrotated or already turns about a parallel axis the angles add and p keeps its own
// axis vector, exactly (so z-only drags keep a plain rotation_deg); the angle is then
// wrapped into [-180, 180]. Otherwise the product is converted back to axis-angle.
void rotate_placement(Placement& p, const std::array<double, 3>& axis, double deg);

// Failure to build a target. The message already names the file or input and the
// problem ("assets/masks/x.png: cannot read image: ..."); callers add the scene
// field when they turn it into an InputError.
class GeomError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace pliant::geom
