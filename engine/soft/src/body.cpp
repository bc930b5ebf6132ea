// Mesh repair, winding-number lattice and surface embedding (see body.h).
#include "pliant/soft/body.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <stdexcept>
#include <unordered_map>

namespace pliant::soft {
namespace {

using Eigen::Vector3d;

struct CellKey {
  long long i, j, k;
  bool operator<(const CellKey& o) const { return std::tie(i, j, k) < std::tie(o.i, o.j, o.k); }
};

}  // namespace

SurfaceMesh repair_mesh(const geom::TriangleMesh& in, RepairReport* report, double weld_tol_rel) {
  RepairReport rep;
  if (in.vertices.empty() || in.triangles.empty()) throw BodyError("mesh has no triangles");
  for (const auto& v : in.vertices)
    for (double c : v)
      if (!std::isfinite(c)) throw BodyError("mesh has a vertex with a non-finite coordinate");
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  for (const auto& v : in.vertices) {
    const Vector3d p(v[0], v[1], v[2]);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diag = (hi - lo).norm();
  const double extent = (hi - lo).maxCoeff();
  if (extent > 1e4) throw BodyError("absurd scale: mesh extent " + std::to_string(extent) + " m is above 1e4 m");
  if (extent < 1e-4) throw BodyError("absurd scale: mesh extent " + std::to_string(extent) + " m is below 1e-4 m");
  // Weld on a hash grid of cell tol: vertices in the same cell merge (cheap, and
  // enough for the duplicated seams exporters write).
  const double tol = std::max(diag * weld_tol_rel, 1e-300);
  std::map<CellKey, int> grid;
  std::vector<int> remap(in.vertices.size());
  std::vector<Vector3d> welded;
  for (size_t v = 0; v < in.vertices.size(); ++v) {
    const Vector3d p(in.vertices[v][0], in.vertices[v][1], in.vertices[v][2]);
    const CellKey key{(long long)std::floor((p[0] - lo[0]) / tol), (long long)std::floor((p[1] - lo[1]) / tol),
                      (long long)std::floor((p[2] - lo[2]) / tol)};
    // Look in the 27 neighbouring cells so pairs straddling a cell face still weld.
    int found = -1;
    for (int dz = -1; dz <= 1 && found < 0; ++dz)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dx = -1; dx <= 1 && found < 0; ++dx) {
          auto it = grid.find(CellKey{key.i + dx, key.j + dy, key.k + dz});
          if (it != grid.end() && (welded[it->second] - p).norm() <= tol) found = it->second;
        }
    if (found >= 0) {
      ++rep.welded_vertices;
      remap[v] = found;
      continue;
    }
    grid.emplace(key, int(welded.size()));
    remap[v] = int(welded.size());
    welded.push_back(p);
  }
  std::vector<std::array<int, 3>> tris;
  const double min_area = 1e-14 * diag * diag;
  for (const auto& t : in.triangles) {
    if (t[0] >= in.vertices.size() || t[1] >= in.vertices.size() || t[2] >= in.vertices.size()) {
      ++rep.dropped_triangles;
      continue;
    }
    const int a = remap[t[0]], b = remap[t[1]], c = remap[t[2]];
    if (a == b || b == c || a == c) {
      ++rep.dropped_triangles;
      continue;
    }
    if (0.5 * (welded[b] - welded[a]).cross(welded[c] - welded[a]).norm() <= min_area) {
      ++rep.dropped_triangles;
      continue;
    }
    tris.push_back({a, b, c});
  }
  if (tris.empty()) throw BodyError("mesh has no area (every triangle is degenerate)");
  std::vector<int> used(welded.size(), -1);
  SurfaceMesh out;
  for (auto& t : tris)
    for (int& v : t) {
      if (used[v] < 0) {
        used[v] = int(out.vertices.size());
        out.vertices.push_back(welded[v]);
      }
      v = used[v];
    }
  rep.unused_vertices = int(welded.size() - out.vertices.size());
  out.triangles = std::move(tris);
  if (report) *report = rep;
  return out;
}

double winding_number(const SurfaceMesh& m, const Vector3d& p) {
  // Solid angle of each triangle (Van Oosterom & Strackee 1983), summed over 4 pi.
  double sum = 0;
  for (const auto& t : m.triangles) {
    const Vector3d a = m.vertices[t[0]] - p, b = m.vertices[t[1]] - p, c = m.vertices[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * M_PI);
}

Lattice build_lattice(const SurfaceMesh& mesh, int resolution, double density) {
  if (resolution < 2 || resolution > 128) throw BodyError("lattice resolution must be in 2..128");
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  for (const auto& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double h = (hi - lo).maxCoeff() / resolution;
  Lattice lat;
  lat.cell_size_m = h;
  // One cell of padding around the box so surface cells always exist.
  lat.origin_m = lo - Vector3d::Constant(h);
  std::array<int, 3> n;
  for (int a = 0; a < 3; ++a) n[a] = int(std::ceil((hi[a] - lat.origin_m[a]) / h)) + 1;
  const auto cid = [&](int i, int j, int k) { return (size_t(k) * n[1] + j) * n[0] + i; };
  std::vector<char> solid(size_t(n[0]) * n[1] * n[2], 0);
  // Cells the surface passes through: sample each triangle densely enough (h/3).
  for (const auto& t : mesh.triangles) {
    const Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const double len = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
    // Samples are nudged a hair against the normal, to the inside of an outward
    // mesh, so faces lying exactly on cell planes mark the inner cell only.
    // Points on edges and corners are also pulled a hair towards the centroid.
    const Vector3d nudge = -1e-6 * h * (b - a).cross(c - a).normalized();
    const Vector3d centroid = (a + b + c) / 3;
    const int s = std::max(1, int(std::ceil(3 * len / h)));
    for (int u = 0; u <= s; ++u)
      for (int v = 0; u + v <= s; ++v) {
        const Vector3d p = a + (b - a) * (double(u) / s) + (c - a) * (double(v) / s);
        const Vector3d g = (p + nudge + 1e-6 * (centroid - p) - lat.origin_m) / h;
        const int i = std::clamp(int(g[0]), 0, n[0] - 1), j = std::clamp(int(g[1]), 0, n[1] - 1),
                  k = std::clamp(int(g[2]), 0, n[2] - 1);
        solid[cid(i, j, k)] = 1;
      }
  }
  // Inside cells by winding number at the centre.
  const long long total = (long long)solid.size();
#pragma omp parallel for schedule(dynamic, 16)
  for (long long c = 0; c < total; ++c) {
    if (solid[c]) continue;
    const int i = int(c % n[0]), j = int((c / n[0]) % n[1]), k = int(c / (size_t(n[0]) * n[1]));
    const Vector3d p = lat.origin_m + h * Vector3d(i + 0.5, j + 0.5, k + 0.5);
    if (std::abs(winding_number(mesh, p)) > 0.5) solid[c] = 1;
  }
  // Face-connected pieces; keep the largest.
  std::vector<int> piece(solid.size(), -1);
  std::vector<int> piece_size;
  for (size_t c0 = 0; c0 < solid.size(); ++c0) {
    if (!solid[c0] || piece[c0] >= 0) continue;
    const int id = int(piece_size.size());
    piece_size.push_back(0);
    std::queue<size_t> q;
    q.push(c0);
    piece[c0] = id;
    while (!q.empty()) {
      const size_t c = q.front();
      q.pop();
      ++piece_size[id];
      const int i = int(c % n[0]), j = int((c / n[0]) % n[1]), k = int(c / (size_t(n[0]) * n[1]));
      const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k}, {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
      for (const auto& d : nb) {
        if (d[0] < 0 || d[1] < 0 || d[2] < 0 || d[0] >= n[0] || d[1] >= n[1] || d[2] >= n[2]) continue;
        const size_t e = cid(d[0], d[1], d[2]);
        if (solid[e] && piece[e] < 0) {
          piece[e] = id;
          q.push(e);
        }
      }
    }
  }
  if (piece_size.empty()) throw BodyError("no solid cell: the mesh encloses no volume at this resolution");
  const int keep = int(std::max_element(piece_size.begin(), piece_size.end()) - piece_size.begin());
  lat.pieces_found = int(piece_size.size());
  lat.pieces_dropped = lat.pieces_found - 1;
  // Nodes and cells.
  const auto nid = [&](int i, int j, int k) { return (size_t(k) * (n[1] + 1) + j) * (n[0] + 1) + i; };
  std::unordered_map<size_t, int> node_of;
  std::vector<int> cell_of(solid.size(), -1);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const size_t c = cid(i, j, k);
        if (piece[c] != keep) continue;
        std::array<int, 8> ids;
        for (int a = 0; a < 8; ++a) {
          const int ii = i + (a & 1), jj = j + ((a >> 1) & 1), kk = k + ((a >> 2) & 1);
          auto [it, fresh] = node_of.emplace(nid(ii, jj, kk), int(lat.rest.size()));
          if (fresh) lat.rest.push_back(lat.origin_m + h * Vector3d(ii, jj, kk));
          ids[a] = it->second;
        }
        cell_of[c] = int(lat.cells.size());
        lat.cells.push_back(ids);
        lat.cell_ijk.push_back({i, j, k});
      }
  // Boundary quads: faces of kept cells whose neighbour is not kept. Corner order
  // chosen so (b-a)x(c-a) points out of the cell.
  static const int face_corners[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  static const int face_dir[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  for (size_t e = 0; e < lat.cells.size(); ++e) {
    const auto& ijk = lat.cell_ijk[e];
    for (int f = 0; f < 6; ++f) {
      const int i = ijk[0] + face_dir[f][0], j = ijk[1] + face_dir[f][1], k = ijk[2] + face_dir[f][2];
      const bool inside = i >= 0 && j >= 0 && k >= 0 && i < n[0] && j < n[1] && k < n[2] && cell_of[cid(i, j, k)] >= 0;
      if (inside) continue;
      lat.boundary_faces.push_back({lat.cells[e][face_corners[f][0]], lat.cells[e][face_corners[f][1]],
                                    lat.cells[e][face_corners[f][2]], lat.cells[e][face_corners[f][3]]});
    }
  }
  // Lumped mass: each cell's mass split equally over its 8 nodes.
  lat.node_mass_kg.assign(lat.rest.size(), 0.0);
  const double cell_mass = density * h * h * h;
  for (const auto& c : lat.cells)
    for (int a = 0; a < 8; ++a) lat.node_mass_kg[c[a]] += cell_mass / 8;
  // Embedding: the containing kept cell, else the nearest kept cell (clamped weights).
  lat.vertex_cell.resize(mesh.vertices.size());
  lat.vertex_weight.resize(mesh.vertices.size());
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vector3d g = (mesh.vertices[v] - lat.origin_m) / h;
    const int i = std::clamp(int(g[0]), 0, n[0] - 1), j = std::clamp(int(g[1]), 0, n[1] - 1),
              k = std::clamp(int(g[2]), 0, n[2] - 1);
    int e = cell_of[cid(i, j, k)];
    if (e < 0) {
      double best = 1e300;
      for (size_t c = 0; c < lat.cells.size(); ++c) {
        const auto& q = lat.cell_ijk[c];
        const double d = (Vector3d(q[0] + 0.5, q[1] + 0.5, q[2] + 0.5) - g).squaredNorm();
        if (d < best) best = d, e = int(c);
      }
    }
    const auto& q = lat.cell_ijk[e];
    Vector3d s = g - Vector3d(q[0], q[1], q[2]);
    s = s.cwiseMax(0.0).cwiseMin(1.0);
    lat.vertex_cell[v] = e;
    for (int a = 0; a < 8; ++a)
      lat.vertex_weight[v][a] = ((a & 1) ? s[0] : 1 - s[0]) * (((a >> 1) & 1) ? s[1] : 1 - s[1]) *
                                (((a >> 2) & 1) ? s[2] : 1 - s[2]);
  }
  return lat;
}

void embed_surface(const Lattice& lat, const Eigen::VectorXd& x, std::vector<Vector3d>& out) {
  out.resize(lat.vertex_cell.size());
  for (size_t v = 0; v < out.size(); ++v) {
    Vector3d p = Vector3d::Zero();
    const auto& cell = lat.cells[lat.vertex_cell[v]];
    for (int a = 0; a < 8; ++a) p += lat.vertex_weight[v][a] * x.segment<3>(3 * cell[a]);
    out[v] = p;
  }
}

void add_vertex_force(const Lattice& lat, int vertex, const Vector3d& force, Eigen::VectorXd& f) {
  if (vertex < 0 || size_t(vertex) >= lat.vertex_cell.size())
    throw std::out_of_range("add_vertex_force: surface vertex " + std::to_string(vertex) + " is not embedded");
  if (f.size() != 3 * lat.nodes()) f.setZero(3 * lat.nodes());
  const auto& cell = lat.cells[lat.vertex_cell[vertex]];
  for (int a = 0; a < 8; ++a) f.segment<3>(3 * cell[a]) += lat.vertex_weight[vertex][a] * force;
}

}  // namespace pliant::soft
