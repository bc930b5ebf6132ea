#version 330 core
// 3D smoke by ray marching a density texture through the box [-half, half]
// (emission-absorption model, front-to-back compositing; Max 1995, "Optical
// models for direct volume rendering"). Single scattering from one directional
// light, with the light's transmittance estimated by a short march toward it.
// Ray starts are jittered by a fixed hash of the pixel (deterministic images).
uniform sampler3D u_density;
uniform mat4 u_inv_view_proj;
uniform vec3 u_half;             // half extent of the domain box
uniform float u_sigma;           // extinction per unit density per unit length
uniform int u_steps;             // samples along the box diagonal
uniform vec3 u_smoke_color;
uniform vec3 u_light_dir;        // toward the light, normalized
in vec2 v_ndc;
out vec4 frag;

float hash12(vec2 p) {
  vec3 p3 = fract(vec3(p.xyx) * 0.1031);
  p3 += dot(p3, p3.yzx + 33.33);
  return fract((p3.x + p3.y) * p3.z);
}

float density_at(vec3 p) { return max(texture(u_density, p / (2.0 * u_half) + 0.5).r, 0.0); }

bool hit_box(vec3 o, vec3 d, out float t0, out float t1) {
  vec3 inv = 1.0 / d;
  vec3 a = (-u_half - o) * inv, b = (u_half - o) * inv;
  vec3 lo = min(a, b), hi = max(a, b);
  t0 = max(max(lo.x, lo.y), max(lo.z, 0.0));
  t1 = min(min(hi.x, hi.y), hi.z);
  return t1 > t0;
}

void main() {
  vec4 near = u_inv_view_proj * vec4(v_ndc, -1.0, 1.0);
  vec4 far = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);
  vec3 o = near.xyz / near.w;
  vec3 d = normalize(far.xyz / far.w - o);
  float t0, t1;
  if (!hit_box(o, d, t0, t1)) discard;
  float dt = length(2.0 * u_half) / float(u_steps);
  float light_dt = dt;
  float jitter = hash12(gl_FragCoord.xy);
  float t = t0 + dt * jitter;
  float transmittance = 1.0;
  vec3 radiance = vec3(0.0);
  for (int i = 0; i < 1024 && t < t1; ++i, t += dt) {
    vec3 p = o + t * d;
    float rho = density_at(p);
    if (rho > 1e-4) {
      float a = 1.0 - exp(-u_sigma * rho * dt);
      // Optical depth toward the light (12 samples), for self-shadowing.
      float tau = 0.0;
      for (int k = 1; k <= 12; ++k) tau += density_at(p + u_light_dir * light_dt * float(k));
      float lit = 0.22 + 0.78 * exp(-u_sigma * tau * light_dt);
      radiance += transmittance * a * lit * u_smoke_color;
      transmittance *= 1.0 - a;
      if (transmittance < 0.004) break;
    }
  }
  // Premultiplied colour; blended with ONE, ONE_MINUS_SRC_ALPHA.
  frag = vec4(radiance, 1.0 - transmittance);
}
