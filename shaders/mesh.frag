#version 330 core
// Headlight, two-sided Lambert plus ambient: open surfaces read from both sides.
in vec3 v_normal;
in vec4 v_color;
out vec4 frag;
void main() {
  float d = abs(normalize(v_normal).z);
  frag = vec4(v_color.rgb * (0.35 + 0.65 * d), v_color.a);
}
