#include "render/orbit_camera.h"

#include <algorithm>
#include <cmath>

#include "render/mat4.h"

namespace pliant::editor {
namespace {
constexpr float kDegToRad = 3.14159265358979f / 180.0f;
constexpr float kOrbitDegPerPx = 0.3f;
constexpr float kWheelFactor = 1.1f;  // one wheel notch zooms by 10%
}  // namespace

void OrbitCamera::orbit(float dx_px, float dy_px) {
  // Dragging right turns the scene right (the eye moves left).
  yaw_deg = std::fmod(yaw_deg - kOrbitDegPerPx * dx_px, 360.0f);
  pitch_deg = std::clamp(pitch_deg + kOrbitDegPerPx * dy_px, -89.0f, 89.0f);
}

void OrbitCamera::zoom(float wheel) {
  const float f = std::pow(kWheelFactor, wheel);
  distance = std::clamp(distance / f, 0.05f, 50.0f);
  zoom2d = std::clamp(zoom2d * f, 0.05f, 100.0f);
}

void OrbitCamera::pan(float dx_px, float dy_px, int viewport_h) {
  const float vh = static_cast<float>(std::max(viewport_h, 1));
  // 3D: move the target in the view plane so the point under the cursor follows it.
  const float world_per_px = 2.0f * distance * std::tan(0.5f * fov_deg * kDegToRad) / vh;
  const Mat4 v = view();
  const Vec3 right{v[0], v[4], v[8]}, up{v[1], v[5], v[9]};
  for (int i = 0; i < 3; ++i) target[i] += (-dx_px * right[i] + dy_px * up[i]) * world_per_px;
  // 2D: the fitted view is about one world unit tall (longest side is 1).
  pan2d[0] -= dx_px / (vh * zoom2d);
  pan2d[1] += dy_px / (vh * zoom2d);
}

void OrbitCamera::reset() { *this = OrbitCamera{}; }

std::array<float, 3> OrbitCamera::eye() const {
  const float y = yaw_deg * kDegToRad, p = pitch_deg * kDegToRad;
  return {target[0] + distance * std::cos(p) * std::sin(y), target[1] + distance * std::sin(p),
          target[2] + distance * std::cos(p) * std::cos(y)};
}

std::array<float, 16> OrbitCamera::view() const { return look_at(eye(), target, {0, 1, 0}); }

std::array<float, 16> OrbitCamera::projection(float aspect) const {
  return perspective(fov_deg, aspect, kNear, kFar);
}

std::array<float, 16> OrbitCamera::view_projection_2d(float aspect, float domain_w, float domain_h) const {
  // Half-height that shows the whole domain: limited by height, or by width / aspect.
  const float half_h = 0.5f * kMargin2d * std::max(domain_h, domain_w / std::max(aspect, 1e-6f)) /
                       std::max(zoom2d, 1e-6f);
  const float half_w = half_h * aspect;
  return ortho(pan2d[0] - half_w, pan2d[0] + half_w, pan2d[1] - half_h, pan2d[1] + half_h, -1.0f, 1.0f);
}

}  // namespace pliant::editor
