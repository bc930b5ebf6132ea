#version 330 core
// Lit triangle meshes (render/mesh_drawer.cpp): positions in world units.
uniform mat4 u_mvp;
uniform mat4 u_modelview;
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_color;
out vec3 v_normal;  // view space
out vec4 v_color;
void main() {
  v_normal = mat3(u_modelview) * a_normal;  // the framing is a uniform scale: no inverse-transpose needed
  v_color = a_color;
  gl_Position = u_mvp * vec4(a_pos, 1.0);
}
