#include "render/screen_ray.h"

#include <cmath>

namespace pliant::editor {

ScreenPoint project_to_screen(const Mat4& m, const Vec3& p, float x0, float y0, float w, float h) {
  const auto c = mat4_apply(m, {p[0], p[1], p[2], 1.0f});
  if (!(c[3] > 1e-6f)) return {};
  return {x0 + 0.5f * (c[0] / c[3] + 1.0f) * w, y0 + 0.5f * (1.0f - c[1] / c[3]) * h, c[2] / c[3], true};
}

bool screen_ray(const Mat4& m, float sx, float sy, float x0, float y0, float w, float h, Vec3* near_pt,
                Vec3* far_pt) {
  if (!(w > 0) || !(h > 0)) return false;
  const Mat4 inv = mat4_inverse(m);
  const float nx = 2.0f * (sx - x0) / w - 1.0f, ny = 1.0f - 2.0f * (sy - y0) / h;
  const auto a = mat4_apply(inv, {nx, ny, -1.0f, 1.0f}), b = mat4_apply(inv, {nx, ny, 1.0f, 1.0f});
  if (a[3] == 0 || b[3] == 0) return false;
  *near_pt = {a[0] / a[3], a[1] / a[3], a[2] / a[3]};
  *far_pt = {b[0] / b[3], b[1] / b[3], b[2] / b[3]};
  return true;
}

bool screen_ray_plane_y(const Mat4& m, float sx, float sy, float x0, float y0, float w, float h, float plane_y,
                        Vec3* hit) {
  Vec3 a, b;
  if (!screen_ray(m, sx, sy, x0, y0, w, h, &a, &b)) return false;
  const float dy = b[1] - a[1];
  if (std::abs(dy) < 1e-9f) return false;
  const float t = (plane_y - a[1]) / dy;
  if (!(t >= 0.0f)) return false;
  *hit = {a[0] + t * (b[0] - a[0]), plane_y, a[2] + t * (b[2] - a[2])};
  return true;
}

}  // namespace pliant::editor
