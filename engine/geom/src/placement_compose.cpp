// Rotation composition for placements: matrix products and the matrix -> axis-angle
// conversion through the unit quaternion (Shepperd 1978, "Quaternion from rotation
// matrix": divide by the largest of 4w^2, 4x^2, 4y^2, 4z^2, so no cancellation).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "pliant/geom/raster_grid.h"

namespace pliant::geom {
namespace {

double norm3(const std::array<double, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

}  // namespace

Rotation3 rotation_about(const std::array<double, 3>& axis, double deg) {
  Placement p;
  p.rotation_axis = axis;
  p.rotation_deg = deg;
  return placement_rotation(p);
}

Rotation3 rotation_product(const Rotation3& a, const Rotation3& b) {
  Rotation3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
  return c;
}

AxisAngle axis_angle_of(const Rotation3& R) {
  // q = (w, x, y, z) with R = rotation by 2 acos(w) about (x, y, z) / |(x, y, z)|.
  const double t = R[0][0] + R[1][1] + R[2][2];
  double w, x, y, z;
  if (t >= R[0][0] && t >= R[1][1] && t >= R[2][2]) {
    const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 + t));  // 4w
    w = 0.25 * s, x = (R[2][1] - R[1][2]) / s, y = (R[0][2] - R[2][0]) / s, z = (R[1][0] - R[0][1]) / s;
  } else if (R[0][0] >= R[1][1] && R[0][0] >= R[2][2]) {
    const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 + R[0][0] - R[1][1] - R[2][2]));  // 4x
    w = (R[2][1] - R[1][2]) / s, x = 0.25 * s, y = (R[0][1] + R[1][0]) / s, z = (R[0][2] + R[2][0]) / s;
  } else if (R[1][1] >= R[2][2]) {
    const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 - R[0][0] + R[1][1] - R[2][2]));  // 4y
    w = (R[0][2] - R[2][0]) / s, x = (R[0][1] + R[1][0]) / s, y = 0.25 * s, z = (R[1][2] + R[2][1]) / s;
  } else {
    const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 - R[0][0] - R[1][1] + R[2][2]));  // 4z
    w = (R[1][0] - R[0][1]) / s, x = (R[0][2] + R[2][0]) / s, y = (R[1][2] + R[2][1]) / s, z = 0.25 * s;
  }
  if (w < 0) w = -w, x = -x, y = -y, z = -z;  // q and -q are the same rotation; angle in [0, 180]
  const double v = std::sqrt(x * x + y * y + z * z);
  AxisAngle out;
  if (!(v > 1e-300)) return out;
  out.axis = {x / v, y / v, z / v};
  out.deg = 2.0 * std::atan2(v, w) * 180.0 / std::numbers::pi;
  return out;
}

void rotate_placement(Placement& p, const std::array<double, 3>& axis, double deg) {
  const double na = norm3(axis);
  if (!(na > 0)) throw GeomError("rotation axis must not be zero");
  if (p.rotation_deg == 0.0) {
    p.rotation_axis = axis;
    p.rotation_deg = std::remainder(deg, 360.0);
    return;
  }
  const auto& k = p.rotation_axis;
  const double nk = norm3(k);
  if (!(nk > 0)) throw GeomError("rotation_axis must not be zero");
  const double cx = k[1] * axis[2] - k[2] * axis[1], cy = k[2] * axis[0] - k[0] * axis[2],
               cz = k[0] * axis[1] - k[1] * axis[0];
  if (std::sqrt(cx * cx + cy * cy + cz * cz) <= 1e-12 * na * nk) {
    const double dot = k[0] * axis[0] + k[1] * axis[1] + k[2] * axis[2];
    p.rotation_deg = std::remainder(p.rotation_deg + (dot > 0 ? deg : -deg), 360.0);
    return;
  }
  const AxisAngle r = axis_angle_of(rotation_product(rotation_about(axis, deg), placement_rotation(p)));
  p.rotation_axis = r.axis;
  p.rotation_deg = r.deg;
}

}  // namespace pliant::geom
