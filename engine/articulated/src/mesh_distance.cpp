// Signed distance to a closed triangle mesh: brute force over the triangles (sign from
// the nearest triangle's face normal), and the same query through a bounding-volume
// tree (MeshBvh: same nearest triangle, same distance to the bit) whose sign comes from
// the angle-weighted pseudo-normal of the nearest feature (face, edge or vertex;
// Baerentzen and Aanaes, IEEE TVCG 11(3) 2005), right at every edge and vertex of a
// closed mesh, where the face normal fails near convex edges sharper than 90 degrees.
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "pliant/articulated/contact.h"

namespace pliant::articulated {
namespace {

// Where the closest point of a triangle lies: a vertex, an edge (0: ab, 1: bc, 2: ca)
// or the face.
enum Feature { kVertexA, kVertexB, kVertexC, kEdgeAB, kEdgeBC, kEdgeCA, kFace };

// Closest point to p on triangle (a, b, c) (Voronoi regions of vertices, edges, face).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Feature* f) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return *f = kVertexA, a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return *f = kVertexB, b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return *f = kEdgeAB, a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return *f = kVertexC, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return *f = kEdgeCA, a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return *f = kEdgeBC, b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double den = 1 / (va + vb + vc);
  return *f = kFace, a + ab * (vb * den) + ac * (vc * den);
}

// The nearest triangle so far: squared distance, closest point, index, feature.
struct Nearest {
  double d2 = 1e300;
  Vec3 q = Vec3::Zero();
  int tri = -1;
  Feature feature = kFace;
};

// Triangle t against the nearest so far. Ties go to the lower index, which is what
// the brute-force scan (strict <, increasing index) keeps.
void visit(const MeshShape& mesh, int t, const Vec3& p, Nearest* best) {
  const auto& tr = mesh.triangles[t];
  Feature f;
  const Vec3 q = closest_on_triangle(p, mesh.vertices[tr[0]], mesh.vertices[tr[1]], mesh.vertices[tr[2]], &f);
  const double d = (p - q).squaredNorm();
  if (d < best->d2 || (d == best->d2 && t < best->tri)) *best = {d, q, t, f};
}

Vec3 face_normal(const MeshShape& mesh, int tri) {
  const auto& t = mesh.triangles[tri];
  const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
  return (b - a).cross(c - a).normalized();
}

// Sign from `sign_normal` ((p - q) . n < 0: inside); the normal returned is along
// p - q (the distance's gradient), or the face normal where p is on the surface.
double signed_from(const MeshShape& mesh, const Vec3& p, const Nearest& best, const Vec3& sign_normal, Vec3* normal) {
  const Vec3 n = best.tri >= 0 ? face_normal(mesh, best.tri) : Vec3(Vec3::UnitZ());
  const double d = std::sqrt(best.d2);
  const bool inside = (p - best.q).dot(sign_normal) < 0;
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
  return signed_from(mesh, p, best, best.tri >= 0 ? face_normal(mesh, best.tri) : Vec3(Vec3::UnitZ()), normal);
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
  // Pseudo-normals: an edge's is the sum of its faces' normals, a vertex's the sum of
  // its faces' normals weighted by the face's angle there (unnormalised: only signs
  // of dot products are taken).
  bvh.vertex_normal.assign(mesh.vertices.size(), Vec3::Zero());
  bvh.vertex_owner.assign(mesh.vertices.size(), -1);
  for (int t = n - 1; t >= 0; --t)
    for (int v : mesh.triangles[t]) bvh.vertex_owner[v] = t;
  bvh.edge_normal.assign(n, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  std::map<std::pair<int, int>, Vec3> edge_sum;
  for (int t = 0; t < n; ++t) {
    const auto& tr = mesh.triangles[t];
    const Vec3 fn = face_normal(mesh, t);
    for (int e = 0; e < 3; ++e) {
      const int i = tr[e], j = tr[(e + 1) % 3], k = tr[(e + 2) % 3];
      const Vec3 u = mesh.vertices[j] - mesh.vertices[i], w = mesh.vertices[k] - mesh.vertices[i];
      bvh.vertex_normal[i] += std::atan2(u.cross(w).norm(), u.dot(w)) * fn;
      edge_sum.emplace(std::make_pair(std::min(i, j), std::max(i, j)), Vec3::Zero()).first->second += fn;
    }
  }
  for (int t = 0; t < n; ++t)
    for (int e = 0; e < 3; ++e) {
      const int i = mesh.triangles[t][e], j = mesh.triangles[t][(e + 1) % 3];
      bvh.edge_normal[t][e] = edge_sum.at({std::min(i, j), std::max(i, j)});
    }
  return bvh;
}

double mesh_signed_distance(const MeshShape& mesh, const MeshBvh& bvh, const Vec3& p, Vec3* normal) {
  Nearest best;
  if (bvh.nodes.empty()) return signed_from(mesh, p, best, Vec3::UnitZ(), normal);
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
  const auto& tr = mesh.triangles[best.tri];
  Vec3 pseudo;
  switch (best.feature) {
    case kVertexA: pseudo = bvh.vertex_normal[tr[0]]; break;
    case kVertexB: pseudo = bvh.vertex_normal[tr[1]]; break;
    case kVertexC: pseudo = bvh.vertex_normal[tr[2]]; break;
    case kEdgeAB: pseudo = bvh.edge_normal[best.tri][0]; break;
    case kEdgeBC: pseudo = bvh.edge_normal[best.tri][1]; break;
    case kEdgeCA: pseudo = bvh.edge_normal[best.tri][2]; break;
    default: pseudo = face_normal(mesh, best.tri); break;
  }
  return signed_from(mesh, p, best, pseudo, normal);
}

}  // namespace pliant::articulated
