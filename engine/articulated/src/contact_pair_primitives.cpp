// Body-body narrow phase for sphere, capsule and box pairs (corners, end spheres, segments, box edges).
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

namespace {

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

}  // namespace

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

namespace {

// A box's 12 edges in world: start points, full-length directions, and whether either
// end corner is inside box `other` (corners as in box_corner).
void box_edges(const Placed& b, const Placed& other, Vec3* p, Vec3* d, bool* corner_inside) {
  const Vec3& sz = b.g->size;
  bool in[8];
  Vec3 n;
  for (int f = 0; f < 8; ++f)
    in[f] = shape_distance(GeomType::Box, other.g->size, other.c, other.r, b.c + b.r * box_corner(sz, f), &n) < 0;
  int k = 0;
  for (int ax = 0; ax < 3; ++ax)
    for (int e = 0; e < 4; ++e, ++k) {
      const int u = (ax + 1) % 3, v = (ax + 2) % 3, start = (e & 1) << u | (e >> 1 & 1) << v;
      Vec3 local;
      local[ax] = -sz[ax];
      local[u] = (e & 1 ? 1 : -1) * sz[u];
      local[v] = (e & 2 ? 1 : -1) * sz[v];
      p[k] = b.c + b.r * local;
      d[k] = b.r.col(ax) * (2 * sz[ax]);
      corner_inside[k] = in[start] || in[start | 1 << ax];
    }
}

// Whether segment p + s d (world, s in [0, 1]) passes through box b (clipped against
// its three slabs).
bool edge_may_meet(const Placed& b, const Vec3& p, const Vec3& d) {
  const Vec3 x0 = b.r.transpose() * (p - b.c), dx = b.r.transpose() * d;
  double s0 = 0, s1 = 1;
  for (int i = 0; i < 3; ++i) {
    const double h = b.g->size[i];
    if (std::abs(dx[i]) < 1e-15) {
      if (std::abs(x0[i]) > h) return false;
      continue;
    }
    const double ta = (-h - x0[i]) / dx[i], tb = (h - x0[i]) / dx[i];
    s0 = std::max(s0, std::min(ta, tb));
    s1 = std::min(s1, std::max(ta, tb));
    if (s0 > s1) return false;
  }
  return true;
}

}  // namespace

// Box edge across box edge (no corner inside the other, e.g. two boxes crosswise on
// their edges): for each non-parallel edge pair whose closest points xa, xb are
// interior to both edges, with xa inside b and xb inside a (each at least half the
// edge-edge distance deep, see below), a contact along the edge-edge direction
// (xa - xb: moves b's edge past a's), depth |xa - xb|, at xb. The closest points
// minimise |xa - xb|, so the gradient at fixed edge parameters is exact, and xa, xb
// lie on one line of action. Edges with a corner inside the other box are skipped:
// that corner's contact reports the touch (so the contact switches off with nonzero
// depth when a corner enters: the energy jumps there, see README, Missing).
void edges_across(const Placed& a, const Placed& b, double margin, std::vector<PairContact>* out) {
  Vec3 pa[12], da[12], pb[12], db[12], n;
  bool ma[12], mb[12];
  box_edges(a, b, pa, da, ma);
  box_edges(b, a, pb, db, mb);
  for (int i = 0; i < 12; ++i) {
    ma[i] = !ma[i] && edge_may_meet(b, pa[i], da[i]);
    mb[i] = !mb[i] && edge_may_meet(a, pb[i], db[i]);
  }
  for (int i = 0; i < 12; ++i) {
    if (!ma[i]) continue;
    for (int j = 0; j < 12; ++j) {
      if (!mb[j]) continue;
      if (da[i].cross(db[j]).squaredNorm() < 1e-4 * da[i].squaredNorm() * db[j].squaredNorm()) continue;
      double s, t;
      segment_closest(pa[i], da[i], pb[j], db[j], &s, &t);
      if (!(s > 0 && s < 1 && t > 0 && t < 1)) continue;  // an end: a corner's touch
      const Vec3 xa = pa[i] + s * da[i], xb = pb[j] + t * db[j];
      const double depth = (xa - xb).norm();
      // A crossing: xa lies in b's right-angle wedge at xb, at least depth cos 45 deg
      // deep (and xb in a's); edges that merely pass through both boxes far apart, or
      // an edge lying in the other's face, fail this.
      const double limit = -0.5 * depth;
      if (!(depth > 1e-12) || shape_distance(GeomType::Box, b.g->size, b.c, b.r, xa, &n) > limit ||
          shape_distance(GeomType::Box, a.g->size, a.c, a.r, xb, &n) > limit)
        continue;
      out->push_back({a.g->body, b.g->body, xb, (xa - xb) / depth, depth + margin});
    }
  }
}

}  // namespace pliant::articulated::contact_internal
