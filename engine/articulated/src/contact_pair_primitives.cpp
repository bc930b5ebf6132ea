// Body-body narrow phase for sphere and capsule pairs and box corners (corners, end spheres, segments;
// capsule-box and box-box in contact_segment_box.cpp).
#include <algorithm>
#include <cmath>

#include "contact_internal.h"

namespace pliant::articulated::contact_internal {

// The pair's margin enters as extra radius: depth = margin - distance, and the
// contact point stays on the force's line.
void corners_against(const Placed& box, const Placed& s, double margin, std::vector<PairContact>* out) {
  for (int f = 0; f < 8; ++f) point_against(s, box.g->body, box.c + box.r * box_corner(box.g->size, f), margin, out);
}

void end_spheres_against(const Placed& cap, const Placed& s, double margin, std::vector<PairContact>* out) {
  for (int e : {-1, 1})
    point_against(s, cap.g->body, cap.c + cap.r.col(2) * (e * cap.g->size[1]), cap.g->size[0] + margin, out);
}

// Closest points of segments p0 + s d0 and p1 + t d1 (s, t in [0, 1]); parallel
// segments: the middle of their overlap along the first (or the nearest ends).
void segment_closest(const Vec3& p0, const Vec3& d0, const Vec3& p1, const Vec3& d1, double* s_out, double* t_out) {
  const Vec3 w = p0 - p1;
  const double a = d0.dot(d0), b = d0.dot(d1), e = d1.dot(d1), c = d0.dot(w), f = d1.dot(w);
  const double denom = a * e - b * b;
  double s, t;
  if (denom > 1e-12 * a * e) {
    s = std::clamp((b * f - c * e) / denom, 0.0, 1.0);
  } else {  // parallel: the second segment's ends projected on the first
    const double s0 = -c / a, s1 = (b - c) / a;
    const double lo = std::max(0.0, std::min(s0, s1)), hi = std::min(1.0, std::max(s0, s1));
    s = lo <= hi ? 0.5 * (lo + hi) : std::clamp(0.5 * (s0 + s1), 0.0, 1.0);
  }
  t = (b * s + f) / e;
  if (t < 0 || t > 1) {
    t = std::clamp(t, 0.0, 1.0);
    s = std::clamp((b * t - c) / a, 0.0, 1.0);
  }
  *s_out = s;
  *t_out = t;
}

// Capsule against capsule, energy k/2 (d_c^2 + sum_e d_e^2 - max_e d_e^2): d_c the
// segments' closest-points depth, d_e the depth of each of the four end spheres
// against the other capsule. The closest points minimise the distance, so d_c >= d_e,
// with equality when they sit at an end (clamped; always so for near-parallel
// overlapping axes): there the energy is sum_e d_e^2, the overlap's end spheres (two
// contacts where the axes lie side by side, so a capsule lying on another cannot rock
// about one point); with both closest points interior (axes crossing) the crossing's
// contact plus every end sphere but the deepest. One formula everywhere, so the energy
// is continuous (and C1 where the closest point reaches an end: it tends to that end
// sphere's contact); exactly parallel axes count as clamped.
void capsule_capsule(const Placed& a, const Placed& b, double margin, std::vector<PairContact>* out) {
  const Vec3 pa = a.c - a.r.col(2) * a.g->size[1], pb = b.c - b.r.col(2) * b.g->size[1];
  const Vec3 da = a.r.col(2) * (2 * a.g->size[1]), db = b.r.col(2) * (2 * b.g->size[1]);
  const size_t first = out->size();
  end_spheres_against(a, b, margin, out);
  end_spheres_against(b, a, margin, out);
  const double dd = da.dot(db);
  if (da.squaredNorm() * db.squaredNorm() - dd * dd <= 1e-12 * da.squaredNorm() * db.squaredNorm()) return;  // parallel
  double s, t;
  segment_closest(pa, da, pb, db, &s, &t);
  if (!(s > 0 && s < 1 && t > 0 && t < 1)) return;  // clamped: an end sphere's contact
  const Vec3 xa = pa + s * da, xb = pb + t * db;
  const double len = (xb - xa).norm(), d = len - a.g->size[0] - b.g->size[0] - margin;
  if (d >= 0) return;
  size_t deepest = first;
  for (size_t i = first + 1; i < out->size(); ++i)
    if ((*out)[i].depth > (*out)[deepest].depth) deepest = i;
  if (deepest < out->size()) out->erase(out->begin() + static_cast<long>(deepest));
  const Vec3 n = len > 1e-12 ? Vec3((xb - xa) / len) : Vec3(a.r.col(0));
  out->push_back({a.g->body, b.g->body, xb - (b.g->size[0] + margin) * n, n, -d});
}

}  // namespace pliant::articulated::contact_internal
