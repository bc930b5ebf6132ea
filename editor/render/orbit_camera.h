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
  std::array<float, 16> view() const;
  std::array<float, 16> projection(float aspect) const;
  std::array<float, 3> eye() const;
};

}  // namespace pliant::editor
