#version 330 core
// 2D smoke: density -> opacity by Beer-Lambert, alpha = 1 - exp(-scale * d),
// coloured by a ramp from smoke_color (thin) to a warmer tint (dense).
uniform sampler2D u_density;
uniform float u_density_scale;
uniform vec3 u_smoke_color;
in vec2 v_uv;
out vec4 frag;
void main() {
  float d = max(texture(u_density, v_uv).r, 0.0);
  float alpha = 1.0 - exp(-u_density_scale * d);
  vec3 dense_tint = u_smoke_color * vec3(1.0, 0.86, 0.66);
  vec3 color = mix(u_smoke_color, dense_tint, smoothstep(0.5, 1.0, alpha));
  frag = vec4(color, alpha);
}
