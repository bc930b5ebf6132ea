// Cylinders and ellipsoids against planes at their exact surface (contact.h,
// PointSupport): the support point of a convex shape S along u = -n, the point of S
// deepest under a plane of normal n, is argmax_y u . y = grad h(u), h the support
// function. Its distance to the plane is min_y n . x(y): by the envelope theorem its
// gradient is a fixed body point's there, and its Hessian a fixed point's plus
// [n] hess h(u) [n] (the shape turning under the plane), which the tessellation's
// vertices lack (a 32-gon rolls in bumps; every vertex sample is a kink).
#include <cmath>

#include "pliant/articulated/contact.h"

namespace pliant::articulated {

namespace {
// A flat cap's rim has no single deepest point: hess h grows as r / |P u| (P u: u's
// part in the cap's plane). The Hessian model (not the energy) holds that below
// this share of a unit direction, where the cap's ring points carry the contact.
constexpr double kRimCurvatureFloor = 0.1;
}  // namespace

Vec3 support_point_local(const Model& m, const ContactPoint& p, const Mat3& rot, Mat3* curvature) {
  const Geom& g = m.geoms[p.geom];
  const Mat3 rg = g.quat.toRotationMatrix();
  const Mat3 rw = rot * rg;  // geom frame -> world
  const Vec3 n = m.geoms[p.plane].quat * Vec3::UnitZ();
  const Vec3 u = -(rw.transpose() * n);  // into the plane, geom frame
  Vec3 s;
  Mat3 h;
  if (p.support == PointSupport::Ellipsoid) {
    // h(u) = |A u|, A = diag(radii): grad A^2 u / |A u|, hess A (I - a a^T) A / |a|, a = A u / |A u|.
    const Vec3 au = g.size.cwiseProduct(u);
    const double len = au.norm();
    const Vec3 a = au / len;
    s = g.size.cwiseProduct(a);
    if (curvature) h = g.size.asDiagonal() * (Mat3::Identity() - a * a.transpose()) * g.size.asDiagonal() / len;
  } else {
    // A cap's rim: circle of radius r at z = -+ half-height; h(u) = z u_z + r |P u|,
    // grad its point c + r e (e = P u / |P u|), hess r t t^T / |P u| (t: e turned 90
    // degrees in the cap's plane). Flat (P u = 0): every rim point is as deep; take x.
    const double r = g.size[0], z = p.support == PointSupport::RimLow ? -g.size[1] : g.size[1];
    const double rho = std::hypot(u.x(), u.y());
    const Vec3 e = rho > 1e-12 ? Vec3(u.x() / rho, u.y() / rho, 0) : Vec3::UnitX();
    s = Vec3(r * e.x(), r * e.y(), z);
    if (curvature) {
      const Vec3 t(-e.y(), e.x(), 0);
      h = r / std::max(rho, kRimCurvatureFloor) * t * t.transpose();
    }
  }
  if (curvature) *curvature = rw * h * rw.transpose();
  return g.pos + rg * s;
}

}  // namespace pliant::articulated
