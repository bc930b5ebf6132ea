#include "render/smoke3d_drawer.h"

#include <algorithm>
#include <cmath>

namespace pliant::editor {

bool Smoke3DDrawer::init(std::string* err) {
  if (!program_.build("volume.vert", "volume.frag", err)) return false;
  vao_ = gl::make_vertex_array();
  density_ = gl::make_texture();
  glBindTexture(GL_TEXTURE_3D, density_.get());
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  // Zero outside the domain, so shadow rays leaving the box see empty space.
  const float zero[4] = {0, 0, 0, 0};
  glTexParameterfv(GL_TEXTURE_3D, GL_TEXTURE_BORDER_COLOR, zero);
  for (GLenum w : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTexParameteri(GL_TEXTURE_3D, w, GL_CLAMP_TO_BORDER);
  glBindTexture(GL_TEXTURE_3D, 0);
  return true;
}

void Smoke3DDrawer::upload(const Field& density) {
  nz_ = static_cast<int>(density.shape[0]);
  ny_ = static_cast<int>(density.shape[1]);
  nx_ = static_cast<int>(density.shape[2]);
  glBindTexture(GL_TEXTURE_3D, density_.get());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexImage3D(GL_TEXTURE_3D, 0, GL_R32F, nx_, ny_, nz_, 0, GL_RED, GL_FLOAT, density.data.data());
  glBindTexture(GL_TEXTURE_3D, 0);
}

void Smoke3DDrawer::draw(const Mat4& view_proj, const Vec3& half, const ViewSettings& view, LineDrawer& lines) {
  if (nx_ == 0) return;
  glEnable(GL_BLEND);
  // Box first, so the smoke in front of its far edges veils them.
  if (view.show_grid) {
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    lines.add_box({-half[0], -half[1], -half[2]}, half, {0.75f, 0.78f, 0.85f, 0.8f});
    lines.draw(view_proj);
  }
  glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied
  program_.use();
  program_.set("u_inv_view_proj", mat4_inverse(view_proj));
  program_.set("u_half", half[0], half[1], half[2]);
  program_.set("u_sigma", kSigmaPerDensity * view.density_scale);
  // About two samples per cell along the longest axis.
  program_.set("u_steps", std::clamp(2 * std::max({nx_, ny_, nz_}), 32, 512));
  program_.set("u_smoke_color", view.smoke_color[0], view.smoke_color[1], view.smoke_color[2]);
  // Light from above and to the left of the default view (y up), so the
  // self-shadowed lower right shows the volume's shape.
  const float l[3] = {-0.5f, 0.8f, 0.3f};
  const float n = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
  program_.set("u_light_dir", l[0] / n, l[1] / n, l[2] / n);
  program_.set("u_density", 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_3D, density_.get());
  glBindVertexArray(vao_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindTexture(GL_TEXTURE_3D, 0);
}

void Smoke3DDrawer::shutdown() {
  program_.reset();
  vao_.reset();
  density_.reset();
  nx_ = ny_ = nz_ = 0;
}

}  // namespace pliant::editor
