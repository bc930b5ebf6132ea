// Mesh containers: a closed triangle mesh sampled into a signed distance grid.
// - Closed: every edge (vertices welded by position) must be used an even
//   number of times; an odd count is a boundary (a hole) and is refused.
// - Sign: ray parity along +y per sample column (one sorted crossing list per
//   column; the column is nudged off the lattice so it misses edges and
//   vertices). Pieces may touch but must not overlap (parity, not winding).
// - Distance: exact point-triangle distance (Ericson, "Real-Time Collision
//   Detection", 5.1.5) within a band of a few samples around each triangle,
//   clamped beyond: the solver needs the surface's neighbourhood only.
// - Cavity: the non-material samples below the rim (the mesh's top) that the
//   outside cannot reach when the rim plane is closed by a lid (flood fill).
#include "container_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <string>

#include "pliant/geom/triangle_mesh.h"

namespace pliant::liquid {
namespace {

using P3 = std::array<double, 3>;

P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot3(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Squared distance from p to triangle abc (closest-point by Voronoi regions).
double dist2_triangle(const P3& p, const P3& a, const P3& b, const P3& c) {
  const P3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  auto at = [&](double v, double w) {
    const P3 q{a[0] + v * ab[0] + w * ac[0], a[1] + v * ab[1] + w * ac[1], a[2] + v * ab[2] + w * ac[2]};
    const P3 d = sub(p, q);
    return dot3(d, d);
  };
  const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
  if (d1 <= 0 && d2 <= 0) return at(0, 0);
  const P3 bp = sub(p, b);
  const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
  if (d3 >= 0 && d4 <= d3) return at(1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return at(d1 / (d1 - d3), 0);
  const P3 cp = sub(p, c);
  const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
  if (d6 >= 0 && d5 <= d6) return at(0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return at(0, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at(1 - w, w);
  }
  const double den = 1 / (va + vb + vc);
  return at(vb * den, vc * den);
}

// Odd-count edges after welding vertices by exact position.
void check_closed(const geom::TriangleMesh& mesh) {
  std::vector<uint32_t> order(mesh.vertices.size()), weld(mesh.vertices.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return mesh.vertices[a] < mesh.vertices[b]; });
  for (size_t i = 0; i < order.size(); ++i)
    weld[order[i]] = i > 0 && mesh.vertices[order[i]] == mesh.vertices[order[i - 1]] ? weld[order[i - 1]] : order[i];
  std::vector<uint64_t> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      uint64_t a = weld[t[e]], b = weld[t[(e + 1) % 3]];
      if (a == b) continue;  // degenerate edge
      if (a > b) std::swap(a, b);
      edges.push_back(a << 32 | b);
    }
  std::sort(edges.begin(), edges.end());
  size_t open = 0;
  uint64_t first = 0;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if ((j - i) % 2 == 1) {
      if (open == 0) first = edges[i];
      ++open;
    }
    i = j;
  }
  if (open > 0) {
    const auto& a = mesh.vertices[first >> 32];
    const auto& b = mesh.vertices[first & 0xffffffffu];
    char buf[200];
    std::snprintf(buf, sizeof buf, "(%g, %g, %g)-(%g, %g, %g)", a[0], a[1], a[2], b[0], b[1], b[2]);
    throw MeshContainerError("mesh is not closed: " + std::to_string(open) +
                             " boundary edge(s), e.g. " + buf + "; a container mesh must be watertight");
  }
}

}  // namespace

double MeshContainerField::distance(const Vec3& p) const {
  double u[3], out2 = 0;
  int i0[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    u[a] = (p[a] - lo[a]) / h;
    const double c = std::clamp(u[a], 0.0, double(n[a] - 1));
    out2 += (u[a] - c) * (u[a] - c);
    i0[a] = std::min(int(c), std::max(0, n[a] - 2));
    t[a] = n[a] > 1 ? c - i0[a] : 0.0;
  }
  auto at = [&](int di, int dj, int dk) {
    return double(sdf[index(std::min(i0[0] + di, n[0] - 1), std::min(i0[1] + dj, n[1] - 1),
                            std::min(i0[2] + dk, n[2] - 1))]);
  };
  double v = 0;
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di)
        v += (di ? t[0] : 1 - t[0]) * (dj ? t[1] : 1 - t[1]) * (dk ? t[2] : 1 - t[2]) * at(di, dj, dk);
  return v + std::sqrt(out2) * h;
}

bool MeshContainerField::in_cavity(const Vec3& p) const {
  int idx[3];
  for (int a = 0; a < 3; ++a) {
    idx[a] = int(std::lround((p[a] - lo[a]) / h));
    if (idx[a] < 0 || idx[a] >= n[a]) return false;
  }
  return cavity[index(idx[0], idx[1], idx[2])];
}

bool MeshContainerField::column_open(const Vec3& p) const {
  const int i = int(std::lround((p[0] - lo[0]) / h)), k = int(std::lround((p[2] - lo[2]) / h));
  if (i < 0 || i >= n[0] || k < 0 || k >= n[2]) return false;
  return open_column[i + n[0] * k];
}

ContainerShape mesh_container(const geom::TriangleMesh& src, double scale, double sample_m) {
  check_closed(src);
  geom::TriangleMesh mesh = src;
  for (auto& v : mesh.vertices)
    for (double& c : v) c *= scale;
  const auto box = mesh.bounds();
  double extent_min = 1e300;
  for (int a = 0; a < 3; ++a) extent_min = std::min(extent_min, box[1][a] - box[0][a]);
  const double vol = std::abs(mesh.signed_volume());
  if (!(vol > 1e-12) || !(extent_min > 1e-6))
    throw MeshContainerError("mesh has no volume (signed volume " + std::to_string(vol) +
                             " m^3 after scale); a container mesh must enclose its wall material");

  auto f = std::make_shared<MeshContainerField>();
  // Keep the grid under ~4M samples: coarser sampling for huge meshes.
  double h = sample_m;
  auto count = [&](double hh) {
    double c = 1;
    for (int a = 0; a < 3; ++a) c *= (box[1][a] - box[0][a]) / hh + 12;
    return c;
  };
  while (count(h) > 4e6) h *= 1.25;
  const int pad = 5;
  f->h = h;
  f->band = (pad - 1) * h;
  Vec3 lo0{};
  for (int a = 0; a < 3; ++a) {
    f->n[a] = int(std::ceil((box[1][a] - box[0][a]) / h)) + 1 + 2 * pad;
    lo0[a] = box[0][a] - pad * h;
  }
  const int nx = f->n[0], ny = f->n[1], nz = f->n[2];
  const size_t total = size_t(nx) * ny * nz;
  f->sdf.assign(total, float(f->band));

  // Unsigned distance in the band around each triangle.
  const int reach = pad - 1;
  for (const auto& tri : mesh.triangles) {
    const P3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    int lo[3], hi[3];
    for (int ax = 0; ax < 3; ++ax) {
      const double mn = std::min({a[ax], b[ax], c[ax]}), mx = std::max({a[ax], b[ax], c[ax]});
      lo[ax] = std::max(0, int(std::floor((mn - lo0[ax]) / h)) - reach);
      hi[ax] = std::min(f->n[ax] - 1, int(std::ceil((mx - lo0[ax]) / h)) + reach);
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const P3 p{lo0[0] + i * h, lo0[1] + j * h, lo0[2] + k * h};
          float& d = f->sdf[f->index(i, j, k)];
          const double dd = std::sqrt(dist2_triangle(p, a, b, c));
          if (dd < d) d = float(dd);
        }
  }
  // Sign by ray parity along +y: crossings of each (i, k) column, sorted.
  std::vector<std::vector<double>> cross(size_t(nx) * nz);
  const double ex = 1.2345e-4 * h, ez = 0.98765e-4 * h;  // off the lattice: misses edges
  for (const auto& tri : mesh.triangles) {
    const P3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    const double area = (b[0] - a[0]) * (c[2] - a[2]) - (c[0] - a[0]) * (b[2] - a[2]);
    if (std::abs(area) < 1e-300) continue;  // edge-on to the ray
    const double mnx = std::min({a[0], b[0], c[0]}), mxx = std::max({a[0], b[0], c[0]});
    const double mnz = std::min({a[2], b[2], c[2]}), mxz = std::max({a[2], b[2], c[2]});
    const int i0 = std::max(0, int(std::ceil((mnx - lo0[0] - ex) / h))), i1 = std::min(nx - 1, int(std::floor((mxx - lo0[0] - ex) / h)));
    const int k0 = std::max(0, int(std::ceil((mnz - lo0[2] - ez) / h))), k1 = std::min(nz - 1, int(std::floor((mxz - lo0[2] - ez) / h)));
    for (int k = k0; k <= k1; ++k)
      for (int i = i0; i <= i1; ++i) {
        const double x = lo0[0] + i * h + ex, z = lo0[2] + k * h + ez;
        // Barycentric coordinates of (x, z) in the projected triangle.
        const double w1 = ((x - a[0]) * (c[2] - a[2]) - (c[0] - a[0]) * (z - a[2])) / area;
        const double w2 = ((b[0] - a[0]) * (z - a[2]) - (x - a[0]) * (b[2] - a[2])) / area;
        if (w1 < 0 || w2 < 0 || w1 + w2 > 1) continue;
        cross[i + size_t(nx) * k].push_back(a[1] + w1 * (b[1] - a[1]) + w2 * (c[1] - a[1]));
      }
  }
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i) {
      auto& cs = cross[i + size_t(nx) * k];
      std::sort(cs.begin(), cs.end());
      size_t below = 0;
      for (int j = 0; j < ny; ++j) {
        const double y = lo0[1] + j * h;
        while (below < cs.size() && cs[below] < y) ++below;
        if (below % 2 == 1) {
          float& d = f->sdf[f->index(i, j, k)];
          d = -std::abs(d);
        }
      }
    }

  // Cavity: flood the outside from the grid's border, below the rim only.
  const double rim = box[1][1];
  int jrim = 0;  // highest sample row clearly below the rim (a row on the rim's face has no reliable sign)
  while (jrim + 1 < ny && lo0[1] + (jrim + 1) * h <= rim - 0.25 * h) ++jrim;
  std::vector<unsigned char> outside(total, 0);
  std::queue<int> q;
  auto seed = [&](int i, int j, int k) {
    const int id = f->index(i, j, k);
    if (j > jrim || outside[id] || f->sdf[id] < 0) return;
    outside[id] = 1;
    q.push(id);
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j <= jrim; ++j)
      for (int i = 0; i < nx; ++i)
        if (i == 0 || i == nx - 1 || j == 0 || k == 0 || k == nz - 1) seed(i, j, k);
  while (!q.empty()) {
    const int id = q.front();
    q.pop();
    const int i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
    if (i > 0) seed(i - 1, j, k);
    if (i + 1 < nx) seed(i + 1, j, k);
    if (j > 0) seed(i, j - 1, k);
    if (j + 1 < ny) seed(i, j + 1, k);
    if (k > 0) seed(i, j, k - 1);
    if (k + 1 < nz) seed(i, j, k + 1);
  }
  f->cavity.assign(total, 0);
  size_t cavity_count = 0, top_count = 0;
  double floor_y = 1e300, cx = 0, cz = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j <= jrim; ++j)
      for (int i = 0; i < nx; ++i) {
        const int id = f->index(i, j, k);
        if (outside[id] || f->sdf[id] < 0) continue;
        f->cavity[id] = 1, ++cavity_count;
        // The floor lies below the lowest cavity sample by its distance.
        floor_y = std::min(floor_y, lo0[1] + j * h - double(f->sdf[id]));
        if (j == jrim) cx += lo0[0] + i * h, cz += lo0[2] + k * h, ++top_count;
      }
  if (cavity_count == 0)
    throw MeshContainerError("mesh encloses no cavity open at the top (a solid, or its opening is not at its top +y)");
  if (top_count == 0)
    throw MeshContainerError("the mesh's cavity does not reach its top (+y): the container is closed");
  cx /= double(top_count), cz /= double(top_count);
  f->open_column.assign(size_t(nx) * nz, 0);
  double rx = 0, rz = 0;
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i)
      if (f->cavity[f->index(i, jrim, k)]) {
        f->open_column[i + size_t(nx) * k] = 1;
        rx = std::max(rx, std::abs(lo0[0] + i * h - cx) + 0.5 * h);
        rz = std::max(rz, std::abs(lo0[2] + k * h - cz) + 0.5 * h);
      }
  // Container frame: opening centre above the origin, cavity floor at y = 0.
  f->lo = {lo0[0] - cx, lo0[1] - floor_y, lo0[2] - cz};
  f->volume3 = double(cavity_count) * h * h * h;
  const int kz = std::clamp(int(std::lround(-f->lo[2] / h)), 0, nz - 1);
  size_t slice = 0;
  for (int j = 0; j <= jrim; ++j)
    for (int i = 0; i < nx; ++i) slice += f->cavity[f->index(i, j, kz)];
  f->area2 = double(slice) * h * h;
  double reach2 = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner{(c & 1 ? box[1][0] : box[0][0]) - cx, (c & 2 ? box[1][1] : box[0][1]) - floor_y,
                      (c & 4 ? box[1][2] : box[0][2]) - cz};
    reach2 = std::max(reach2, dot3(corner, corner));
  }
  f->reach_m = std::sqrt(reach2);

  ContainerShape s;
  s.type = ContainerShape::Mesh;
  s.height_m = rim - floor_y;
  s.radius_m = rx;
  s.depth_m = rz;
  // Wall at the rim: the narrower side of the body around the opening.
  const double side = std::min({cx - box[0][0], box[1][0] - cx, cz - box[0][2], box[1][2] - cz});
  s.wall_m = std::max(h, side - std::max(rx, rz));
  s.neck_radius_m = rx;
  s.body_height_m = 0.6 * s.height_m;
  s.mesh = f;
  return s;
}

}  // namespace pliant::liquid
