// Container signed distance fields, poses and the key-pose trajectory.
//
// Shapes are solids of revolution (or of a scaled radial measure for oval and
// box) described by a profile in the (r, y) half-plane: the wall is the outer
// body minus the cavity, sdf = max(outer, -cavity) (exact where the closest
// feature is unique; sign-correct everywhere, which is what the solver needs).
#include <algorithm>
#include <cmath>

#include "container_mesh.h"
#include "pliant/liquid/liquid.h"

namespace pliant::liquid {
namespace {

constexpr double kOpenAbove = 100.0;  // cavities extend this far above the opening

// Exact SDF of the axis-aligned rectangle [-rx, rx] x [y0, y1] at (r, y).
double rect_sdf(double r, double y, double rx, double y0, double y1) {
  const double cy = 0.5 * (y0 + y1), hy = 0.5 * (y1 - y0);
  const double qx = std::abs(r) - rx, qy = std::abs(y - cy) - hy;
  const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0);
  return std::sqrt(ox * ox + oy * oy) + std::min(std::max(qx, qy), 0.0);
}

// Radial measure in the container frame: for oval and box it is scaled so the
// cavity boundary is at r = radius_m.
double radial(const ContainerShape& c, const Vec3& p, int dim) {
  if (dim == 2) return std::abs(p[0]);
  switch (c.type) {
    case ContainerShape::Oval: {
      const double a = p[0] / c.radius_m, b = p[2] / c.depth_m;
      return c.radius_m * std::sqrt(a * a + b * b);
    }
    case ContainerShape::Box:
      return std::max(std::abs(p[0]), std::abs(p[2]) * c.radius_m / c.depth_m);
    default:
      return std::sqrt(p[0] * p[0] + p[2] * p[2]);
  }
}

double cavity_sdf(const ContainerShape& c, double r, double y) {
  if (c.type == ContainerShape::Bottle) {
    return std::min(rect_sdf(r, y, c.radius_m, 0, c.body_height_m),
                    rect_sdf(r, y, c.neck_radius_m, 0, c.height_m + kOpenAbove));
  }
  return rect_sdf(r, y, c.radius_m, 0, c.height_m + kOpenAbove);
}

double outer_sdf(const ContainerShape& c, double r, double y) {
  const double w = c.wall_m;
  if (c.type == ContainerShape::Bottle) {
    return std::min(rect_sdf(r, y, c.radius_m + w, -w, c.body_height_m + w),
                    rect_sdf(r, y, c.neck_radius_m + w, -w, c.height_m));
  }
  return rect_sdf(r, y, c.radius_m + w, -w, c.height_m);
}

}  // namespace

double ContainerShape::wall_sdf(const Vec3& p, int dim) const {
  if (type == Mesh) return mesh->distance({p[0], p[1], dim == 3 ? p[2] : 0.0});
  const double r = radial(*this, p, dim);
  double d = std::max(outer_sdf(*this, r, p[1]), -cavity_sdf(*this, r, p[1]));
  if (type == Cup) {
    // Handle: a torus in the xy-plane on the +x side (two discs in 2D).
    const double R = 0.3 * height_m, t = 0.35 * wall_m + 0.004;
    const double cx = radius_m + wall_m + 0.5 * R, cy = 0.55 * height_m;
    const double q = std::hypot(p[0] - cx, p[1] - cy) - R;
    const double z = dim == 3 ? p[2] : 0.0;
    d = std::min(d, std::hypot(q, z) - t);
  }
  return d;
}

bool ContainerShape::in_cavity(const Vec3& p, int dim) const {
  if (type == Mesh) return p[1] <= height_m && mesh->in_cavity({p[0], p[1], dim == 3 ? p[2] : 0.0});
  const double r = radial(*this, p, dim);
  return p[1] <= height_m && cavity_sdf(*this, r, p[1]) < 0;
}

bool ContainerShape::in_extended_cavity(const Vec3& p, int dim) const {
  if (type == Mesh) {
    const Vec3 q{p[0], p[1], dim == 3 ? p[2] : 0.0};
    return p[1] <= height_m ? mesh->in_cavity(q) : mesh->column_open(q);
  }
  return cavity_sdf(*this, radial(*this, p, dim), p[1]) < 0;
}

double ContainerShape::cavity_volume(int dim) const {
  if (type == Mesh) return dim == 3 ? mesh->volume3 : mesh->area2;
  const double pi = 3.14159265358979323846;
  auto section = [&](double rad) {
    if (dim == 2) return 2 * rad;
    switch (type) {
      case Oval: return pi * rad * depth_m * rad / radius_m;
      case Box: return 4 * rad * depth_m * rad / radius_m;
      default: return pi * rad * rad;
    }
  };
  if (type == Bottle)
    return section(radius_m) * body_height_m + section(neck_radius_m) * (height_m - body_height_m);
  return section(radius_m) * height_m;
}

Vec3 Pose::to_local(const Vec3& w) const {
  // Rotation by -tilt about z maps local to world; its inverse is +tilt.
  const double c = std::cos(tilt_rad), s = std::sin(tilt_rad);
  const double x = w[0] - position_m[0], y = w[1] - position_m[1];
  return {c * x - s * y, s * x + c * y, w[2] - position_m[2]};
}

Vec3 Pose::to_world(const Vec3& l) const {
  const double c = std::cos(tilt_rad), s = std::sin(tilt_rad);
  return {c * l[0] + s * l[1] + position_m[0], -s * l[0] + c * l[1] + position_m[1], l[2] + position_m[2]};
}

std::array<float, 7> Pose::as_array() const {
  return {float(position_m[0]), float(position_m[1]), float(position_m[2]), float(std::cos(0.5 * tilt_rad)),
          0.f, 0.f, float(-std::sin(0.5 * tilt_rad))};
}

namespace {
// Catmull-Rom segment between keys i and i+1 with non-uniform tangents.
struct Segment {
  double t0, t1;
  double p0[4], p1[4], m0[4], m1[4];  // x, y, z, tilt
};

void pack(const Pose& p, double* out) {
  out[0] = p.position_m[0], out[1] = p.position_m[1], out[2] = p.position_m[2], out[3] = p.tilt_rad;
}

Segment segment(const std::vector<KeyPose>& k, size_t i) {
  Segment s;
  s.t0 = k[i].time_s, s.t1 = k[i + 1].time_s;
  double a[4], b[4], pa[4], nb[4];
  pack(k[i].pose, a), pack(k[i + 1].pose, b);
  const size_t ia = i > 0 ? i - 1 : i, ib = i + 2 < k.size() ? i + 2 : i + 1;
  pack(k[ia].pose, pa), pack(k[ib].pose, nb);
  const double ta = k[ia].time_s, tb = k[ib].time_s;
  for (int c = 0; c < 4; ++c) {
    s.p0[c] = a[c], s.p1[c] = b[c];
    // First and last keys have zero velocity so a pour starts and ends at rest.
    s.m0[c] = i == 0 ? 0.0 : (b[c] - pa[c]) / std::max(1e-9, s.t1 - ta);
    s.m1[c] = i + 2 >= k.size() ? 0.0 : (nb[c] - a[c]) / std::max(1e-9, tb - s.t0);
  }
  return s;
}

// Hermite evaluation: value (d = 0) or time derivative (d = 1).
void hermite(const Segment& s, double t, int d, double* out) {
  const double h = s.t1 - s.t0, u = std::clamp((t - s.t0) / h, 0.0, 1.0);
  double h00, h10, h01, h11;
  if (d == 0) {
    h00 = 2 * u * u * u - 3 * u * u + 1, h10 = u * u * u - 2 * u * u + u;
    h01 = -2 * u * u * u + 3 * u * u, h11 = u * u * u - u * u;
    for (int c = 0; c < 4; ++c) out[c] = h00 * s.p0[c] + h10 * h * s.m0[c] + h01 * s.p1[c] + h11 * h * s.m1[c];
  } else {
    h00 = (6 * u * u - 6 * u) / h, h10 = 3 * u * u - 4 * u + 1;
    h01 = (-6 * u * u + 6 * u) / h, h11 = 3 * u * u - 2 * u;
    for (int c = 0; c < 4; ++c) out[c] = h00 * s.p0[c] + h10 * s.m0[c] + h01 * s.p1[c] + h11 * s.m1[c];
  }
}

size_t find_segment(const std::vector<KeyPose>& k, double t) {
  size_t i = 0;
  while (i + 2 < k.size() && t > k[i + 1].time_s) ++i;
  return i;
}
}  // namespace

Pose Trajectory::at(double t) const {
  if (keys.empty()) return Pose{};
  if (keys.size() == 1 || t <= keys.front().time_s) return keys.front().pose;
  if (t >= keys.back().time_s) return keys.back().pose;
  double v[4];
  hermite(segment(keys, find_segment(keys, t)), t, 0, v);
  Pose p;
  p.position_m = {v[0], v[1], v[2]};
  p.tilt_rad = v[3];
  return p;
}

void Trajectory::velocity(double t, Vec3* linear, double* tilt_rate) const {
  *linear = {0, 0, 0};
  *tilt_rate = 0;
  if (keys.size() < 2 || t <= keys.front().time_s || t >= keys.back().time_s) return;
  double v[4];
  hermite(segment(keys, find_segment(keys, t)), t, 1, v);
  *linear = {v[0], v[1], v[2]};
  *tilt_rate = v[3];
}

}  // namespace pliant::liquid
