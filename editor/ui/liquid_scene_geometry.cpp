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

bool liquid_scene_geometry(const nlohmann::json& scene, LiquidSceneGeometry* out, std::string* err) {
  (void)kRegistered;
#ifdef PLIANT_HAVE_LIQUID
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
      const liquid::LiquidModel m = liquid::liquid_compile(s);
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
    } catch (const std::exception& e) {
      if (first_error.empty()) first_error = e.what();
    }
  }
  if (err) *err = first_error;
  return false;
#else
  (void)scene;
  (void)out;
  if (err) *err = "the liquid module is not built";
  return false;
#endif
}

}  // namespace pliant::editor
