// Minimal column-major 4x4 matrix math for the renderer (GL conventions:
// right-handed view space looking down -z, clip z in [-1, 1]). Small enough
// that pulling Eigen into the GL side would cost more than it saves.
#pragma once
#include <array>

namespace pliant::editor {

using Mat4 = std::array<float, 16>;  // m[col * 4 + row]
using Vec3 = std::array<float, 3>;

Mat4 mat4_identity();
Mat4 mat4_mul(const Mat4& a, const Mat4& b);  // a * b
// Inverse by cofactors; returns identity for a singular matrix.
Mat4 mat4_inverse(const Mat4& m);
Mat4 look_at(const Vec3& eye, const Vec3& target, const Vec3& up);
// gluPerspective: fovy in degrees.
Mat4 perspective(float fovy_deg, float aspect, float z_near, float z_far);
// glOrtho.
Mat4 ortho(float left, float right, float bottom, float top, float z_near, float z_far);
// m * (x, y, z, w).
std::array<float, 4> mat4_apply(const Mat4& m, const std::array<float, 4>& v);

}  // namespace pliant::editor
