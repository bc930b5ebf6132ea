#include "render/mesh_drawer.h"

#include <cmath>
#include <cstddef>

namespace pliant::editor {

namespace {

Vec3 apply_point(const Mat4& m, const Vec3& p) {
  return {m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12], m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13],
          m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14]};
}
Vec3 apply_dir(const Mat4& m, const Vec3& d) {
  return {m[0] * d[0] + m[4] * d[1] + m[8] * d[2], m[1] * d[0] + m[5] * d[1] + m[9] * d[2],
          m[2] * d[0] + m[6] * d[1] + m[10] * d[2]};
}
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
float dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 normalized(const Vec3& v) {
  const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return n > 1e-20f ? Vec3{v[0] / n, v[1] / n, v[2] / n} : Vec3{0, 0, 1};
}

constexpr int kSlices = 24, kStacks = 12;
constexpr float kPi = 3.14159265358979f;

}  // namespace

Mat4 pose_matrix(const Vec3& p, const std::array<float, 4>& q) {
  const float w = q[0], x = q[1], y = q[2], z = q[3];
  Mat4 m = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z),     2 * (x * z - w * y),     0,
            2 * (x * y - w * z),     1 - 2 * (x * x + z * z), 2 * (y * z + w * x),     0,
            2 * (x * z + w * y),     2 * (y * z - w * x),     1 - 2 * (x * x + y * y), 0,
            p[0],                    p[1],                    p[2],                    1};
  return m;
}

bool MeshDrawer::init(std::string* err) {
  if (!program_.build("mesh.vert", "mesh.frag", err)) return false;
  vao_ = gl::make_vertex_array();
  vbo_ = gl::make_buffer();
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<const void*>(offsetof(Vertex, pos)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                        reinterpret_cast<const void*>(offsetof(Vertex, normal)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                        reinterpret_cast<const void*>(offsetof(Vertex, color)));
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  return true;
}

void MeshDrawer::clear() {
  verts_.clear();
  dirty_ = true;
}

void MeshDrawer::add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& na, const Vec3& nb,
                              const Vec3& nc, const Color& col) {
  for (const auto& [p, n] : {std::pair{a, na}, std::pair{b, nb}, std::pair{c, nc}})
    verts_.push_back({{p[0], p[1], p[2]}, {n[0], n[1], n[2]}, {col[0], col[1], col[2], col[3]}});
  dirty_ = true;
}

void MeshDrawer::add_mesh(const float* xyz, size_t nverts, const uint32_t* tris, size_t ntris, const Color& c,
                          const Mat4& model, float crease_deg) {
  std::vector<Vec3> p(nverts);
  for (size_t i = 0; i < nverts; ++i) p[i] = apply_point(model, {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
  auto valid = [&](size_t t) {
    return tris[3 * t] < nverts && tris[3 * t + 1] < nverts && tris[3 * t + 2] < nverts;
  };
  std::vector<Vec3> fn(ntris, Vec3{0, 0, 0});  // length = 2 area
  for (size_t t = 0; t < ntris; ++t) {
    if (!valid(t)) continue;
    const uint32_t* f = tris + 3 * t;
    fn[t] = cross(sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]]));
  }
  verts_.reserve(verts_.size() + 3 * ntris);
  if (!(crease_deg > 0)) {
    // Smooth: one area-weighted normal per vertex.
    std::vector<Vec3> n(nverts, Vec3{0, 0, 0});
    for (size_t t = 0; t < ntris; ++t) {
      if (!valid(t)) continue;
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) n[tris[3 * t + k]][d] += fn[t][d];
    }
    for (auto& v : n) v = normalized(v);
    for (size_t t = 0; t < ntris; ++t) {
      if (!valid(t)) continue;
      const uint32_t* f = tris + 3 * t;
      add_triangle(p[f[0]], p[f[1]], p[f[2]], n[f[0]], n[f[1]], n[f[2]], c);
    }
    return;
  }
  // Creased: a corner averages only the faces around its vertex within crease_deg
  // of its own face, so a box-like mesh keeps sharp edges and a fine one stays smooth.
  const float cos_crease = std::cos(crease_deg * kPi / 180.0f);
  std::vector<uint32_t> start(nverts + 1, 0), faces;
  for (size_t t = 0; t < ntris; ++t)
    if (valid(t))
      for (int k = 0; k < 3; ++k) ++start[tris[3 * t + k] + 1];
  for (size_t v = 0; v < nverts; ++v) start[v + 1] += start[v];
  faces.resize(start[nverts]);
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (size_t t = 0; t < ntris; ++t)
    if (valid(t))
      for (int k = 0; k < 3; ++k) faces[fill[tris[3 * t + k]]++] = uint32_t(t);
  std::vector<Vec3> unit(ntris);
  for (size_t t = 0; t < ntris; ++t) unit[t] = normalized(fn[t]);
  for (size_t t = 0; t < ntris; ++t) {
    if (!valid(t)) continue;
    const uint32_t* f = tris + 3 * t;
    Vec3 n[3];
    for (int k = 0; k < 3; ++k) {
      Vec3 sum{0, 0, 0};
      for (uint32_t i = start[f[k]]; i < start[f[k] + 1]; ++i)
        if (dot(unit[faces[i]], unit[t]) >= cos_crease)
          for (int d = 0; d < 3; ++d) sum[d] += fn[faces[i]][d];
      n[k] = normalized(sum);
    }
    add_triangle(p[f[0]], p[f[1]], p[f[2]], n[0], n[1], n[2], c);
  }
}

void MeshDrawer::add_sphere(const Mat4& model, float r, const Color& c) { add_capsule(model, r, 0.0f, c); }

void MeshDrawer::add_capsule(const Mat4& model, float r, float half_len, const Color& c) {
  // Two hemispheres (latitude rings, the lower centred at -half_len, the upper
  // at +half_len) joined by a cylinder between their equators.
  auto point = [&](int i, int j, float zc, Vec3* normal) {
    const float phi = kPi * (float(i) / kStacks - 0.5f);  // -pi/2 .. pi/2
    const float th = 2 * kPi * float(j) / kSlices;
    const Vec3 nl{std::cos(phi) * std::cos(th), std::cos(phi) * std::sin(th), std::sin(phi)};
    *normal = normalized(apply_dir(model, nl));
    return apply_point(model, {r * nl[0], r * nl[1], zc + r * nl[2]});
  };
  for (int i = 0; i < kStacks; ++i) {
    const float zc = 2 * i < kStacks ? -half_len : half_len;
    for (int j = 0; j < kSlices; ++j) {
      Vec3 n00, n01, n10, n11;
      const Vec3 p00 = point(i, j, zc, &n00), p01 = point(i, j + 1, zc, &n01);
      const Vec3 p10 = point(i + 1, j, zc, &n10), p11 = point(i + 1, j + 1, zc, &n11);
      add_triangle(p00, p01, p11, n00, n01, n11, c);
      add_triangle(p00, p11, p10, n00, n11, n10, c);
    }
  }
  if (half_len <= 0) return;
  for (int j = 0; j < kSlices; ++j) {
    Vec3 n0, n1, m0, m1;
    const int eq = kStacks / 2;
    const Vec3 a0 = point(eq, j, -half_len, &n0), a1 = point(eq, j + 1, -half_len, &n1);
    const Vec3 b0 = point(eq, j, half_len, &m0), b1 = point(eq, j + 1, half_len, &m1);
    add_triangle(a0, a1, b1, n0, n1, m1, c);
    add_triangle(a0, b1, b0, n0, m1, m0, c);
  }
}

void MeshDrawer::add_box(const Mat4& model, const Vec3& h, const Color& c) {
  for (int axis = 0; axis < 3; ++axis) {
    for (int s = -1; s <= 1; s += 2) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      Vec3 nl{0, 0, 0};
      nl[axis] = float(s);
      const Vec3 n = normalized(apply_dir(model, nl));
      Vec3 q[4];
      for (int k = 0; k < 4; ++k) {
        Vec3 p{0, 0, 0};
        p[axis] = s * h[axis];
        p[u] = ((k == 1 || k == 2) ? 1 : -1) * h[u];
        p[v] = (k >= 2 ? 1 : -1) * h[v];
        q[k] = apply_point(model, p);
      }
      add_triangle(q[0], q[1], q[2], n, n, n, c);
      add_triangle(q[0], q[2], q[3], n, n, n, c);
    }
  }
}

void MeshDrawer::draw(const Mat4& world_to_clip, const Mat4& world_to_view) {
  if (verts_.empty() || !program_) return;
  program_.use();
  program_.set("u_mvp", world_to_clip);
  program_.set("u_modelview", world_to_view);
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
  if (dirty_) {
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(verts_.size() * sizeof(Vertex)), verts_.data(),
                 GL_DYNAMIC_DRAW);
    dirty_ = false;
  }
  glEnable(GL_DEPTH_TEST);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(verts_.size()));
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glBindVertexArray(0);
}

void MeshDrawer::shutdown() {
  program_.reset();
  vbo_.reset();
  vao_.reset();
  clear();
}

}  // namespace pliant::editor
