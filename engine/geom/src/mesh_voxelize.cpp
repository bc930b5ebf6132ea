// Mesh voxelisation by ray parity: for every sub-sample row (y, z) a ray along +x
// crosses the triangles; sorted crossing abscissae toggle inside/outside. Rays
// through a shared edge or vertex would be counted twice, so each ray is nudged by
// a tiny irrational fraction of the sub-sample spacing (a simulation-of-simplicity
// style tie break) and the edge tests are strict. Rows are independent (OpenMP).
#include <algorithm>
#include <cmath>

#include "pliant/geom/keyframe_raster.h"

namespace pliant::geom {
namespace {

// x where the line {y = py, z = pz} crosses triangle (a, b, c), if it does. Uses the
// 2D edge functions in the (y, z) plane with a consistent tie rule.
bool cross_x(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
             double py, double pz, double* x) {
  auto edge = [&](const std::array<double, 3>& p, const std::array<double, 3>& q) {
    return (q[1] - p[1]) * (pz - p[2]) - (q[2] - p[2]) * (py - p[1]);
  };
  const double e0 = edge(b, c), e1 = edge(c, a), e2 = edge(a, b);
  const bool pos = e0 > 0 && e1 > 0 && e2 > 0, neg = e0 < 0 && e1 < 0 && e2 < 0;
  const double sum = e0 + e1 + e2;
  if ((!pos && !neg) || sum == 0) return false;
  *x = (e0 * a[0] + e1 * b[0] + e2 * c[0]) / sum;
  return true;
}

}  // namespace

std::vector<float> raster_mesh(const RasterGrid& g, const TriangleMesh& mesh, const Placement& p, double size_m,
                               int supersample) {
  if (g.dim != 3) throw GeomError("mesh targets need a 3D grid");
  const auto bb = mesh.bounds();
  double extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::max(extent, bb[1][a] - bb[0][a]);
  if (!(extent > 0)) throw GeomError("mesh has a zero-size bounding box");
  // World position of every vertex: centre the box, scale, rotate (any axis), move.
  const double s = size_m * p.scale / extent;
  const Rotation3 R = placement_rotation(p);
  std::vector<std::array<double, 3>> w(mesh.vertices.size());
  for (size_t i = 0; i < w.size(); ++i) {
    std::array<double, 3> q;
    for (int a = 0; a < 3; ++a) q[a] = (mesh.vertices[i][a] - 0.5 * (bb[0][a] + bb[1][a])) * s;
    for (int a = 0; a < 3; ++a) w[i][a] = R[a][0] * q[0] + R[a][1] * q[1] + R[a][2] * q[2] + p.center_m[a];
  }
  const int ss = std::max(1, supersample);
  const double h = g.cell_size_m, sub = h / ss;
  const int rows_y = g.n[1] * ss, rows_z = g.n[2] * ss, nxs = g.n[0] * ss;
  std::vector<float> out(g.cells(), 0.0f);
  const double norm = 1.0 / (double(ss) * ss * ss);
#pragma omp parallel
  {
    std::vector<double> xs;
#pragma omp for collapse(2) schedule(dynamic, 4)
    for (int rz = 0; rz < rows_z; ++rz)
      for (int ry = 0; ry < rows_y; ++ry) {
        const double py = (ry + 0.5 + 1.41421356e-6) * sub, pz = (rz + 0.5 + 2.71828183e-6) * sub;
        xs.clear();
        for (const auto& t : mesh.triangles) {
          double x;
          if (cross_x(w[t[0]], w[t[1]], w[t[2]], py, pz, &x)) xs.push_back(x);
        }
        if (xs.size() < 2) continue;
        std::sort(xs.begin(), xs.end());
        // Sub-sample xi is inside when an odd number of crossings lie left of it.
        size_t c = 0;
        for (int xi = 0; xi < nxs; ++xi) {
          const double px = (xi + 0.5) * sub;
          while (c < xs.size() && xs[c] < px) ++c;
          if (c % 2 == 1) {
            const size_t cell = size_t(xi / ss) + size_t(g.n[0]) * (size_t(ry / ss) + size_t(g.n[1]) * (rz / ss));
#pragma omp atomic
            out[cell] += float(norm);
          }
        }
      }
  }
  return out;
}

}  // namespace pliant::geom
