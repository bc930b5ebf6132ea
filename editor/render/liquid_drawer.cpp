// Liquid take frames (engine/liquid/README.md, "Take fields"): "particles" [n, dim]
// as point sprites coloured by "speed" [n], the source and target containers at
// "source_pose" / "target_pose" [7]. 3D containers are the marching-tetrahedra
// surface of their wall SDF (render/liquid_container_mesh.h), drawn see-through
// after the particles; 2D containers are their z = 0 section as lines.
// Container meshes are built once per take scene and reposed every frame.
#include "render/liquid_drawer.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "render/mesh_drawer.h"

namespace pliant::editor {

namespace {

LiquidSceneResolver g_resolver = nullptr;
LiquidViewTransform g_last_view;

constexpr float kSpeedWhite = 1.5f;  // m/s drawn white: a free fall of ~11 cm
const MeshDrawer::Color kSourceColor{0.80f, 0.82f, 0.88f, 0.35f};
const MeshDrawer::Color kTargetColor{0.55f, 0.85f, 0.55f, 0.35f};
const LineDrawer::Color kSourceLine{0.85f, 0.87f, 0.95f, 1.0f};
const LineDrawer::Color kTargetLine{0.55f, 0.90f, 0.55f, 1.0f};
const LineDrawer::Color kPathLine{0.95f, 0.75f, 0.35f, 0.6f};

Vec3 pose_apply(const Pose7& p, float x, float y, float z) {
  const Mat4 m = pose_matrix({p[0], p[1], p[2]}, {p[3], p[4], p[5], p[6]});
  return {m[0] * x + m[4] * y + m[8] * z + m[12], m[1] * x + m[5] * y + m[9] * z + m[13],
          m[2] * x + m[6] * y + m[10] * z + m[14]};
}

bool read_pose(const Record& r, const char* name, Pose7* out) {
  const Field* f = r.find(name);
  if (!f || f->data.size() != 7) return false;
  std::copy(f->data.begin(), f->data.end(), out->begin());
  return true;
}

void grow(WorldBox* b, const Vec3& p) {
  for (int i = 0; i < 3; ++i) {
    b->lo[i] = std::min(b->lo[i], p[i]);
    b->hi[i] = std::max(b->hi[i], p[i]);
  }
}

struct BuiltContainer {
  bool present = false;
  TriangleMesh mesh;                  // 3D
  std::vector<LineSegment2> section;  // 2D
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};      // of the drawn surface, local
};

BuiltContainer build(const LiquidContainerGeometry& g, int dim) {
  BuiltContainer b;
  b.present = static_cast<bool>(g.wall_sdf);
  if (!b.present) return b;
  b.lo = {1e30f, 1e30f, 1e30f};
  b.hi = {-1e30f, -1e30f, -1e30f};
  WorldBox box{b.lo, b.hi};
  if (dim == 2) {
    b.section = sdf_section_lines(g.wall_sdf, g.lo, g.hi, g.step);
    for (const auto& s : b.section) {
      grow(&box, {s.ax, s.ay, 0});
      grow(&box, {s.bx, s.by, 0});
    }
  } else {
    b.mesh = sdf_surface_mesh(g.wall_sdf, g.lo, g.hi, g.step);
    for (size_t i = 0; i < b.mesh.vertex_count(); ++i)
      grow(&box, {b.mesh.xyz[3 * i], b.mesh.xyz[3 * i + 1], b.mesh.xyz[3 * i + 2]});
  }
  if (box.empty()) box = {g.lo, g.hi};
  b.lo = box.lo;
  b.hi = box.hi;
  return b;
}

class LiquidDrawer final : public FrameDrawer {
 public:
  const char* name() const override { return "liquid"; }

  bool init(std::string* err) override {
    if (!points_.build("liquid_points.vert", "liquid_points.frag", err)) return false;
    if (!meshes_.init(err)) return false;
    vao_ = gl::make_vertex_array();
    vbo_ = gl::make_buffer();
    glBindVertexArray(vao_.get());
    glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    return true;
  }

  bool upload(const Record& frame, const nlohmann::json* take_scene) override {
    const Field* p = frame.find("particles");
    if (!p || p->shape.size() != 2 || (p->shape[1] != 2 && p->shape[1] != 3)) return false;
    const size_t n = p->shape[0];
    const int pdim = int(p->shape[1]);
    if (p->data.size() != n * pdim) return false;
    const Field* sp = frame.find("speed");
    const bool has_speed = sp && sp->data.size() == n;
    dim_ = pdim;
    resolve(take_scene);

    const float* xs = p->data.data();
    const float* ss = has_speed ? sp->data.data() : nullptr;
    staging_.resize(4 * n);
    particle_box_ = {{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
    for (size_t i = 0; i < n; ++i) {
      const Vec3 q{xs[pdim * i], xs[pdim * i + 1], pdim == 3 ? xs[pdim * i + 2] : 0.0f};
      staging_[4 * i] = q[0];
      staging_[4 * i + 1] = q[1];
      staging_[4 * i + 2] = q[2];
      staging_[4 * i + 3] = ss ? ss[i] : 0.0f;
      grow(&particle_box_, q);
    }
    count_ = n;
    points_dirty_ = true;

    has_source_pose_ = read_pose(frame, "source_pose", &source_pose_);
    has_target_pose_ = read_pose(frame, "target_pose", &target_pose_);
    if (!has_target_pose_) target_pose_ = geo_.target_pose;
    meshes_dirty_ = true;
    return true;
  }

  WorldBox bounds() const override {
    // Framing must not depend on which frame is drawn first (a growing take
    // shows whatever frame is newest): the simulation domain and both
    // containers over the scene's trajectory when the scene is known, the
    // particles and poses of this frame otherwise.
    WorldBox b{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
    const bool known = !geo_.domain.empty() && (geo_.domain.hi[0] > geo_.domain.lo[0]);
    if (known) {
      grow(&b, geo_.domain.lo);
      grow(&b, geo_.domain.hi);
    } else if (!particle_box_.empty()) {
      b = particle_box_;
    }
    auto add_container = [&](const BuiltContainer& c, const Pose7& pose) {
      if (!c.present) return;
      for (int k = 0; k < 8; ++k)
        grow(&b, pose_apply(pose, (k & 1) ? c.hi[0] : c.lo[0], (k & 2) ? c.hi[1] : c.lo[1],
                            dim_ == 2 ? 0.0f : (k & 4) ? c.hi[2] : c.lo[2]));
    };
    for (const Pose7& pose : geo_.source_path) add_container(source_, pose);
    if (!known && has_source_pose_) add_container(source_, source_pose_);
    add_container(target_, known || !has_target_pose_ ? geo_.target_pose : target_pose_);
    if (b.empty()) b = {{0, 0, 0}, {0, 0, 0}};
    if (dim_ == 2) b.lo[2] = b.hi[2] = 0;
    return b;
  }

  int dim() const override { return dim_; }

  void draw(const DrawContext& ctx) override {
    g_last_view = {true, dim_, ctx.world_to_clip, ctx.width, ctx.height};
    if (count_ > 0) {
      glBindVertexArray(vao_.get());
      glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
      if (points_dirty_) {
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(staging_.size() * sizeof(float)), staging_.data(), GL_DYNAMIC_DRAW);
        points_dirty_ = false;
      }
      points_.use();
      points_.set("u_mvp", ctx.world_to_clip);
      // A sprite a little wider than the particle spacing closes the gaps.
      const float size = std::clamp(1.6f * geo_.particle_spacing_m * ctx.pixels_per_metre, 2.0f, 48.0f);
      points_.set("u_size_px", size);
      points_.set("u_speed_max", kSpeedWhite);
      glEnable(GL_PROGRAM_POINT_SIZE);
      glDrawArrays(GL_POINTS, 0, GLsizei(count_));
      glDisable(GL_PROGRAM_POINT_SIZE);
      glBindVertexArray(0);
      glBindBuffer(GL_ARRAY_BUFFER, 0);
    }
    if (dim_ == 2) {
      draw_lines(ctx);
      return;
    }
    if (meshes_dirty_) {
      meshes_.clear();
      add_mesh(source_, source_pose_, has_source_pose_, kSourceColor);
      add_mesh(target_, target_pose_, true, kTargetColor);
      meshes_dirty_ = false;
    }
    // See-through walls: blended over the particles, no depth writes.
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    meshes_.draw(ctx.world_to_clip, ctx.world_to_view);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    draw_path(ctx);
  }

  void shutdown() override {
    points_.reset();
    meshes_.shutdown();
    vao_.reset();
    vbo_.reset();
  }

 private:
  void resolve(const nlohmann::json* scene) {
    const size_t key = scene ? std::hash<std::string>{}(scene->dump()) : 0;
    if (key == scene_key_ && resolved_) return;
    scene_key_ = key;
    resolved_ = true;
    geo_ = LiquidSceneGeometry{};
    geo_.dim = dim_;
    std::string err;
    if (!scene || !g_resolver || !g_resolver(*scene, &geo_, &err)) {
      geo_ = LiquidSceneGeometry{};
      geo_.dim = dim_;
      if (scene) spacing_from_json(*scene);
    }
    source_ = geo_.has_source ? build(geo_.source, dim_) : BuiltContainer{};
    target_ = geo_.has_target ? build(geo_.target, dim_) : BuiltContainer{};
  }

  void spacing_from_json(const nlohmann::json& s) {
    const double h = s.contains("domain") ? s["domain"].value("cell_size_m", 0.02) : 0.02;
    const int ppa = s.contains("liquid") ? s["liquid"].value("particles_per_axis", 2) : 2;
    geo_.particle_spacing_m = float(h / std::max(ppa, 1));
  }

  void add_mesh(const BuiltContainer& c, const Pose7& pose, bool has_pose, const MeshDrawer::Color& col) {
    if (!c.present || !has_pose || c.mesh.triangle_count() == 0) return;
    meshes_.add_mesh(c.mesh.xyz.data(), c.mesh.vertex_count(), c.mesh.tris.data(), c.mesh.triangle_count(), col,
                     pose_matrix({pose[0], pose[1], pose[2]}, {pose[3], pose[4], pose[5], pose[6]}));
  }

  void draw_section(const DrawContext& ctx, const BuiltContainer& c, const Pose7& pose, const LineDrawer::Color& col) {
    for (const auto& s : c.section) ctx.lines->add(pose_apply(pose, s.ax, s.ay, 0), pose_apply(pose, s.bx, s.by, 0), col);
  }

  // The source's planned path (origin positions over the scene's key poses).
  void draw_path(const DrawContext& ctx) {
    for (size_t i = 1; i < geo_.source_path.size(); ++i) {
      const Pose7 &a = geo_.source_path[i - 1], &b = geo_.source_path[i];
      ctx.lines->add({a[0], a[1], a[2]}, {b[0], b[1], b[2]}, kPathLine);
    }
  }

  void draw_lines(const DrawContext& ctx) {
    if (!ctx.lines) return;
    if (has_source_pose_) draw_section(ctx, source_, source_pose_, kSourceLine);
    draw_section(ctx, target_, target_pose_, kTargetLine);
    draw_path(ctx);
  }

  int dim_ = 2;
  gl::Program points_;
  gl::VertexArray vao_;
  gl::Buffer vbo_;
  MeshDrawer meshes_;
  std::vector<float> staging_;
  size_t count_ = 0;
  bool points_dirty_ = false, meshes_dirty_ = true;
  WorldBox particle_box_;
  size_t scene_key_ = 0;
  bool resolved_ = false;
  LiquidSceneGeometry geo_;
  BuiltContainer source_, target_;
  Pose7 source_pose_{0, 0, 0, 1, 0, 0, 0}, target_pose_{0, 0, 0, 1, 0, 0, 0};
  bool has_source_pose_ = false, has_target_pose_ = false;
};

}  // namespace

void set_liquid_scene_resolver(LiquidSceneResolver resolver) { g_resolver = resolver; }
LiquidSceneResolver liquid_scene_resolver() { return g_resolver; }
const LiquidViewTransform& liquid_last_view() { return g_last_view; }

std::unique_ptr<FrameDrawer> make_liquid_drawer() { return std::make_unique<LiquidDrawer>(); }

}  // namespace pliant::editor
