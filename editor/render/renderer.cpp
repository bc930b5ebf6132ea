#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "render/frame_drawer.h"
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
  std::vector<std::unique_ptr<FrameDrawer>> kinds;  // liquid, soft, articulated
  FrameDrawer* active = nullptr;                    // kind drawer of the shown frame
  bool framed = false;
  bool frame0_seen = false;  // set_take_frame looked at frame 0 since reset_framing()
  Vec3 centre{0, 0, 0};
  float scale = 1;  // world units -> unit box
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
  for (auto make : {make_liquid_drawer, make_soft_drawer, make_articulated_drawer}) {
    std::unique_ptr<FrameDrawer> d = make();
    if (!d) continue;
    if (!d->init(&e)) {
      if (err) *err = std::string("renderer: ") + d->name() + ": " + e;
      return false;
    }
    impl_->kinds.push_back(std::move(d));
  }
  impl_->ready = true;
  return true;
}

namespace {
// The unit-box framing of a kind drawer's world bounds (longest side -> 1).
void frame_bounds(const WorldBox& b, int dim, Vec3* centre, float* scale, std::array<float, 3>* extent) {
  Vec3 size{0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    (*centre)[i] = 0.5f * (b.lo[i] + b.hi[i]);
    size[i] = b.hi[i] - b.lo[i];
  }
  if (dim == 2) size[2] = 0;
  float longest = std::max({size[0], size[1], size[2]});
  if (!(longest > 1e-9f) || !std::isfinite(longest)) longest = 1;
  *scale = 1.0f / longest;
  *extent = {size[0] * *scale, size[1] * *scale, size[2] * *scale};
  for (int i = 0; i < 3; ++i) (*extent)[i] = std::max((*extent)[i], 1e-3f);
  if (dim == 2) (*extent)[2] = 0;
}
}  // namespace

void Renderer::set_frame(const Record& frame, const nlohmann::json* take_scene) {
  impl_->active = nullptr;
  const Field* density = find_field(frame, "density");
  if (!impl_->ready) return;
  if (density == nullptr || !well_formed(*density) ||
      (density->shape.size() != 2 && density->shape.size() != 3)) {
    for (auto& d : impl_->kinds) {
      if (!d->upload(frame, take_scene)) continue;
      impl_->active = d.get();
      impl_->dim = d->dim() == 2 ? 2 : 3;
      const WorldBox b = d->bounds();
      if (!impl_->framed && !b.empty()) {
        frame_bounds(b, impl_->dim, &impl_->centre, &impl_->scale, &impl_->extent);
        impl_->framed = true;
      }
      if (!impl_->framed) impl_->extent = {1, 1, impl_->dim == 2 ? 0.0f : 1.0f};
      return;
    }
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

void Renderer::set_take_frame(TakeReader& take, size_t i) {
  const nlohmann::json* scene = &take.manifest().scene;
  if (!impl_->framed && !impl_->frame0_seen && i != 0) set_frame(take.read_frame_at(0), scene);
  impl_->frame0_seen = true;
  set_frame(take.read_frame_at(i), scene);
}

void Renderer::clear_frame() {
  impl_->active = nullptr;
  impl_->dim = 0;
  impl_->extent = {0, 0, 0};
}

bool Renderer::has_frame() const { return impl_->dim != 0; }
std::array<float, 3> Renderer::domain_extent() const { return impl_->extent; }
int Renderer::frame_dim() const { return impl_->dim; }
void Renderer::reset_framing() {
  impl_->framed = false;
  impl_->frame0_seen = false;
}
std::string Renderer::drawer_name() const { return impl_->active ? impl_->active->name() : ""; }

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
  if (impl_->active) {
    // World -> unit box: scale about the framing centre.
    const float s = impl_->scale;
    const Vec3& c = impl_->centre;
    Mat4 framing = mat4_identity();
    framing[0] = framing[5] = framing[10] = s;
    framing[12] = -s * c[0];
    framing[13] = -s * c[1];
    framing[14] = impl_->dim == 2 ? 0.0f : -s * c[2];
    DrawContext ctx;
    ctx.width = w;
    ctx.height = h;
    ctx.view = &view;
    ctx.lines = &impl_->lines;
    if (impl_->dim == 2) {
      const Mat4 vp = cam.view_projection_2d(aspect, e[0], e[1]);
      ctx.world_to_clip = mat4_mul(vp, framing);
      ctx.world_to_view = ctx.world_to_clip;
      ctx.pixels_per_metre = 0.5f * vp[0] * w * s;
      ctx.eye_world = {c[0], c[1], c[2] + 1.0f / s};
    } else {
      const Mat4 v = cam.view();
      ctx.world_to_view = mat4_mul(v, framing);
      ctx.world_to_clip = mat4_mul(cam.projection(aspect), ctx.world_to_view);
      const Vec3 eye = cam.eye();
      for (int i = 0; i < 3; ++i) ctx.eye_world[i] = c[i] + eye[i] / s;
      const float f = 1.0f / std::tan(0.5f * cam.fov_deg * 3.14159265f / 180.0f);
      ctx.pixels_per_metre = 0.5f * h * f * s / std::max(cam.distance, 1e-3f);
    }
    glEnable(GL_DEPTH_TEST);
    impl_->active->draw(ctx);
    glDisable(GL_DEPTH_TEST);
    impl_->lines.draw(ctx.world_to_clip);
  } else if (impl_->dim == 2) {
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
  for (auto& d : impl_->kinds) d->shutdown();
  impl_->kinds.clear();
  impl_->active = nullptr;
  impl_->lines.shutdown();
  impl_->smoke2d.shutdown();
  impl_->smoke3d.shutdown();
  impl_->ready = false;
  clear_frame();
}

}  // namespace pliant::editor
