#version 330 core
// The 2D domain quad [-half, half], drawn as a 4-vertex triangle strip with no
// vertex buffer. uv (0,0) is the lower-left cell: density row 0 is the bottom (+y up).
uniform mat4 u_mvp;
uniform vec2 u_half;
out vec2 v_uv;
void main() {
  vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
  v_uv = corner;
  gl_Position = u_mvp * vec4((corner * 2.0 - 1.0) * u_half, 0.0, 1.0);
}
