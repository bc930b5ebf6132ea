#include "render/renderer.h"

#include <algorithm>

#include "render/line_drawer.h"
#include "render/mat4.h"
#include "render/smoke2d_drawer.h"
#include "render/smoke3d_drawer.h"

namespace pliant::editor {

struct Renderer::Impl {
  bool ready = false;
  int dim = 0;
  std::array<float, 3> extent{0, 0, 0};
  LineDrawer lines;
  Smoke2DDrawer smoke2d;
  Smoke3DDrawer smoke3d;
};

namespace {
const Field* find_field(const Record& r, std::string_view name) {
  for (const Field& f : r.fields)
    if (f.name == name) return &f;
  return nullptr;
}

bool well_formed(const Field& f) {
  size_t n = 1;
  for (uint32_t d : f.shape) {
    if (d == 0) return false;
    n *= d;
  }
  return !f.shape.empty() && n == f.data.size();
}
}  // namespace

Renderer::Renderer() : impl_(new Impl) {}
Renderer::~Renderer() {
  // Call shutdown() while the context is current. Without a current context
  // GLVND turns the glDelete* calls of the handles into no-ops, so this is safe.
  delete impl_;
}

bool Renderer::init(std::string* err) {
  std::string e;
  if (!impl_->lines.init(&e) || !impl_->smoke2d.init(&e) || !impl_->smoke3d.init(&e)) {
    if (err) *err = "renderer: " + e;
    return false;
  }
  impl_->ready = true;
  return true;
}

void Renderer::set_frame(const Record& frame) {
  const Field* density = find_field(frame, "density");
  if (!impl_->ready || density == nullptr || !well_formed(*density) ||
      (density->shape.size() != 2 && density->shape.size() != 3)) {
    clear_frame();
    return;
  }
  const auto& s = density->shape;
  if (s.size() == 2) {
    const Field* velocity = find_field(frame, "velocity");
    const Field* force = find_field(frame, "force");
    impl_->smoke2d.upload(*density, velocity && well_formed(*velocity) ? velocity : nullptr,
                          force && well_formed(*force) ? force : nullptr);
    const float longest = static_cast<float>(std::max(s[0], s[1]));
    impl_->extent = {s[1] / longest, s[0] / longest, 0.0f};
    impl_->dim = 2;
  } else {
    impl_->smoke3d.upload(*density);
    const float longest = static_cast<float>(std::max({s[0], s[1], s[2]}));
    impl_->extent = {s[2] / longest, s[1] / longest, s[0] / longest};
    impl_->dim = 3;
  }
}

void Renderer::clear_frame() {
  impl_->dim = 0;
  impl_->extent = {0, 0, 0};
}

bool Renderer::has_frame() const { return impl_->dim != 0; }
std::array<float, 3> Renderer::domain_extent() const { return impl_->extent; }
int Renderer::frame_dim() const { return impl_->dim; }

void Renderer::render(const OrbitCamera& cam, const ViewSettings& view, int w, int h) {
  if (w <= 0 || h <= 0) return;
  glViewport(0, 0, w, h);
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 0, w, h);
  glClearColor(view.background[0], view.background[1], view.background[2], 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  if (!impl_->ready) return;
  const float aspect = static_cast<float>(w) / static_cast<float>(h);
  const auto& e = impl_->extent;
  if (impl_->dim == 2) {
    impl_->smoke2d.draw(cam.view_projection_2d(aspect, e[0], e[1]), 0.5f * e[0], 0.5f * e[1], view,
                        impl_->lines);
  } else if (impl_->dim == 3) {
    const Mat4 vp = mat4_mul(cam.projection(aspect), cam.view());
    impl_->smoke3d.draw(vp, {0.5f * e[0], 0.5f * e[1], 0.5f * e[2]}, view, impl_->lines);
  }
  glDisable(GL_BLEND);
  glUseProgram(0);
}

void Renderer::shutdown() {
  impl_->lines.shutdown();
  impl_->smoke2d.shutdown();
  impl_->smoke3d.shutdown();
  impl_->ready = false;
  clear_frame();
}

}  // namespace pliant::editor
