#include "ui/liquid_scene_geometry.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#ifdef PLIANT_HAVE_LIQUID
#include "pliant/liquid/liquid.h"
#endif

namespace pliant::editor {

namespace fs = std::filesystem;

namespace {

std::mutex g_dirs_mutex;
std::vector<fs::path> g_dirs;

#ifdef PLIANT_HAVE_LIQUID
// A container without a closed-form box (a mesh: radius/depth are the
// opening's half widths, the body and a handle may reach further): the box of
// the wall material found on a coarse grid over a generous region, padded.
void probe_box(const liquid::ContainerShape& c, int dim, LiquidContainerGeometry* g) {
  const double r = std::max({c.radius_m, c.depth_m, 1e-3}) + c.wall_m;
  const double side = 2.0 * r + 0.6 * c.height_m;
  const double lo[3] = {-side, -(0.6 * c.height_m + c.wall_m), dim == 3 ? -side : 0.0};
  const double hi[3] = {side, c.height_m + c.wall_m + 0.2 * r, dim == 3 ? side : 0.0};
  const int n = 40;
  double step[3];
  for (int a = 0; a < 3; ++a) step[a] = (hi[a] - lo[a]) / n;
  double blo[3] = {1e30, 1e30, 1e30}, bhi[3] = {-1e30, -1e30, -1e30};
  const double near = std::max({step[0], step[1], dim == 3 ? step[2] : 0.0});
  for (int k = 0; k <= (dim == 3 ? n : 0); ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const double p[3] = {lo[0] + i * step[0], lo[1] + j * step[1], lo[2] + k * step[2]};
        if (c.wall_sdf({p[0], p[1], p[2]}, dim) > near) continue;
        for (int a = 0; a < 3; ++a) {
          blo[a] = std::min(blo[a], p[a]);
          bhi[a] = std::max(bhi[a], p[a]);
        }
      }
  if (!(bhi[0] >= blo[0])) return;  // nothing found: keep the opening's box
  for (int a = 0; a < dim; ++a) {
    g->lo[size_t(a)] = float(blo[a] - near - 2.0 * g->step);
    g->hi[size_t(a)] = float(bhi[a] + near + 2.0 * g->step);
  }
}

// Local box of the wall: shell around the cavity, plus the cup's handle on +x.
LiquidContainerGeometry container_geometry(const liquid::ContainerShape& c, int dim) {
  LiquidContainerGeometry g;
  const int d = dim;
  g.wall_sdf = [c, d](double x, double y, double z) { return c.wall_sdf({x, y, z}, d); };
  g.step = float(std::clamp(c.wall_m / (dim == 2 ? 4.0 : 2.5), 0.001, 0.02));
  const double handle = c.type == liquid::ContainerShape::Cup ? 0.45 * c.height_m + c.wall_m + 0.005 : 0.0;
  const double r = std::max(c.radius_m, c.type == liquid::ContainerShape::Cylinder ? c.radius_m : c.depth_m);
  const double pad = 2.0 * g.step;
  g.lo = {float(-(c.radius_m + c.wall_m + pad)), float(-(c.wall_m + pad)), float(dim == 3 ? -(r + c.wall_m + pad) : 0)};
  g.hi = {float(c.radius_m + c.wall_m + handle + pad), float(c.height_m + pad), float(dim == 3 ? r + c.wall_m + pad : 0)};
  const bool analytic = c.type == liquid::ContainerShape::Cylinder || c.type == liquid::ContainerShape::Oval ||
                        c.type == liquid::ContainerShape::Box || c.type == liquid::ContainerShape::Cup ||
                        c.type == liquid::ContainerShape::Bottle;
  if (!analytic) probe_box(c, dim, &g);
  // Keep the 3D sampling grid under ~300k points on big containers.
  if (dim == 3) {
    const double cells = double(g.hi[0] - g.lo[0]) * (g.hi[1] - g.lo[1]) * (g.hi[2] - g.lo[2]) / std::pow(g.step, 3);
    if (cells > 3e5) g.step = float(g.step * std::cbrt(cells / 3e5));
  }
  return g;
}

Pose7 pose7(const liquid::Pose& p) { return p.as_array(); }
#endif

bool resolve_for_drawer(const nlohmann::json& scene, LiquidSceneGeometry* out, std::string* err) {
  return liquid_scene_geometry(scene, out, err);
}

// The drawer asks through this hook; this file is linked whenever the liquid
// panels are (kind_panels.cpp refers to them), so the registration runs.
const bool kRegistered = (set_liquid_scene_resolver(&resolve_for_drawer), true);

}  // namespace

void liquid_set_scene_dirs(std::vector<fs::path> dirs) {
  std::lock_guard<std::mutex> lock(g_dirs_mutex);
  g_dirs = std::move(dirs);
}

#ifdef PLIANT_HAVE_LIQUID
namespace {
// Compiles `scene` against each scene folder in turn (relative container
// paths); the first that compiles wins, else the first error.
bool compile_scene(const nlohmann::json& scene, liquid::LiquidModel* out, std::string* err) {
  std::vector<fs::path> dirs;
  {
    std::lock_guard<std::mutex> lock(g_dirs_mutex);
    dirs = g_dirs;
  }
#ifdef PLIANT_SOURCE_DIR
  dirs.push_back(fs::path(PLIANT_SOURCE_DIR) / "assets" / "scenes");
#endif
  if (dirs.empty()) dirs.push_back(".");
  std::string first_error;
  for (const fs::path& dir : dirs) {
    Scene s;
    s.file = "take scene";
    s.dir = dir;
    s.kind = "liquid";
    s.doc = scene;
    try {
      *out = liquid::liquid_compile(s);
      return true;
    } catch (const std::exception& e) {
      if (first_error.empty()) first_error = e.what();
    }
  }
  if (err) *err = first_error;
  return false;
}
}  // namespace
#endif

bool liquid_scene_geometry(const nlohmann::json& scene, LiquidSceneGeometry* out, std::string* err) {
  (void)kRegistered;
#ifdef PLIANT_HAVE_LIQUID
  liquid::LiquidModel m;
  if (!compile_scene(scene, &m, err)) return false;
  *out = LiquidSceneGeometry{};
  out->dim = m.dim;
  out->has_source = m.has_source;
  out->has_target = m.has_target;
  if (m.has_source) out->source = container_geometry(m.source.shape, m.dim);
  if (m.has_target) out->target = container_geometry(m.target.shape, m.dim);
  out->target_pose = pose7(m.target.pose);
  if (m.has_source)
    for (int f = 0; f <= m.frames; ++f) out->source_path.push_back(pose7(liquid::source_pose_at(m, f * m.dt_s)));
  out->particle_spacing_m = float(m.cell_size_m / std::max(m.particles_per_axis, 1));
  for (int i = 0; i < 3; ++i) {
    out->domain.lo[i] = float(m.domain_min_m[i]);
    out->domain.hi[i] = float(m.domain_max_m[i]);
  }
  return true;
#else
  (void)scene;
  (void)out;
  if (err) *err = "the liquid module is not built";
  return false;
#endif
}

bool liquid_initial_frame(const nlohmann::json& scene, Record* out, std::string* err) {
#ifdef PLIANT_HAVE_LIQUID
  liquid::LiquidModel m;
  if (!compile_scene(scene, &m, err)) return false;
  try {
    const liquid::LiquidState s = liquid::liquid_init(m);
    *out = liquid::liquid_frame_record(m, s);
    return true;
  } catch (const std::exception& e) {
    if (err) *err = e.what();
    return false;
  }
#else
  (void)scene;
  (void)out;
  if (err) *err = "the liquid module is not built";
  return false;
#endif
}

}  // namespace pliant::editor
