// Soft character take frames (engine/soft README, "Take"): the surface mesh
// ("vertices" [nverts, 3] each frame, "triangles" from frame 0) lit with the
// shared MeshDrawer, and in world-space lines: the ground grid (or the water
// volume's outline), the COM trail up to the shown frame, the position target,
// the heading arrow, the jump height ring and the pinned-vertex targets of the
// shown frame, all read from the take's own scene copy; sphere obstacles as
// grey meshes.
//
// Framing: the bounds are the ground patch covering the start and the goal
// (soft_goal), so a walk stays in view while the character moves.
#include "render/soft_drawer.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "doc/soft_scene.h"
#include "render/frame_drawer.h"
#include "render/mesh_drawer.h"
#include "render/renderer.h"

namespace pliant::editor {

namespace {

// UI thread only (the renderer and the panels run there).
std::map<uint64_t, SoftTakeData>& take_data_map() {
  static std::map<uint64_t, SoftTakeData> m;
  return m;
}

constexpr LineDrawer::Color kGrid{0.45f, 0.48f, 0.55f, 0.55f};
constexpr LineDrawer::Color kWater{0.35f, 0.6f, 0.95f, 0.8f};
constexpr LineDrawer::Color kTrail{1.0f, 0.85f, 0.3f, 0.95f};
constexpr LineDrawer::Color kTarget{0.35f, 0.95f, 0.45f, 1.0f};
constexpr LineDrawer::Color kHeading{0.3f, 0.8f, 1.0f, 1.0f};
constexpr LineDrawer::Color kJump{1.0f, 0.45f, 0.85f, 0.9f};
constexpr LineDrawer::Color kPin{1.0f, 0.3f, 0.3f, 1.0f};
constexpr MeshDrawer::Color kBody{0.93f, 0.62f, 0.38f, 1.0f};
constexpr MeshDrawer::Color kObstacle{0.55f, 0.58f, 0.66f, 1.0f};

Vec3 f3(const SoftVec3& v) { return {float(v[0]), float(v[1]), float(v[2])}; }
Vec3 add(const Vec3& a, const Vec3& b, float s = 1) { return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]}; }

// A grid step of 1, 2 or 5 x 10^k giving about `lines` lines over `extent`.
float nice_step(float extent, int lines) {
  const float raw = std::max(extent / float(lines), 1e-6f);
  const float p = std::pow(10.0f, std::floor(std::log10(raw)));
  for (float m : {1.0f, 2.0f, 5.0f})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

void add_arrow(LineDrawer& l, const Vec3& from, const Vec3& dir, float len, const LineDrawer::Color& c) {
  const Vec3 tip = add(from, dir, len);
  l.add(from, tip, c);
  // Head in the plane of dir and the up axis (or x when dir is vertical).
  Vec3 side = std::abs(dir[1]) > 0.9f ? Vec3{1, 0, 0} : Vec3{-dir[2], 0, dir[0]};
  const float n = std::sqrt(side[0] * side[0] + side[1] * side[1] + side[2] * side[2]);
  for (float& x : side) x /= std::max(n, 1e-9f);
  for (float s : {-1.0f, 1.0f}) l.add(tip, add(add(tip, dir, -0.25f * len), side, s * 0.12f * len), c);
}

void add_cross(LineDrawer& l, const Vec3& p, float r, const LineDrawer::Color& c) {
  for (int a = 0; a < 3; ++a) {
    Vec3 d{0, 0, 0};
    d[a] = r;
    l.add(add(p, d, -1), add(p, d), c);
  }
}

void add_ring(LineDrawer& l, const Vec3& centre, float r, const LineDrawer::Color& c) {
  constexpr int kSeg = 32;
  for (int i = 0; i < kSeg; ++i) {
    const float a0 = 6.2831853f * i / kSeg, a1 = 6.2831853f * (i + 1) / kSeg;
    l.add({centre[0] + r * std::cos(a0), centre[1], centre[2] + r * std::sin(a0)},
          {centre[0] + r * std::cos(a1), centre[1], centre[2] + r * std::sin(a1)}, c);
  }
}

class SoftDrawer;
SoftDrawer* g_primary = nullptr;

class SoftDrawer final : public FrameDrawer {
 public:
  SoftDrawer() {
    if (!g_primary) g_primary = this;
  }
  ~SoftDrawer() override {
    if (g_primary == this) g_primary = nullptr;
  }
  Mat4 last_world_to_clip = mat4_identity();
  int last_w = 0, last_h = 0;
  bool drawn = false;

  const char* name() const override { return "soft"; }
  bool init(std::string* err) override { return mesh_.init(err); }

  bool upload(const Record& frame, const nlohmann::json* take_scene) override {
    const Field* v = frame.find("vertices");
    if (!v || v->shape.size() != 2 || v->shape[1] != 3 || v->data.size() != size_t(v->shape[0]) * 3) return false;
    const size_t nverts = v->shape[0];
    if (nverts == 0) return false;
    key_ = take_scene ? soft_scene_key(*take_scene) : 0;
    info_ = take_scene ? soft_scene_info(*take_scene) : SoftSceneInfo{};
    frame_index_ = frame.index;
    pins_ = take_scene ? soft_pins(*take_scene) : std::vector<SoftPin>{};
    if (const Field* t = frame.find("triangles"); t && t->shape.size() == 2 && t->shape[1] == 3) {
      triangles_.resize(t->data.size());
      for (size_t i = 0; i < t->data.size(); ++i) triangles_[i] = uint32_t(std::max(0.0f, t->data[i]));
      triangles_nverts_ = nverts;
    } else if (triangles_nverts_ != nverts || triangles_key_ != key_) {
      triangles_.clear();
      auto it = take_data_map().find(key_);
      if (it != take_data_map().end() && it->second.rest_vertices.size() == nverts * 3)
        triangles_ = it->second.triangles;
      triangles_nverts_ = triangles_.empty() ? 0 : nverts;
    }
    triangles_key_ = key_;
    vertices_ = v->data;
    com_ = mean_vertex();
    if (const Field* c = frame.find("com"); c && c->data.size() == 3) com_ = {c->data[0], c->data[1], c->data[2]};
    // Extent of this frame's body.
    lo_ = hi_ = {vertices_[0], vertices_[1], vertices_[2]};
    for (size_t i = 0; i < nverts; ++i)
      for (int a = 0; a < 3; ++a) {
        lo_[a] = std::min(lo_[a], vertices_[3 * i + a]);
        hi_[a] = std::max(hi_[a], vertices_[3 * i + a]);
      }
    body_lo_ = lo_;
    body_hi_ = hi_;
    start_ = com_;
    if (auto it = take_data_map().find(key_); it != take_data_map().end() && it->second.rest_vertices.size() >= 3) {
      const auto& r = it->second.rest_vertices;
      body_lo_ = body_hi_ = {r[0], r[1], r[2]};
      for (size_t i = 0; i + 2 < r.size(); i += 3)
        for (int a = 0; a < 3; ++a) {
          body_lo_[a] = std::min(body_lo_[a], r[i + a]);
          body_hi_[a] = std::max(body_hi_[a], r[i + a]);
        }
      if (!it->second.com.empty()) start_ = it->second.com[0];
    }
    mesh_.clear();
    for (const auto& sp : info_.spheres)  // obstacles
      mesh_.add_sphere(pose_matrix(f3(sp.center), {1, 0, 0, 0}), float(sp.radius), kObstacle);
    if (!triangles_.empty())
      mesh_.add_mesh(vertices_.data(), nverts, triangles_.data(), triangles_.size() / 3, kBody, mat4_identity());
    else
      for (size_t i = 0; i < nverts; ++i)  // no triangles yet: the vertices as small boxes
        mesh_.add_box(pose_matrix({vertices_[3 * i], vertices_[3 * i + 1], vertices_[3 * i + 2]}, {1, 0, 0, 0}),
                      {body_size() * 0.01f, body_size() * 0.01f, body_size() * 0.01f}, kBody);
    return true;
  }

  WorldBox bounds() const override { return patch(); }
  int dim() const override { return 3; }

  void draw(const DrawContext& ctx) override {
    last_world_to_clip = ctx.world_to_clip;
    last_w = ctx.width;
    last_h = ctx.height;
    drawn = true;
    mesh_.draw(ctx.world_to_clip, ctx.world_to_view);
    if (!ctx.lines) return;
    LineDrawer& l = *ctx.lines;
    const bool show_grid = !ctx.view || ctx.view->show_grid;
    const WorldBox p = patch();
    if (info_.water) {
      if (show_grid) l.add_box(p.lo, p.hi, kWater);
    } else if (info_.ground && show_grid) {
      const float y = float(info_.ground_y);
      const float step = nice_step(std::max(p.hi[0] - p.lo[0], p.hi[2] - p.lo[2]), 16);
      for (float x = std::ceil(p.lo[0] / step) * step; x <= p.hi[0]; x += step) l.add({x, y, p.lo[2]}, {x, y, p.hi[2]}, kGrid);
      for (float z = std::ceil(p.lo[2] / step) * step; z <= p.hi[2]; z += step) l.add({p.lo[0], y, z}, {p.hi[0], y, z}, kGrid);
    }
    const SoftTakeData* data = nullptr;
    if (auto it = take_data_map().find(key_); it != take_data_map().end()) data = &it->second;
    const float size = body_size();
    // COM trail up to the shown frame.
    if (data)
      for (int i = 1; i <= frame_index_ && i < int(data->com.size()); ++i) l.add(data->com[i - 1], data->com[i], kTrail);
    // Objectives.
    if (info_.has_position) {
      const Vec3 t = f3(info_.position_target);
      add_cross(l, t, 0.3f * size, kTarget);
      add_ring(l, t, 0.3f * size, kTarget);
    } else if (info_.has_velocity || info_.has_distance) {
      const Vec3 s = start();
      const Vec3 g = f3(soft_goal(info_, {s[0], s[1], s[2]}));
      add_cross(l, g, 0.3f * size, kTarget);
    }
    if (info_.has_heading) add_arrow(l, com_, f3(info_.heading_direction), 0.8f * size, kHeading);
    if (info_.has_jump && info_.jump_height > 0) {
      const Vec3 s = start();
      add_ring(l, {com_[0], s[1] + float(info_.jump_height), com_[2]}, 0.4f * size, kJump);
      l.add({com_[0], s[1], com_[2]}, {com_[0], s[1] + float(info_.jump_height), com_[2]}, kJump);
    }
    // Pins of this frame: vertex -> its target (rest + start offset + offset).
    if (data && !pins_.empty()) {
      const size_t n = vertices_.size() / 3;
      for (const SoftPin& pin : pins_) {
        if (pin.frame != frame_index_ || pin.vertex < 0 || size_t(pin.vertex) >= n ||
            data->rest_vertices.size() != vertices_.size())
          continue;
        const float* r = &data->rest_vertices[3 * size_t(pin.vertex)];
        const Vec3 target{r[0] + float(pin.offset[0]), r[1] + float(pin.offset[1]), r[2] + float(pin.offset[2])};
        const float* x = &vertices_[3 * size_t(pin.vertex)];
        add_cross(l, target, 0.06f * size, kPin);
        l.add({x[0], x[1], x[2]}, target, kPin);
      }
    }
  }

  void shutdown() override { mesh_.shutdown(); }

 private:
  Vec3 mean_vertex() const {
    Vec3 m{0, 0, 0};
    const size_t n = vertices_.size() / 3;
    for (size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) m[a] += vertices_[3 * i + a];
    for (float& x : m) x /= float(std::max<size_t>(n, 1));
    return m;
  }
  float body_size() const {
    return std::max({body_hi_[0] - body_lo_[0], body_hi_[1] - body_lo_[1], body_hi_[2] - body_lo_[2], 1e-3f});
  }
  // The character's centre at frame 0 (the trail's first point when known).
  Vec3 start() const { return start_; }
  // Ground patch: the body, the start and the goal with a margin of a body size.
  WorldBox patch() const {
    WorldBox b;
    if (vertices_.empty()) return b;
    const Vec3 s = start();
    const Vec3 g = f3(soft_goal(info_, {s[0], s[1], s[2]}));
    const float size = body_size();
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min({body_lo_[a], s[a], g[a]}) - 0.5f * size;
      b.hi[a] = std::max({body_hi_[a], s[a], g[a]}) + 0.5f * size;
    }
    if (info_.ground && !info_.water) b.lo[1] = float(info_.ground_y);
    if (info_.has_jump) b.hi[1] = std::max(b.hi[1], body_hi_[1] + float(info_.jump_height));
    return b;
  }

  MeshDrawer mesh_;
  uint64_t key_ = 0, triangles_key_ = ~uint64_t(0);
  SoftSceneInfo info_;
  int frame_index_ = 0;
  std::vector<float> vertices_;
  std::vector<uint32_t> triangles_;
  size_t triangles_nverts_ = 0;
  Vec3 com_{0, 0, 0}, lo_{0, 0, 0}, hi_{0, 0, 0};
  // Frame 0's body extent and centre when the take's data is known (else this
  // frame's): the framing must not depend on which frame was shown first.
  Vec3 body_lo_{0, 0, 0}, body_hi_{0, 0, 0}, start_{0, 0, 0};
  std::vector<SoftPin> pins_;
};

}  // namespace

uint64_t soft_scene_key(const nlohmann::json& take_scene) { return std::hash<std::string>{}(take_scene.dump()); }

void soft_drawer_set_take_data(uint64_t scene_key, SoftTakeData data) {
  take_data_map()[scene_key] = std::move(data);
}

const SoftTakeData* soft_drawer_take_data(uint64_t scene_key) {
  auto it = take_data_map().find(scene_key);
  return it == take_data_map().end() ? nullptr : &it->second;
}

bool soft_drawer_primary_view(Mat4* world_to_clip, int* w, int* h) {
  if (!g_primary || !g_primary->drawn) return false;
  *world_to_clip = g_primary->last_world_to_clip;
  *w = g_primary->last_w;
  *h = g_primary->last_h;
  return true;
}

std::unique_ptr<FrameDrawer> make_soft_drawer() { return std::make_unique<SoftDrawer>(); }

}  // namespace pliant::editor
