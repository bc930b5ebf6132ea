#version 330 core
// Liquid particles as point sprites; colour from speed (blue at rest, white fast).
uniform mat4 u_mvp;
uniform float u_size_px;     // sprite diameter in pixels
uniform float u_speed_max;   // speed shown white (m/s)
layout(location = 0) in vec4 a_pos_speed;  // xyz (m), speed (m/s)
out vec3 v_color;
void main() {
  float t = clamp(a_pos_speed.w / u_speed_max, 0.0, 1.0);
  vec3 slow = vec3(0.10, 0.32, 0.85), mid = vec3(0.25, 0.80, 1.00), fast = vec3(1.0);
  v_color = t < 0.5 ? mix(slow, mid, 2.0 * t) : mix(mid, fast, 2.0 * t - 1.0);
  gl_Position = u_mvp * vec4(a_pos_speed.xyz, 1.0);
  gl_PointSize = u_size_px;
}
