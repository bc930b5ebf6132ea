#version 330 core
// Round sprite shaded like a small sphere lit from the viewer.
in vec3 v_color;
out vec4 frag;
void main() {
  vec2 d = 2.0 * gl_PointCoord - 1.0;
  float r2 = dot(d, d);
  if (r2 > 1.0) discard;
  frag = vec4(v_color * (0.55 + 0.45 * sqrt(1.0 - r2)), 1.0);
}
