// Segments against boxes: a capsule against a box (end spheres, the box's edges against
// the segment, the segment's deepest point where it penetrates the box), and a box's
// edges into another box (every vertex of an edge's depth profile in the other box).
#include <algorithm>
#include <cmath>

#include "contact_internal.h"

namespace pliant::articulated::contact_internal {

namespace {

// The six face lines of the box |x_i| <= h_i along x(t) = a + t u: line j is
// s_j (a_{j/2} + t u_{j/2}) - h_{j/2}, s_j = +1 for even j, -1 for odd. Their max is
// the signed distance inside the box (outside, a lower bound of it).
double face_line_envelope(const Vec3& a, const Vec3& u, const Vec3& h, double t) {
  double m = -1e300;
  for (int i = 0; i < 3; ++i) m = std::max(m, std::abs(a[i] + t * u[i]) - h[i]);
  return m;
}

// Where face lines j and k cross (false where they are parallel).
bool face_lines_cross(const Vec3& a, const Vec3& u, const Vec3& h, int j, int k, double* t) {
  const double sj = j & 1 ? -1 : 1, sk = k & 1 ? -1 : 1;
  const double slope = sj * u[j / 2] - sk * u[k / 2];
  if (std::abs(slope) < 1e-15) return false;
  *t = -(sj * a[j / 2] - h[j / 2] - sk * a[k / 2] + h[k / 2]) / slope;
  return true;
}

// Segment x(t) = a + t u, t in [0, 1], penetrating the box |x_i| <= h_i (box frame):
// its deepest point. Inside, the signed distance is the max of the six face lines
// l(t) = +-(a_i + t u_i) - h_i (outside, the true distance is >= that max, so a
// negative minimum of it is the segment's); a max of lines is least at t = 0, 1 or
// where two lines cross, so the minimum is exact. Returns false where the segment
// stays outside or the minimum is at an end (that end sphere is as deep); else the
// minimiser *t (the middle where the minimum is flat), the signed distance *d < 0 and
// its gradient in x at fixed t, *n (box frame): the face's unit normal, or at a kink
// between two faces a mix of their normals, |n| < 1.
bool segment_box_minimum(const Vec3& a, const Vec3& u, const Vec3& h, double* t_out, double* d_out, Vec3* n_out) {
  const double tol = 1e-12 * (h.maxCoeff() + a.cwiseAbs().maxCoeff() + u.cwiseAbs().maxCoeff());
  const auto g = [&](double t) { return face_line_envelope(a, u, h, t); };
  double cand[17];
  int nc = 0;
  cand[nc++] = 0;
  cand[nc++] = 1;
  for (int j = 0; j < 6; ++j)
    for (int k = j + 1; k < 6; ++k) {
      double t;
      if (face_lines_cross(a, u, h, j, k, &t) && t > 0 && t < 1) cand[nc++] = t;
    }
  double gmin = 1e300;
  for (int i = 0; i < nc; ++i) gmin = std::min(gmin, g(cand[i]));
  if (gmin < -tol) {
    if (g(0) <= gmin + tol || g(1) <= gmin + tol) return false;  // an end sphere is as deep
    double lo = 1, hi = 0;
    for (int i = 0; i < nc; ++i)
      if (g(cand[i]) <= gmin + tol) lo = std::min(lo, cand[i]), hi = std::max(hi, cand[i]);
    const double t = 0.5 * (lo + hi);
    const Vec3 x = a + t * u;
    // The active face lines at t: a flat minimum has one of slope 0; a kink, lines of
    // both signs. The minimum's gradient (minimax, Danskin) is the mix l1 n1 + l2 n2
    // of the steepest falling and rising lines' normals with l1 s1 + l2 s2 = 0.
    int fall = -1, rise = -1, flat = -1;
    double s_fall = 0, s_rise = 0;
    for (int j = 0; j < 6; ++j) {
      const int i = j / 2;
      const double sg = j & 1 ? -1 : 1, lj = sg * x[i] - h[i], sj = sg * u[i];
      if (lj < gmin - tol) continue;
      if (sj < s_fall) s_fall = sj, fall = j;
      if (sj > s_rise) s_rise = sj, rise = j;
      if (sj == 0 && flat < 0) flat = j;
    }
    Vec3 n = Vec3::Zero();
    if (fall >= 0 && rise >= 0) {
      n[fall / 2] += (fall & 1 ? -1 : 1) * s_rise / (s_rise - s_fall);
      n[rise / 2] += (rise & 1 ? -1 : 1) * -s_fall / (s_rise - s_fall);
    } else {
      const int j = flat >= 0 ? flat : fall >= 0 ? fall : rise;
      if (j < 0) return false;
      n[j / 2] = j & 1 ? -1 : 1;
    }
    *t_out = t;
    *d_out = gmin;
    *n_out = n;
    return n.squaredNorm() > 1e-12;
  }
  return false;  // outside: the end spheres and edges hold the segment's minimum (capsule_box)
}

}  // namespace

// Candidates: the end spheres against the box and the segment against each of the
// box's 12 edges (segment_closest, clamped on both: a continuous distance, whose
// gradient at the closest points is exact by the envelope theorem). The edges carry a
// capsule lying across one (two where it lies over a face with both ends beyond it, an
// end sphere and an edge where one end overhangs: two-point support, no rocking on one
// point), a box face across a capsule (its two edges) and a box corner in a capsule
// (its three edges: three times the old corner contact's stiffness there). Where the
// segment stays outside the box its nearest point lies at an end, on an edge or over a
// face between two edges at the same distance, so the candidates are exact; where it
// penetrates, its deepest point (depth d_s > every candidate's) replaces the deepest
// candidate: energy k/2 (d_s^2 + sum_i d_i^2 - max_i d_i^2), continuous as the segment
// enters (d_s -> max d_i, like capsule_capsule's crossing). d_s's gradient: the
// minimiser's motion drops out (envelope theorem); at a kink between two faces the
// deeper face's normal stands in for the faces' mix. The Gauss-Newton matrix k n n^T of
// every contact drops the closest points' and the normal's motion.
void capsule_box(const Placed& cap, const Placed& box, double margin, std::vector<PairContact>* out,
                 bool end_spheres) {
  const size_t first = out->size();
  if (end_spheres) end_spheres_against(cap, box, margin, out);
  const double rho = cap.g->size[0] + margin, hl = cap.g->size[1];
  const Vec3 p0 = cap.c - cap.r.col(2) * hl, dc = cap.r.col(2) * (2 * hl);
  const Vec3& h = box.g->size;
  for (int ax = 0; ax < 3; ++ax)
    for (int e = 0; e < 4; ++e) {
      const int u = (ax + 1) % 3, v = (ax + 2) % 3;
      Vec3 local;
      local[ax] = -h[ax];
      local[u] = (e & 1 ? 1 : -1) * h[u];
      local[v] = (e & 2 ? 1 : -1) * h[v];
      const Vec3 pe = box.c + box.r * local, de = box.r.col(ax) * (2 * h[ax]);
      double s, t;
      segment_closest(p0, dc, pe, de, &s, &t);
      const Vec3 xs = p0 + s * dc, diff = xs - (pe + t * de);
      const double dist = diff.norm();
      if (dist >= rho || !(dist > 1e-12)) continue;
      const Vec3 n = diff / dist;
      out->push_back({box.g->body, cap.g->body, xs - rho * n, n, rho - dist});
    }
  const Vec3 a = box.r.transpose() * (p0 - box.c), ul = box.r.transpose() * dc;
  double t, d;
  Vec3 nl;
  if (!segment_box_minimum(a, ul, h, &t, &d, &nl)) return;
  // (Against a static box the end spheres are not among the candidates: the deepest
  // point then replaces the deepest edge only, so the energy jumps by the difference
  // where, deep inside, the minimum reaches an end.)
  size_t deepest = first;
  for (size_t i = first + 1; i < out->size(); ++i)
    if ((*out)[i].depth > (*out)[deepest].depth) deepest = i;
  if (deepest < out->size()) out->erase(out->begin() + static_cast<long>(deepest));
  const double gain = nl.norm();
  const Vec3 n = box.r * nl / gain;
  out->push_back({box.g->body, cap.g->body, p0 + t * dc - rho * n, n, rho - d, ContactMix{}, gain});
}

namespace {

// Vertices of the depth profile of segment x(t) = a + t u (t in (0, 1)) inside the box
// |x_i| <= h_i (box frame): the breakpoints of g(t) = max of the six face lines
// l_j(t) = +-(a_i + t u_i) - h_i where g < 0, at most 15 (one per pair of lines). For
// an edge lying across a face these are the two ends of its pressed interval (where
// it passes under the face's side planes), for two edges crossing the one peak. The
// value at a vertex, l_1 = l_2 at t*(q), has the gradient (s_2 dl_1 - s_1 dl_2) /
// (s_2 - s_1) (t*'s motion included; s the lines' slopes in t), a mix of the two
// faces' normals (the steepest falling and rising active lines; both may fall or
// rise): *ns (box frame), |n| the contact's gain. Returns their number.
int segment_box_vertices(const Vec3& a, const Vec3& u, const Vec3& h, double* ts, double* ds, Vec3* ns) {
  const double tol = 1e-12 * (h.maxCoeff() + a.cwiseAbs().maxCoeff() + u.cwiseAbs().maxCoeff());
  // Every vertex lies inside the box by more than tol (g < -tol): a segment that stays
  // outside one slab |x_i| <= h_i (by more than tol / 2, which g's round-off cannot
  // bridge) has none. Most edges of the candidate pairs in a pile never enter.
  for (int i = 0; i < 3; ++i) {
    const double e0 = a[i], e1 = a[i] + u[i];
    const double closest = (e0 < 0) != (e1 < 0) ? 0 : std::min(std::abs(e0), std::abs(e1));
    if (closest - h[i] > -0.5 * tol) return 0;
  }
  const auto g = [&](double t) { return face_line_envelope(a, u, h, t); };
  int nv = 0;
  for (int j = 0; j < 6; ++j)
    for (int k = j + 1; k < 6; ++k) {
      double t;
      if (!face_lines_cross(a, u, h, j, k, &t) || !(t > 0 && t < 1)) continue;
      const double sj = j & 1 ? -1 : 1;
      const double gt = g(t), lj = sj * (a[j / 2] + t * u[j / 2]) - h[j / 2];
      if (gt >= -tol || lj < gt - tol) continue;  // outside the box, or under the envelope
      bool seen = false;  // three lines through one point
      for (int v = 0; v < nv; ++v) seen = seen || std::abs(ts[v] - t) < 1e-12;
      if (seen) continue;
      const Vec3 x = a + t * u;
      int lo = -1, hi = -1;
      double s_lo = 1e300, s_hi = -1e300;
      for (int q = 0; q < 6; ++q) {
        const int i = q / 2;
        const double sg = q & 1 ? -1 : 1, sq = sg * u[i];
        if (sg * x[i] - h[i] < gt - tol) continue;
        if (sq < s_lo) s_lo = sq, lo = q;
        if (sq > s_hi) s_hi = sq, hi = q;
      }
      if (lo < 0 || hi < 0 || !(s_hi - s_lo > 1e-15)) continue;
      Vec3 n = Vec3::Zero();
      n[lo / 2] += (lo & 1 ? -1 : 1) * s_hi / (s_hi - s_lo);
      n[hi / 2] += (hi & 1 ? -1 : 1) * -s_lo / (s_hi - s_lo);
      if (n.squaredNorm() <= 1e-12) continue;
      ts[nv] = t;
      ds[nv] = gt;
      ns[nv] = n;
      ++nv;
    }
  return nv;
}

// Box a's edges into box b: a contact at every vertex of each edge's depth profile in b
// (segment_box_vertices; an edge pressed into b's face with both corners outside, a box
// lying across another's edge: the corners missed these and the box sank), depth
// margin - d, on top of the corners' contacts. A box lying flat across another's edge
// touches on a polygon whose corners are its corners in the other box and the two
// points where the edges cross; these are those points (each crossing found from both
// edges, as two crossing edges' peak is). The former rule (one contact at each edge's
// deepest point, in place of the deeper corner) jumped the contact by the pressed
// interval's length (and a corner by the edge's) as the resting box tilted by 1e-6
// rad either way: a kinked energy whose minimum LM could only approach by shrinking
// steps (pile: 11.25 LM iterations per step). Where a vertex reaches an edge's end
// (the corner on b's medial plane, i.e. at b's edge) or two vertices merge, a
// contact ends with its depth > 0: the energy jumps by k/2 d^2 there.
void box_edges_into(const Placed& a, const Placed& b, double margin, std::vector<PairContact>* out) {
  const Vec3& h = a.g->size;
  const Mat3 rt = b.r.transpose();
  for (int ax = 0; ax < 3; ++ax)
    for (int e = 0; e < 4; ++e) {
      const int u = (ax + 1) % 3, v = (ax + 2) % 3, start = (e & 1) << u | (e >> 1 & 1) << v;
      const Vec3 p0 = a.c + a.r * box_corner(h, start), d = a.r.col(ax) * (2 * h[ax]);
      double ts[15], ds[15];
      Vec3 ns[15];
      const int nv = segment_box_vertices(rt * (p0 - b.c), rt * d, b.g->size, ts, ds, ns);
      for (int i = 0; i < nv; ++i) {
        const double gain = ns[i].norm();
        const Vec3 n = b.r * ns[i] / gain;
        // b's face pushes a's edge: body_a = b, body_b = a, along b's outward normal.
        out->push_back({b.g->body, a.g->body, p0 + ts[i] * d - margin * n, n, margin - ds[i], ContactMix{}, gain});
      }
    }
}

}  // namespace

// Box against box: each box's corners in the other (point_against, the margin as
// radius) and each box's edges into the other (box_edges_into). Two boxes crossing on
// their edges get both edges' contacts, at the kink between two faces each (mixed
// normals): for the 45-degree crosswise pair their forces sum to k times the edges'
// distance, which the former edge-edge contact gave alone (it switched off with a
// jump where a corner entered; removed).
void box_box(const Placed& a, const Placed& b, double margin, std::vector<PairContact>* out) {
  corners_against(a, b, margin, out);
  corners_against(b, a, margin, out);
  box_edges_into(a, b, margin, out);
  box_edges_into(b, a, margin, out);
}

}  // namespace pliant::articulated::contact_internal
