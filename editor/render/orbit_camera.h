// Orbit camera: yaw/pitch around a target at a distance. 2D frames use it as a
// pan/zoom camera (orthographic, yaw/pitch ignored).
#pragma once
#include <array>

namespace pliant::editor {

struct OrbitCamera {
  float yaw_deg = 30, pitch_deg = 20, distance = 2.2f, fov_deg = 40;
  std::array<float, 3> target{0, 0, 0};
  float zoom2d = 1.0f;                 // orthographic zoom for 2D
  std::array<float, 2> pan2d{0, 0};

  void orbit(float dx_px, float dy_px);   // mouse drag
  void zoom(float wheel);                 // scroll
  void pan(float dx_px, float dy_px, int viewport_h);
  void reset();
  // Column-major 4x4 matrices.
  // eye = target + distance * (cos(pitch) sin(yaw), sin(pitch), cos(pitch) cos(yaw)), y up.
  std::array<float, 16> view() const;
  // gluPerspective(fov_deg, aspect, kNear, kFar).
  std::array<float, 16> projection(float aspect) const;
  std::array<float, 3> eye() const;
  // 2D: orthographic view-projection of a domain [-w/2, w/2] x [-h/2, h/2]
  // fitted into the viewport with aspect preserved and a 5% margin, then
  // zoomed by zoom2d about pan2d (the world point at the viewport centre).
  std::array<float, 16> view_projection_2d(float aspect, float domain_w, float domain_h) const;

  static constexpr float kNear = 0.01f, kFar = 100.0f;
  static constexpr float kMargin2d = 1.05f;
};

}  // namespace pliant::editor
