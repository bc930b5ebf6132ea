#include "render/liquid_container_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "render/contour.h"

namespace pliant::editor {

namespace {

// Kuhn triangulation of the unit cube: corner k = (k & 1, k >> 1 & 1, k >> 2 & 1);
// every tetrahedron runs 0 -> one axis -> two axes -> 7, so neighbouring cubes
// split their shared faces along the same diagonal.
constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                             {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

struct Grid {
  int nx, ny, nz;  // vertices per axis
  Vec3 lo;
  float step;
  size_t index(int i, int j, int k) const { return (size_t(k) * ny + j) * nx + i; }
  Vec3 point(size_t g) const {
    const int i = int(g % nx), j = int((g / nx) % ny), k = int(g / (size_t(nx) * ny));
    return {lo[0] + i * step, lo[1] + j * step, lo[2] + k * step};
  }
};

class Extractor {
 public:
  Extractor(const Grid& g, const std::vector<float>& v, TriangleMesh* out) : g_(g), v_(v), out_(out) {}

  void tet(const std::array<size_t, 4>& c) {
    std::array<size_t, 4> neg{}, pos{};
    int nn = 0, np = 0;
    for (size_t id : c) {
      if (v_[id] < 0) neg[nn++] = id;
      else pos[np++] = id;
    }
    if (nn == 0 || np == 0) return;
    // Outward (towards positive distance) for the winding.
    Vec3 outward{0, 0, 0};
    for (int a = 0; a < np; ++a) add_scaled(&outward, g_.point(pos[a]), 1.0f / np);
    for (int a = 0; a < nn; ++a) add_scaled(&outward, g_.point(neg[a]), -1.0f / nn);
    if (nn == 1 || np == 1) {
      const size_t lone = nn == 1 ? neg[0] : pos[0];
      const auto& others = nn == 1 ? pos : neg;
      tri(edge(lone, others[0]), edge(lone, others[1]), edge(lone, others[2]), outward);
    } else {
      // Quad between the two negative and two positive corners, in cyclic order.
      const uint32_t ac = edge(neg[0], pos[0]), ad = edge(neg[0], pos[1]);
      const uint32_t bd = edge(neg[1], pos[1]), bc = edge(neg[1], pos[0]);
      tri(ac, ad, bd, outward);
      tri(ac, bd, bc, outward);
    }
  }

 private:
  static void add_scaled(Vec3* a, const Vec3& b, float s) {
    for (int i = 0; i < 3; ++i) (*a)[i] += s * b[i];
  }
  // The zero crossing on grid edge (a, b), shared by every tetrahedron using it.
  uint32_t edge(size_t a, size_t b) {
    const uint64_t key = uint64_t(std::min(a, b)) * (uint64_t(g_.nx) * g_.ny * g_.nz) + std::max(a, b);
    auto [it, inserted] = edges_.try_emplace(key, uint32_t(out_->vertex_count()));
    if (inserted) {
      const float va = v_[a], vb = v_[b];
      const float t = std::clamp(va / (va - vb), 0.0f, 1.0f);
      const Vec3 pa = g_.point(a), pb = g_.point(b);
      for (int i = 0; i < 3; ++i) out_->xyz.push_back(pa[i] + t * (pb[i] - pa[i]));
    }
    return it->second;
  }
  void tri(uint32_t a, uint32_t b, uint32_t c, const Vec3& outward) {
    const float* p = out_->xyz.data();
    const Vec3 e1{p[3 * b] - p[3 * a], p[3 * b + 1] - p[3 * a + 1], p[3 * b + 2] - p[3 * a + 2]};
    const Vec3 e2{p[3 * c] - p[3 * a], p[3 * c + 1] - p[3 * a + 1], p[3 * c + 2] - p[3 * a + 2]};
    const Vec3 n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    if (n[0] * n[0] + n[1] * n[1] + n[2] * n[2] < 1e-30f) return;  // collapsed at a grid vertex
    const bool flip = n[0] * outward[0] + n[1] * outward[1] + n[2] * outward[2] < 0;
    out_->tris.insert(out_->tris.end(), {a, flip ? c : b, flip ? b : c});
  }

  const Grid& g_;
  const std::vector<float>& v_;
  TriangleMesh* out_;
  std::unordered_map<uint64_t, uint32_t> edges_;
};

int cells(float lo, float hi, float step) { return std::max(1, int(std::ceil((hi - lo) / step))); }

}  // namespace

TriangleMesh sdf_surface_mesh(const LocalSdf& sdf, const Vec3& lo, const Vec3& hi, float step) {
  TriangleMesh mesh;
  if (!(step > 0)) return mesh;
  Grid g{cells(lo[0], hi[0], step) + 1, cells(lo[1], hi[1], step) + 1, cells(lo[2], hi[2], step) + 1, lo, step};
  std::vector<float> v(size_t(g.nx) * g.ny * g.nz);
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const size_t id = g.index(i, j, k);
        const Vec3 p = g.point(id);
        v[id] = float(sdf(p[0], p[1], p[2]));
      }
  Extractor ex(g, v, &mesh);
  for (int k = 0; k + 1 < g.nz; ++k)
    for (int j = 0; j + 1 < g.ny; ++j)
      for (int i = 0; i + 1 < g.nx; ++i) {
        std::array<size_t, 8> corner;
        for (int c = 0; c < 8; ++c) corner[c] = g.index(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
        for (const auto& t : kTets) ex.tet({corner[t[0]], corner[t[1]], corner[t[2]], corner[t[3]]});
      }
  return mesh;
}

std::vector<LineSegment2> sdf_section_lines(const LocalSdf& sdf, const Vec3& lo, const Vec3& hi, float step) {
  std::vector<LineSegment2> out;
  if (!(step > 0)) return out;
  const int nx = cells(lo[0], hi[0], step), ny = cells(lo[1], hi[1], step);
  // contour_lines wants values at cell centres, higher inside the shape.
  std::vector<float> v(size_t(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) v[size_t(j) * nx + i] = -float(sdf(lo[0] + (i + 0.5) * step, lo[1] + (j + 0.5) * step, 0));
  for (const ContourSegment& s : contour_lines(v.data(), nx, ny, 0.0f))
    out.push_back({lo[0] + s.a[0] * step, lo[1] + s.a[1] * step, lo[0] + s.b[0] * step, lo[1] + s.b[1] * step});
  return out;
}

}  // namespace pliant::editor
