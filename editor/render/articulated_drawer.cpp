// Articulated take frames: each body's geoms (capsules, boxes, spheres) posed
// by the frame's "body_pose" [nb, 7], static obstacles and a checkered ground
// patch for planes, contact points with force arrows ("contacts" [n, 6]).
// The model is compiled from the take's scene copy once per scene and cached.
#include "render/articulated_drawer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "render/frame_drawer.h"
#include "render/mesh_drawer.h"


namespace pliant::editor {

namespace {

namespace fs = std::filesystem;

fs::path& scene_dir() {
  static fs::path d;
  return d;
}
ArticulatedFrameInfo& frame_info() {
  static ArticulatedFrameInfo i;
  return i;
}
int& highlight_body() {
  static int b = 0;
  return b;
}

using Shape = ArticulatedGeom::Shape;
using GeomView = ArticulatedGeom;

ArticulatedGeometryFn& geometry_source() {
  static ArticulatedGeometryFn f = nullptr;
  return f;
}

float bound_radius(const GeomView& g) {
  switch (g.shape) {
    case Shape::Sphere: return g.size[0];
    case Shape::Capsule: return g.size[0] + g.size[1];
    case Shape::Box: return std::sqrt(g.size[0] * g.size[0] + g.size[1] * g.size[1] + g.size[2] * g.size[2]);
    case Shape::Mesh: return g.mesh ? g.mesh->radius : 0;
    default: return 0;
  }
}

struct ModelView : ArticulatedGeometry {
  std::string key;  // scene text + folder it was compiled for
  bool ok = false;
  std::string error;
};

// World z-up -> display y-up: display = (x, z, -y).
const Mat4 kZupToYup = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
Vec3 to_display(const Vec3& p) { return {p[0], p[2], -p[1]}; }

Vec3 rotate(const std::array<float, 4>& q, const Vec3& v) {
  const Mat4 m = pose_matrix({0, 0, 0}, q);
  return {m[0] * v[0] + m[4] * v[1] + m[8] * v[2], m[1] * v[0] + m[5] * v[1] + m[9] * v[2],
          m[2] * v[0] + m[6] * v[1] + m[10] * v[2]};
}
Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
float dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Mat4 translation(const Vec3& t) {
  Mat4 m = mat4_identity();
  m[12] = t[0];
  m[13] = t[1];
  m[14] = t[2];
  return m;
}

void compile_model(const nlohmann::json* scene, ModelView* mv) {
  const std::string key = (scene ? scene->dump() : std::string()) + "\n" + scene_dir().string();
  if (key == mv->key) return;
  *mv = ModelView{};
  mv->key = key;
  if (!geometry_source()) {
    mv->error = "no articulated engine in this editor build";
    return;
  }
  if (!scene || !scene->is_object()) {
    mv->error = "the take has no scene copy";
    return;
  }
  std::string err;
  ArticulatedGeometry g;
  if (geometry_source()(*scene, scene_dir(), &g, &err)) {
    static_cast<ArticulatedGeometry&>(*mv) = std::move(g);
    mv->ok = true;
  } else {
    mv->error = err;
  }
}

// Body colours: distinct, mid-bright hues that read on the dark background.
// The selected body is tinted towards a pale yellow (stands out from every hue).
MeshDrawer::Color body_color(int b) {
  static const MeshDrawer::Color kPalette[] = {
      {0.90f, 0.55f, 0.25f, 1}, {0.35f, 0.65f, 0.90f, 1}, {0.55f, 0.80f, 0.40f, 1}, {0.85f, 0.40f, 0.55f, 1},
      {0.75f, 0.70f, 0.35f, 1}, {0.55f, 0.50f, 0.85f, 1}, {0.35f, 0.78f, 0.72f, 1}, {0.88f, 0.62f, 0.70f, 1}};
  MeshDrawer::Color c = kPalette[(b - 1 + 64) % 8];
  if (b > 0 && b == highlight_body()) {
    const float tint[3] = {1.0f, 0.97f, 0.55f};
    for (int i = 0; i < 3; ++i) c[i] = 0.35f * c[i] + 0.65f * tint[i];
  }
  return c;
}

class ArticulatedDrawer;
ArticulatedDrawer*& primary_drawer() {
  static ArticulatedDrawer* d = nullptr;
  return d;
}

// "Nice" tile size near x: 1, 2 or 5 times a power of ten.
float nice_step(float x) {
  if (!(x > 0)) return 0.1f;
  const float p = std::pow(10.0f, std::floor(std::log10(x)));
  const float f = x / p;
  return (f < 1.5f ? 1 : f < 3.5f ? 2 : 5) * p;
}

class ArticulatedDrawer final : public FrameDrawer {
 public:
  ArticulatedDrawer() {
    if (!primary_drawer()) primary_drawer() = this;
  }
  ~ArticulatedDrawer() override {
    if (primary_drawer() == this) primary_drawer() = nullptr;
  }
  const ArticulatedView& view() const { return view_; }
  const char* name() const override { return "articulated"; }
  bool init(std::string* err) override { return mesh_.init(err); }

  bool upload(const Record& frame, const nlohmann::json* take_scene) override {
    const Field* pose = frame.find("body_pose");
    if (!pose || pose->shape.size() != 2 || pose->shape[1] != 7 ||
        pose->data.size() != size_t(pose->shape[0]) * 7)
      return false;
    const std::string old_key = model_.key;
    compile_model(take_scene, &model_);
    const int nb = static_cast<int>(pose->shape[0]);
    const bool use_model = model_.ok && model_.bodies == nb;
    std::vector<Vec3> pos(nb + 1, Vec3{0, 0, 0});
    std::vector<std::array<float, 4>> quat(nb + 1, std::array<float, 4>{1, 0, 0, 0});
    for (int b = 0; b < nb; ++b) {
      const float* p = pose->data.data() + 7 * b;
      pos[b + 1] = {p[0], p[1], p[2]};
      quat[b + 1] = {p[3], p[4], p[5], p[6]};
    }
    if (model_.key != old_key || !have_reference_) {
      reference_root_ = nb > 0 ? pos[1] : Vec3{0, 0, 0};
      have_reference_ = true;
      bounds_ = compute_bounds(pos, quat, use_model);
    }
    const ArticulatedDrawOptions& opt = articulated_draw_options();
    // Follow: shift the world so the root body keeps its first horizontal place.
    Vec3 shift{0, 0, 0};
    if (opt.follow && model_.floating && nb > 0)
      shift = {reference_root_[0] - pos[1][0], reference_root_[1] - pos[1][1], 0};
    const Mat4 world = mat4_mul(kZupToYup, translation(shift));
    world_ = world;
    view_.model = use_model ? &model_ : nullptr;
    view_.pos = pos;
    view_.quat = quat;

    mesh_.clear();
    int geoms_drawn = 0;
    if (use_model) {
      for (const GeomView& g : model_.geoms) {
        if (g.body == 0) continue;
        const Mat4 body = pose_matrix(pos[g.body], quat[g.body]);
        const Mat4 m = mat4_mul(world, mat4_mul(body, pose_matrix(g.pos, g.quat)));
        add_primitive(g, m, body_color(g.body));
        ++geoms_drawn;
      }
      for (const GeomView& g : model_.geoms) {
        if (g.body != 0) continue;
        if (g.shape == Shape::Plane) add_ground(g, world, nb > 0 ? pos[1] : Vec3{0, 0, 0});
        else add_primitive(g, mat4_mul(world, pose_matrix(g.pos, g.quat)), {0.55f, 0.56f, 0.60f, 1});
      }
    } else {
      // No model (compile failed or body count differs): the body origins as balls.
      const float r = 0.02f * longest_side();
      for (int b = 1; b <= nb; ++b) mesh_.add_sphere(mat4_mul(world, pose_matrix(pos[b], quat[b])), r, body_color(b));
    }

    // Contacts: display-space segments, drawn by the shared LineDrawer in draw().
    segments_.clear();
    ArticulatedFrameInfo& info = frame_info();
    info = ArticulatedFrameInfo{};
    info.bodies = nb;
    info.geoms = geoms_drawn;
    info.model_error = model_.ok ? (use_model ? "" : "model has " + std::to_string(model_.bodies) +
                                                         " bodies, the take " + std::to_string(nb))
                                 : model_.error;
    const Field* contacts = frame.find("contacts");
    if (contacts && contacts->shape.size() == 2 && contacts->shape[1] == 6 &&
        contacts->data.size() == size_t(contacts->shape[0]) * 6) {
      const int nc = static_cast<int>(contacts->shape[0]);
      info.contacts = nc;
      for (int c = 0; c < nc; ++c) {
        const float* d = contacts->data.data() + 6 * c;
        info.max_force = std::max(info.max_force, std::sqrt(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]));
      }
      if (opt.show_contacts) add_contacts(contacts->data.data(), nc, shift, opt.force_scale, info.max_force);
    }
    if (const Field* e = frame.find("energy"); e && e->data.size() == 3) {
      info.has_energy = true;
      for (int i = 0; i < 3; ++i) info.energy[i] = e->data[i];
    }
    return true;
  }

  WorldBox bounds() const override { return bounds_; }
  int dim() const override { return 3; }

  void draw(const DrawContext& ctx) override {
    view_.drawn = true;
    view_.world_to_clip = mat4_mul(ctx.world_to_clip, world_);
    view_.width = ctx.width;
    view_.height = ctx.height;
    mesh_.draw(ctx.world_to_clip, ctx.world_to_view);
    if (ctx.lines)
      for (const Segment& s : segments_) ctx.lines->add(s.a, s.b, s.color);
  }

  void shutdown() override {
    mesh_.shutdown();
    model_ = ModelView{};
    have_reference_ = false;
    view_ = ArticulatedView{};
  }

 private:
  struct Segment {
    Vec3 a, b;
    LineDrawer::Color color;
  };

  float longest_side() const {
    if (bounds_.empty()) return 1.0f;
    return std::max({bounds_.hi[0] - bounds_.lo[0], bounds_.hi[1] - bounds_.lo[1], bounds_.hi[2] - bounds_.lo[2],
                     1e-3f});
  }

  void add_primitive(const GeomView& g, const Mat4& m, const MeshDrawer::Color& c) {
    switch (g.shape) {
      case Shape::Sphere: mesh_.add_sphere(m, g.size[0], c); break;
      case Shape::Capsule: mesh_.add_capsule(m, g.size[0], g.size[1], c); break;
      case Shape::Box: mesh_.add_box(m, g.size, c); break;
      case Shape::Mesh:
        if (g.mesh)
          mesh_.add_mesh(g.mesh->xyz.data(), g.mesh->xyz.size() / 3, g.mesh->triangles.data(),
                         g.mesh->triangles.size() / 3, c, m, /*crease_deg=*/40);
        break;
      case Shape::Plane: break;
    }
  }

  // A checkered patch of an infinite plane around the root body's foot point;
  // tiles are snapped to the plane's own grid so they move when the view follows.
  void add_ground(const GeomView& g, const Mat4& world, const Vec3& root) {
    const Vec3 u = rotate(g.quat, {1, 0, 0}), v = rotate(g.quat, {0, 1, 0});
    const float tile = nice_step(longest_side() / 8);
    const int half = 12;  // tiles each way
    const Vec3 rel{root[0] - g.pos[0], root[1] - g.pos[1], root[2] - g.pos[2]};
    const int cu = int(std::floor(dot(rel, u) / tile)), cv = int(std::floor(dot(rel, v) / tile));
    std::vector<float> xyz[2];
    std::vector<uint32_t> tris[2];
    for (int i = cu - half; i < cu + half; ++i)
      for (int j = cv - half; j < cv + half; ++j) {
        const int k = ((i + j) % 2 + 2) % 2;
        const uint32_t base = static_cast<uint32_t>(xyz[k].size() / 3);
        for (int c = 0; c < 4; ++c) {
          const float a = (i + (c == 1 || c == 2)) * tile, b = (j + (c >= 2)) * tile;
          for (int d = 0; d < 3; ++d) xyz[k].push_back(g.pos[d] + a * u[d] + b * v[d]);
        }
        for (uint32_t t : {0u, 1u, 2u, 0u, 2u, 3u}) tris[k].push_back(base + t);
      }
    const MeshDrawer::Color colors[2] = {{0.30f, 0.31f, 0.34f, 1}, {0.24f, 0.25f, 0.28f, 1}};
    for (int k = 0; k < 2; ++k)
      mesh_.add_mesh(xyz[k].data(), xyz[k].size() / 3, tris[k].data(), tris[k].size() / 3, colors[k], world);
  }

  void add_contacts(const float* d, int n, const Vec3& shift, float force_scale, float max_force) {
    const float size = longest_side();
    // Arrow length grows with the force and saturates at 0.4 x the view, so an
    // impact many times the weight stays on screen: a force equal to the model's
    // weight (x force_scale) is 0.25 x the view. Without a mass, the frame's
    // largest force is the unit.
    const double weight = model_.ok ? model_.total_mass * model_.gravity : 0;
    const float unit = float(weight > 1e-9 ? weight : std::max(max_force, 1e-6f));
    auto arrow_length = [&](float f) { return 0.4f * size * (1.0f - std::exp(-force_scale * f / unit)); };
    const LineDrawer::Color point_color{1.0f, 0.92f, 0.3f, 1}, arrow_color{1.0f, 0.35f, 0.25f, 1};
    const float cross = 0.012f * size;
    for (int c = 0; c < n; ++c) {
      const float* e = d + 6 * c;
      const Vec3 p = to_display(add({e[0], e[1], e[2]}, shift));
      for (int axis = 0; axis < 3; ++axis) {
        Vec3 a = p, b = p;
        a[axis] -= cross;
        b[axis] += cross;
        segments_.push_back({a, b, point_color});
      }
      const Vec3 f = to_display({e[3], e[4], e[5]});
      const float fn = std::sqrt(dot(f, f));
      const float len = arrow_length(fn);
      if (len < 1e-4f * size) continue;
      const Vec3 dir{f[0] / fn, f[1] / fn, f[2] / fn};
      const Vec3 tip{p[0] + len * dir[0], p[1] + len * dir[1], p[2] + len * dir[2]};
      segments_.push_back({p, tip, arrow_color});
      // Arrow head: two short strokes back from the tip, in a plane holding the arrow.
      Vec3 side = std::fabs(dir[1]) < 0.9f ? Vec3{-dir[2], 0, dir[0]} : Vec3{0, dir[2], -dir[1]};
      const float sl = std::sqrt(dot(side, side));
      const float head = std::min(0.25f * len, 0.04f * size);
      for (int s = -1; s <= 1; s += 2) {
        Vec3 h;
        for (int i = 0; i < 3; ++i) h[i] = tip[i] - head * dir[i] + s * 0.5f * head * side[i] / sl;
        segments_.push_back({tip, h, arrow_color});
      }
    }
  }

  // Fixed framing box (display units) from the first frame of a take: a fixed-base
  // model stays inside the ball its reach sweeps around the root; a floating one
  // gets its first pose's box grown by a quarter of its longest side each way.
  WorldBox compute_bounds(const std::vector<Vec3>& pos, const std::vector<std::array<float, 4>>& quat,
                          bool use_model) const {
    const int nb = static_cast<int>(pos.size()) - 1;
    Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    auto grow = [&](const Vec3& c, float r) {
      for (int i = 0; i < 3; ++i) {
        lo[i] = std::min(lo[i], c[i] - r);
        hi[i] = std::max(hi[i], c[i] + r);
      }
    };
    float reach = 0;
    const Vec3 root = nb > 0 ? pos[1] : Vec3{0, 0, 0};
    if (use_model) {
      for (const GeomView& g : model_.geoms) {
        if (g.shape == Shape::Plane) continue;
        const Vec3 c = g.body == 0 ? g.pos : add(pos[g.body], rotate(quat[g.body], g.pos));
        grow(c, bound_radius(g));
        if (g.body != 0) {
          const Vec3 d{c[0] - root[0], c[1] - root[1], c[2] - root[2]};
          reach = std::max(reach, std::sqrt(dot(d, d)) + bound_radius(g));
        }
      }
    }
    for (int b = 1; b <= nb; ++b) grow(pos[b], 0);
    if (!(hi[0] >= lo[0])) grow({0, 0, 0}, 0.5f);
    if (use_model && !model_.floating && reach > 0) {
      grow(root, reach);
    } else {
      const float pad = 0.25f * std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 0.1f});
      for (int i = 0; i < 3; ++i) {
        lo[i] -= pad;
        hi[i] += pad;
      }
    }
    WorldBox box;
    box.lo = {lo[0], lo[2], -hi[1]};
    box.hi = {hi[0], hi[2], -lo[1]};
    return box;
  }

  MeshDrawer mesh_;
  ModelView model_;
  WorldBox bounds_;
  Vec3 reference_root_{0, 0, 0};
  bool have_reference_ = false;
  std::vector<Segment> segments_;
  Mat4 world_ = mat4_identity();  // engine world -> display world of the last upload
  ArticulatedView view_;
};

}  // namespace

ArticulatedDrawOptions& articulated_draw_options() {
  static ArticulatedDrawOptions o;
  return o;
}

void articulated_drawer_set_scene_dir(const fs::path& dir) { scene_dir() = dir; }
void articulated_drawer_set_geometry_source(ArticulatedGeometryFn fn) { geometry_source() = fn; }

const ArticulatedFrameInfo& articulated_last_frame_info() { return frame_info(); }

const ArticulatedView* articulated_primary_view() {
  return primary_drawer() && primary_drawer()->view().drawn ? &primary_drawer()->view() : nullptr;
}

bool articulated_drawer_set_highlight(int body) {
  if (highlight_body() == body) return false;
  highlight_body() = body;
  return true;
}

std::unique_ptr<FrameDrawer> make_articulated_drawer() { return std::make_unique<ArticulatedDrawer>(); }

}  // namespace pliant::editor
