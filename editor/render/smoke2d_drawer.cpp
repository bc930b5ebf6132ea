#include "render/smoke2d_drawer.h"

#include <algorithm>
#include <cmath>

namespace pliant::editor {

bool Smoke2DDrawer::init(std::string* err) {
  if (!program_.build("smoke2d.vert", "smoke2d.frag", err)) return false;
  vao_ = gl::make_vertex_array();  // core profile needs a bound VAO even without attributes
  density_ = gl::make_texture();
  glBindTexture(GL_TEXTURE_2D, density_.get());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_2D, 0);
  return true;
}

void Smoke2DDrawer::upload(const Field& density, const Field* velocity, const Field* force) {
  ny_ = static_cast<int>(density.shape[0]);
  nx_ = static_cast<int>(density.shape[1]);
  glBindTexture(GL_TEXTURE_2D, density_.get());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, nx_, ny_, 0, GL_RED, GL_FLOAT, density.data.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  velocity_.clear();
  if (velocity && velocity->shape.size() == 3 && velocity->shape[0] == density.shape[0] &&
      velocity->shape[1] == density.shape[1] && velocity->shape[2] == 2)
    velocity_ = velocity->data;
  force_.clear();
  if (force && force->shape.size() == 3 && force->shape[0] == density.shape[0] &&
      force->shape[1] == density.shape[1] && force->shape[2] == 2)
    force_ = force->data;
}

int Smoke2DDrawer::arrow_stride(int nx, int ny) { return std::max(1, std::max(nx, ny) / 16); }

void Smoke2DDrawer::add_arrows(const std::vector<float>& field, float half_w, float half_h,
                               const std::array<float, 4>& color_in, LineDrawer& lines) const {
  const int k = arrow_stride(nx_, ny_);
  const float cell = 2.0f * half_w / static_cast<float>(nx_);
  float vmax = 0;
  for (size_t i = 0; i + 1 < field.size(); i += 2)
    vmax = std::max(vmax, std::hypot(field[i], field[i + 1]));
  if (vmax <= 0) return;
  // The fastest arrow is 0.9 strides long.
  const float scale = 0.9f * static_cast<float>(k) * cell / vmax;
  const LineDrawer::Color color{color_in[0], color_in[1], color_in[2], color_in[3]};
  for (int j = k / 2; j < ny_; j += k) {
    for (int i = k / 2; i < nx_; i += k) {
      const float* v = &field[(static_cast<size_t>(j) * nx_ + i) * 2];
      const float ux = v[0] * scale, uy = v[1] * scale;
      const float len = std::hypot(ux, uy);
      if (len < 0.05f * cell) continue;
      const float x0 = -half_w + (i + 0.5f) * cell, y0 = -half_h + (j + 0.5f) * cell;
      const float x1 = x0 + ux, y1 = y0 + uy;
      lines.add({x0, y0, 0}, {x1, y1, 0}, color);
      // Arrow head: two strokes at +-25 degrees back from the tip, 30% of the length.
      const float hx = -ux * 0.3f, hy = -uy * 0.3f;
      const float c = 0.906f, s = 0.423f;
      lines.add({x1, y1, 0}, {x1 + c * hx - s * hy, y1 + s * hx + c * hy, 0}, color);
      lines.add({x1, y1, 0}, {x1 + c * hx + s * hy, y1 - s * hx + c * hy, 0}, color);
    }
  }
}

void Smoke2DDrawer::draw(const Mat4& mvp, float half_w, float half_h, const ViewSettings& view,
                         LineDrawer& lines) {
  if (nx_ == 0) return;
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  const float cell = 2.0f * half_w / static_cast<float>(nx_);
  if (view.show_grid) {
    // Faint lines every 8th of the longest side (in whole cells), under the smoke.
    const int step = std::max(1, std::max(nx_, ny_) / 8);
    const LineDrawer::Color faint{1, 1, 1, 0.08f};
    for (int i = step; i < nx_; i += step)
      lines.add({-half_w + i * cell, -half_h, 0}, {-half_w + i * cell, half_h, 0}, faint);
    for (int j = step; j < ny_; j += step)
      lines.add({-half_w, -half_h + j * cell, 0}, {half_w, -half_h + j * cell, 0}, faint);
    lines.draw(mvp);
  }

  program_.use();
  program_.set("u_mvp", mvp);
  program_.set("u_half", half_w, half_h);
  program_.set("u_density_scale", view.density_scale);
  program_.set("u_smoke_color", view.smoke_color[0], view.smoke_color[1], view.smoke_color[2]);
  program_.set("u_density", 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, density_.get());
  glBindVertexArray(vao_.get());
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  glBindVertexArray(0);
  glBindTexture(GL_TEXTURE_2D, 0);

  if (view.show_grid) {
    const LineDrawer::Color outline{0.75f, 0.78f, 0.85f, 0.9f};
    const Vec3 c00{-half_w, -half_h, 0}, c10{half_w, -half_h, 0}, c11{half_w, half_h, 0}, c01{-half_w, half_h, 0};
    lines.add(c00, c10, outline);
    lines.add(c10, c11, outline);
    lines.add(c11, c01, outline);
    lines.add(c01, c00, outline);
  }
  if (view.show_velocity && !velocity_.empty()) add_arrows(velocity_, half_w, half_h, {1.0f, 0.62f, 0.2f, 0.9f}, lines);
  if (view.show_force && !force_.empty()) add_arrows(force_, half_w, half_h, {0.35f, 1.0f, 0.45f, 0.9f}, lines);
  lines.draw(mvp);
}

void Smoke2DDrawer::shutdown() {
  program_.reset();
  vao_.reset();
  density_.reset();
  nx_ = ny_ = 0;
  velocity_.clear();
  force_.clear();
}

}  // namespace pliant::editor
