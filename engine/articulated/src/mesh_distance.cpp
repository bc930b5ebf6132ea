// Signed distance to a closed triangle mesh: brute force over the triangles, and the
// same query through a bounding-volume tree (MeshBvh) that returns bit-identical
// results (same triangle, same arithmetic), so switching a caller to the tree cannot
// change a trajectory.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "pliant/articulated/contact.h"

namespace pliant::articulated {
namespace {

// Closest point to p on triangle (a, b, c) (Voronoi regions of vertices, edges, face).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double den = 1 / (va + vb + vc);
  return a + ab * (vb * den) + ac * (vc * den);
}

// The nearest triangle so far: squared distance, closest point, index.
struct Nearest {
  double d2 = 1e300;
  Vec3 q = Vec3::Zero();
  int tri = -1;
};

// Triangle t against the nearest so far. Ties go to the lower index, which is what
// the brute-force scan (strict <, increasing index) keeps.
void visit(const MeshShape& mesh, int t, const Vec3& p, Nearest* best) {
  const auto& tr = mesh.triangles[t];
  const Vec3 q = closest_on_triangle(p, mesh.vertices[tr[0]], mesh.vertices[tr[1]], mesh.vertices[tr[2]]);
  const double d = (p - q).squaredNorm();
  if (d < best->d2 || (d == best->d2 && t < best->tri)) *best = {d, q, t};
}

// Sign and normal from the nearest triangle's face normal (exact on faces, an
// approximation near edges and vertices, see README).
double signed_from(const MeshShape& mesh, const Vec3& p, const Nearest& best, Vec3* normal) {
  Vec3 n = Vec3::UnitZ();
  if (best.tri >= 0) {
    const auto& t = mesh.triangles[best.tri];
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    n = (b - a).cross(c - a).normalized();
  }
  const double d = std::sqrt(best.d2);
  const bool inside = (p - best.q).dot(n) < 0;
  *normal = d > 1e-12 ? Vec3((inside ? -1.0 : 1.0) * (p - best.q) / d) : n;
  return inside ? -d : d;
}

constexpr int kLeafTriangles = 4;

// Nodes of triangles order[first, first + count): a leaf, or split at the median of
// the centroids along their widest axis (children: left = this + 1, then right).
void build(const MeshShape& mesh, const std::vector<Vec3>& centroid, int first, int count, MeshBvh* bvh) {
  const int self = static_cast<int>(bvh->nodes.size());
  bvh->nodes.push_back({});
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300), clo = lo, chi = hi;
  for (int i = first; i < first + count; ++i) {
    const int t = bvh->order[i];
    for (int v : mesh.triangles[t]) lo = lo.cwiseMin(mesh.vertices[v]), hi = hi.cwiseMax(mesh.vertices[v]);
    clo = clo.cwiseMin(centroid[t]), chi = chi.cwiseMax(centroid[t]);
  }
  bvh->nodes[self].lo = lo;
  bvh->nodes[self].hi = hi;
  if (count <= kLeafTriangles) {
    bvh->nodes[self].first = first;
    bvh->nodes[self].count = count;
    return;
  }
  int axis;
  (chi - clo).maxCoeff(&axis);
  const int half = count / 2;
  std::nth_element(bvh->order.begin() + first, bvh->order.begin() + first + half, bvh->order.begin() + first + count,
                   [&](int x, int y) { return centroid[x][axis] < centroid[y][axis]; });
  build(mesh, centroid, first, half, bvh);
  bvh->nodes[self].right = static_cast<int>(bvh->nodes.size());
  build(mesh, centroid, first + half, count - half, bvh);
}

double box_distance2(const MeshBvh::Node& n, const Vec3& p) {
  return (n.lo - p).cwiseMax(0.0).cwiseMax(p - n.hi).squaredNorm();
}

}  // namespace

double mesh_signed_distance(const MeshShape& mesh, const Vec3& p, Vec3* normal) {
  Nearest best;
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) visit(mesh, t, p, &best);
  return signed_from(mesh, p, best, normal);
}

MeshBvh mesh_bvh(const MeshShape& mesh) {
  MeshBvh bvh;
  const int n = static_cast<int>(mesh.triangles.size());
  if (n == 0) return bvh;
  std::vector<Vec3> centroid(n);
  for (int t = 0; t < n; ++t) {
    const auto& tr = mesh.triangles[t];
    centroid[t] = (mesh.vertices[tr[0]] + mesh.vertices[tr[1]] + mesh.vertices[tr[2]]) / 3;
  }
  bvh.order.resize(n);
  std::iota(bvh.order.begin(), bvh.order.end(), 0);
  build(mesh, centroid, 0, n, &bvh);
  return bvh;
}

double mesh_signed_distance(const MeshShape& mesh, const MeshBvh& bvh, const Vec3& p, Vec3* normal) {
  Nearest best;
  if (bvh.nodes.empty()) return signed_from(mesh, p, best, normal);
  // Depth-first, nearer child first. A node is skipped only when its box is farther
  // than the best triangle by more than round-off (1e-9 relative), so every triangle
  // that ties with the best is still visited and the result equals the scan's.
  // Median splits keep the depth at log2(triangles / 4) + 1, far below the stack.
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const MeshBvh::Node& n = bvh.nodes[stack[--top]];
    if (box_distance2(n, p) > best.d2 * (1 + 1e-9)) continue;
    if (n.count > 0) {
      for (int i = n.first; i < n.first + n.count; ++i) visit(mesh, bvh.order[i], p, &best);
      continue;
    }
    const int left = static_cast<int>(&n - bvh.nodes.data()) + 1, right = n.right;
    const bool left_first = box_distance2(bvh.nodes[left], p) <= box_distance2(bvh.nodes[right], p);
    stack[top++] = left_first ? right : left;
    stack[top++] = left_first ? left : right;
  }
  return signed_from(mesh, p, best, normal);
}

}  // namespace pliant::articulated
