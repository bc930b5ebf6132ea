#include "render/mat4.h"

#include <cmath>

namespace pliant::editor {
namespace {
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
float dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 normalize(const Vec3& a) {
  const float n = std::sqrt(dot(a, a));
  return n > 0 ? Vec3{a[0] / n, a[1] / n, a[2] / n} : a;
}
}  // namespace

Mat4 mat4_identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Mat4 mat4_mul(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row) {
      float s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + row] * b[c * 4 + k];
      r[c * 4 + row] = s;
    }
  return r;
}

std::array<float, 4> mat4_apply(const Mat4& m, const std::array<float, 4>& v) {
  std::array<float, 4> r{};
  for (int row = 0; row < 4; ++row)
    for (int k = 0; k < 4; ++k) r[row] += m[k * 4 + row] * v[k];
  return r;
}

Mat4 mat4_inverse(const Mat4& m) {
  // Laplace expansion by 2x2 minors (the classic MESA gluInvertMatrix layout, written out).
  const float a0 = m[0] * m[5] - m[1] * m[4], a1 = m[0] * m[6] - m[2] * m[4];
  const float a2 = m[0] * m[7] - m[3] * m[4], a3 = m[1] * m[6] - m[2] * m[5];
  const float a4 = m[1] * m[7] - m[3] * m[5], a5 = m[2] * m[7] - m[3] * m[6];
  const float b0 = m[8] * m[13] - m[9] * m[12], b1 = m[8] * m[14] - m[10] * m[12];
  const float b2 = m[8] * m[15] - m[11] * m[12], b3 = m[9] * m[14] - m[10] * m[13];
  const float b4 = m[9] * m[15] - m[11] * m[13], b5 = m[10] * m[15] - m[11] * m[14];
  const float det = a0 * b5 - a1 * b4 + a2 * b3 + a3 * b2 - a4 * b1 + a5 * b0;
  if (std::fabs(det) < 1e-30f) return mat4_identity();
  const float s = 1.0f / det;
  Mat4 r;
  r[0] = (m[5] * b5 - m[6] * b4 + m[7] * b3) * s;
  r[1] = (-m[1] * b5 + m[2] * b4 - m[3] * b3) * s;
  r[2] = (m[13] * a5 - m[14] * a4 + m[15] * a3) * s;
  r[3] = (-m[9] * a5 + m[10] * a4 - m[11] * a3) * s;
  r[4] = (-m[4] * b5 + m[6] * b2 - m[7] * b1) * s;
  r[5] = (m[0] * b5 - m[2] * b2 + m[3] * b1) * s;
  r[6] = (-m[12] * a5 + m[14] * a2 - m[15] * a1) * s;
  r[7] = (m[8] * a5 - m[10] * a2 + m[11] * a1) * s;
  r[8] = (m[4] * b4 - m[5] * b2 + m[7] * b0) * s;
  r[9] = (-m[0] * b4 + m[1] * b2 - m[3] * b0) * s;
  r[10] = (m[12] * a4 - m[13] * a2 + m[15] * a0) * s;
  r[11] = (-m[8] * a4 + m[9] * a2 - m[11] * a0) * s;
  r[12] = (-m[4] * b3 + m[5] * b1 - m[6] * b0) * s;
  r[13] = (m[0] * b3 - m[1] * b1 + m[2] * b0) * s;
  r[14] = (-m[12] * a3 + m[13] * a1 - m[14] * a0) * s;
  r[15] = (m[8] * a3 - m[9] * a1 + m[10] * a0) * s;
  return r;
}

Mat4 look_at(const Vec3& eye, const Vec3& target, const Vec3& up) {
  const Vec3 f = normalize(sub(target, eye));
  const Vec3 s = normalize(cross(f, up));
  const Vec3 u = cross(s, f);
  Mat4 m = mat4_identity();
  m[0] = s[0]; m[4] = s[1]; m[8] = s[2];
  m[1] = u[0]; m[5] = u[1]; m[9] = u[2];
  m[2] = -f[0]; m[6] = -f[1]; m[10] = -f[2];
  m[12] = -dot(s, eye);
  m[13] = -dot(u, eye);
  m[14] = dot(f, eye);
  return m;
}

Mat4 perspective(float fovy_deg, float aspect, float z_near, float z_far) {
  const float f = 1.0f / std::tan(fovy_deg * 3.14159265358979f / 360.0f);
  Mat4 m{};
  m[0] = f / aspect;
  m[5] = f;
  m[10] = (z_far + z_near) / (z_near - z_far);
  m[11] = -1;
  m[14] = 2 * z_far * z_near / (z_near - z_far);
  return m;
}

Mat4 ortho(float l, float r, float b, float t, float n, float f) {
  Mat4 m = mat4_identity();
  m[0] = 2 / (r - l);
  m[5] = 2 / (t - b);
  m[10] = -2 / (f - n);
  m[12] = -(r + l) / (r - l);
  m[13] = -(t + b) / (t - b);
  m[14] = -(f + n) / (f - n);
  return m;
}

}  // namespace pliant::editor
