// Scene -> LiquidModel. Every problem is an InputError naming file, JSON
// pointer and expectation (JsonReader); containers may be inline objects or
// paths to container files (assets/containers/*.json) relative to the scene.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"
#include "pliant/core/scene.h"
#include "pliant/geom/raster_grid.h"
#include "pliant/geom/triangle_mesh.h"
#include "container_mesh.h"
#include "pliant/liquid/feedback.h"
#include "pliant/liquid/liquid.h"
#include "pliant/liquid/problem_generator.h"

namespace pliant::liquid {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

Vec3 read_vec(JsonReader& r, std::string_view key, const Vec3& def, int dim) {
  std::vector<double> d(def.begin(), def.begin() + dim);
  const auto v = r.numbers(key, d, size_t(dim), size_t(dim == 2 ? 3 : 3));
  Vec3 out{0, 0, 0};
  for (size_t i = 0; i < v.size() && i < 3; ++i) out[i] = v[i];
  if (dim == 2) out[2] = 0;
  return out;
}

Vec3 required_vec(JsonReader& r, std::string_view key, int dim) {
  if (!r.has(key)) r.fail(key, "missing required field; expected an array of " + std::to_string(dim) + " numbers");
  return read_vec(r, key, {0, 0, 0}, dim);
}

// {"shape": "mesh", "file": "mug.obj", "scale": 1}: a closed triangle mesh
// (assimp formats), file relative to `base` (the container file's folder, or
// the scene's for an inline container), sampled at half the cell size.
ContainerShape read_mesh_shape(JsonReader& r, const std::filesystem::path& base, double cell) {
  const std::string rel = r.string("file", "");
  if (rel.empty()) r.fail("file", "missing required field; expected the path of a closed triangle mesh");
  const double scale = r.number("scale", 1.0, 1e-6, 1e6);
  r.accept("comment");
  r.accept("origin");
  r.finish();
  const std::filesystem::path path = std::filesystem::path(rel).is_absolute() ? std::filesystem::path(rel) : base / rel;
  try {
    ContainerShape c = mesh_container(geom::load_mesh(path, path.string()), scale, 0.5 * cell);
    c.mesh_file = path.string();
    return c;
  } catch (const geom::GeomError& e) {
    r.fail("file", e.what());
  } catch (const MeshContainerError& e) {
    r.fail("file", path.string() + ": " + e.what());
  }
}

ContainerShape read_shape(JsonReader& r, const std::filesystem::path& base, double cell) {
  ContainerShape c;
  const std::string type = r.choice("shape", "cylinder", {"cylinder", "oval", "box", "cup", "bottle", "mesh"});
  if (type == "mesh") return read_mesh_shape(r, base, cell);
  c.type = type == "oval"     ? ContainerShape::Oval
           : type == "box"    ? ContainerShape::Box
           : type == "cup"    ? ContainerShape::Cup
           : type == "bottle" ? ContainerShape::Bottle
                              : ContainerShape::Cylinder;
  c.radius_m = r.number("radius_m", c.radius_m, 1e-3, 10);
  c.depth_m = r.number("depth_m", c.radius_m, 1e-3, 10);
  c.height_m = r.number("height_m", c.height_m, 1e-3, 10);
  c.wall_m = r.number("wall_m", c.wall_m, 1e-4, 1);
  c.neck_radius_m = r.number("neck_radius_m", std::min(c.neck_radius_m, c.radius_m), 1e-3, 10);
  c.body_height_m = r.number("body_height_m", 0.6 * c.height_m, 1e-3, 10);
  if (c.type == ContainerShape::Bottle) {
    if (c.neck_radius_m > c.radius_m) r.fail("neck_radius_m", "must not exceed radius_m");
    if (c.body_height_m >= c.height_m) r.fail("body_height_m", "must be below height_m");
  }
  r.accept("comment");
  r.accept("origin");
  r.finish();
  return c;
}

// Walls thinner than a cell let the grid leak (no cell centre inside the wall).
void check_wall(const ContainerShape& c, double cell, JsonReader& parent) {
  if (c.type == ContainerShape::Mesh && c.wall_m < cell)
    parent.fail("container", "the mesh's wall at the rim (" + std::to_string(c.wall_m) +
                                 " m) is thinner than /domain/cell_size_m " + std::to_string(cell) +
                                 "; walls need at least one cell (scale the mesh up or refine the grid)");
  if (c.wall_m < cell)
    parent.fail("container", "wall_m " + std::to_string(c.wall_m) + " is thinner than /domain/cell_size_m " +
                                 std::to_string(cell) + "; walls need at least one cell");
}

// "container": an object, or a path to a JSON file holding one.
ContainerShape read_container(JsonReader& parent, const Scene& scene, double cell) {
  if (!parent.has("container")) parent.fail("container", "missing required field; expected a container object or file");
  const nlohmann::json& v = parent.value().at("container");
  parent.accept("container");
  if (v.is_string()) {
    const std::string rel = v.get<std::string>();
    const auto path = scene.asset_path(rel);
    std::ifstream in(path);
    if (!in) parent.fail("container", "cannot read container file \"" + path.string() + "\"");
    std::stringstream ss;
    ss << in.rdbuf();
    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(ss.str(), nullptr, true, true);
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError(path.string(), "", std::string("invalid JSON: ") + e.what());
    }
    JsonReader r(doc, path.string());
    return read_shape(r, path.parent_path(), cell);
  }
  if (!v.is_object()) parent.fail("container", "expected a container object or a file path");
  JsonReader r(v, parent.file(), parent.child_pointer("container"));
  return read_shape(r, scene.asset_path("."), cell);
}

Pose read_pose(JsonReader& r, int dim, bool position_required) {
  Pose p;
  p.position_m = position_required ? required_vec(r, "position_m", dim) : read_vec(r, "position_m", {0, 0, 0}, dim);
  p.tilt_rad = r.number("tilt_deg", 0, -360, 360) * kDeg;
  return p;
}

void read_planner(JsonReader& root, LiquidModel& m, const Scene& scene) {
  if (auto p = root.object("planner")) {
    const std::string mode = p->choice("mode", "none", {"none", "correction", "simplified", "feedback"});
    m.planner.planner = mode == "correction"   ? Planner::Correction
                        : mode == "simplified" ? Planner::Simplified
                        : mode == "feedback"   ? Planner::Feedback
                                               : Planner::None;
    m.planner.iterations = int(p->integer("iterations", m.planner.iterations, 1, 1000));
    m.planner.population = int(p->integer("population", m.planner.population, 4, 1000));
    m.planner.generations = int(p->integer("generations", m.planner.generations, 1, 100000));
    m.planner.keys = int(p->integer("keys", m.planner.keys, 1, 20));
    m.planner.fit_discharge = p->boolean("fit_discharge", m.planner.fit_discharge);
    m.planner.refine_iterations = int(p->integer("refine_iterations", m.planner.refine_iterations, 0, 100));
    m.planner.discharge_coefficient = p->number("discharge_coefficient", m.planner.discharge_coefficient, 0.01, 10);
    m.planner.pour_time_s = p->number("pour_time_s", m.planner.pour_time_s, 0.1, 100);
    m.planner.max_tilt_rad = p->number("max_tilt_deg", m.planner.max_tilt_rad / kDeg, 10, 180) * kDeg;
    m.planner.seed = uint64_t(p->integer("seed", 1, 0));
    const std::string net = p->string("network", "");
    m.planner.network = net.empty() ? default_feedback_network().string() : scene.asset_path(net).string();
    if (m.planner.planner == Planner::Feedback && !std::filesystem::exists(m.planner.network))
      p->fail("network", "cannot read the feedback network \"" + m.planner.network +
                             "\" (train one: liquid_train OUT/liquid_dataset NET.json)");
    m.planner.interval_s = p->number("interval_s", m.planner.interval_s, 1e-3, 10);
    m.planner.horizon = int(p->integer("horizon", m.planner.horizon, 1, 50));
    m.planner.record_samples = p->boolean("record_samples", m.planner.record_samples);
    m.planner.sample_rollouts = int(p->integer("sample_rollouts", m.planner.sample_rollouts, 0, 100));
    p->finish();
    if ((m.planner.planner != Planner::None || m.planner.record_samples) && (!m.has_source || !m.has_target))
      p->fail("mode", "a planner needs both /source and /target");
    // The network's features one-hot the five analytic shapes it was trained on.
    if ((m.planner.planner == Planner::Feedback || m.planner.record_samples) && m.has_source &&
        m.source.shape.type == ContainerShape::Mesh)
      p->fail("mode", "the feedback network knows the analytic source shapes only (cylinder, oval, box, cup, "
                      "bottle); plan a mesh source with \"correction\" or \"simplified\"");
  }
}

}  // namespace

LiquidModel liquid_compile(const Scene& scene) {
  LiquidModel m;
  JsonReader root(scene.doc, scene.file);
  accept_scene_envelope(root);
  root.accept("comment");
  m.dim = int(root.integer("dim", 3, 2, 3));
  if (auto pr = root.object("problem")) {
    // A problem of the fixed-seed generator (dataset sweeps, benchmarks): it
    // sets everything but the planner.
    for (const char* key : {"domain", "time", "pressure", "gravity_m_per_s2", "liquid", "source", "target"})
      if (root.has(key)) root.fail(key, "not allowed together with /problem (the generator sets it)");
    const uint64_t seed = uint64_t(pr->integer("seed", 2026, 0));
    const int id = int(pr->required_integer("id", 0, 1000000000));
    const std::string split = pr->choice("split", "train", {"train", "held_out", "any"});
    if (split == "train" && id % 5 == 0)
      pr->fail("id", "problem " + std::to_string(id) + " is held out (id % 5 == 0); training uses the others");
    if (split == "held_out" && id % 5 != 0)
      pr->fail("id", "problem " + std::to_string(id) + " is a training problem; held-out ids are multiples of 5");
    pr->finish();
    m = generate_problem(id, seed, m.dim).model;
    read_planner(root, m, scene);
    root.finish();
    return m;
  }
  auto domain = root.object("domain");
  if (!domain) root.fail("domain", "missing required field; expected {\"min_m\", \"max_m\", \"cell_size_m\"}");
  m.domain_min_m = required_vec(*domain, "min_m", m.dim);
  m.domain_max_m = required_vec(*domain, "max_m", m.dim);
  m.cell_size_m = domain->required_number("cell_size_m", 1e-4, 1);
  for (int a = 0; a < m.dim; ++a) {
    const double len = m.domain_max_m[a] - m.domain_min_m[a];
    if (len <= 2 * m.cell_size_m) domain->fail("max_m", "must exceed min_m by at least two cells on every axis");
    m.n[a] = int(std::ceil(len / m.cell_size_m - 1e-9));
  }
  if (m.dim == 2) m.n[2] = 1;
  const double cells = double(m.n[0]) * m.n[1] * m.n[2];
  if (cells > 4e7) domain->fail("cell_size_m", "grid of " + std::to_string(long(cells)) + " cells is too large (limit 4e7)");
  domain->finish();

  if (auto t = root.object("time")) {
    m.dt_s = t->number("dt_s", m.dt_s, 1e-5, 1);
    m.frames = int(t->integer("frames", m.frames, 1, 100000));
    m.cfl = t->number("cfl", m.cfl, 0.05, 10);
    m.max_substeps = int(t->integer("max_substeps", m.max_substeps, 1, 10000));
    t->finish();
  }
  if (auto p = root.object("pressure")) {
    m.pressure_tolerance = p->number("tolerance", m.pressure_tolerance, 1e-12, 1);
    m.pressure_max_iterations = int(p->integer("max_iterations", m.pressure_max_iterations, 1, 100000));
    p->finish();
  }
  m.gravity_m_per_s2 = read_vec(root, "gravity_m_per_s2", {0, -9.81, 0}, m.dim);
  if (auto l = root.object("liquid")) {
    m.viscosity_pa_s = l->number("viscosity_pa_s", m.viscosity_pa_s, 0, 1e4);
    m.density_kg_per_m3 = l->number("density_kg_per_m3", m.density_kg_per_m3, 1, 1e5);
    m.flip_ratio = l->number("flip_ratio", m.flip_ratio, 0, 1);
    m.fill_fraction = l->number("fill_fraction", m.fill_fraction, 0, 1);
    m.particles_per_axis = int(l->integer("particles_per_axis", m.particles_per_axis, 1, 4));
    m.reseed = l->boolean("reseed", m.reseed);
    m.seed = uint64_t(l->integer("seed", 1, 0));
    for (JsonReader& b : l->objects("boxes")) {
      const Vec3 lo = required_vec(b, "min_m", m.dim), hi = required_vec(b, "max_m", m.dim);
      for (int a = 0; a < m.dim; ++a)
        if (hi[a] <= lo[a]) b.fail("max_m", "must exceed min_m on every axis");
      b.finish();
      m.liquid_boxes.push_back({lo, hi});
    }
    l->finish();
  }
  if (auto s = root.object("source")) {
    m.source.shape = read_container(*s, scene, m.cell_size_m);
    m.source.pose = read_pose(*s, m.dim, true);
    check_wall(m.source.shape, m.cell_size_m, *s);
    const auto keys = s->objects("trajectory");
    double last = -1;
    for (JsonReader k : keys) {
      KeyPose kp;
      kp.time_s = k.required_number("time_s", 0, 1e6);
      if (kp.time_s <= last) k.fail("time_s", "key times must increase");
      last = kp.time_s;
      kp.pose = read_pose(k, m.dim, true);
      k.finish();
      m.source_path.keys.push_back(kp);
    }
    s->finish();
  } else {
    m.has_source = false;
  }
  if (auto t = root.object("target")) {
    m.target.shape = read_container(*t, scene, m.cell_size_m);
    m.target.pose = read_pose(*t, m.dim, true);
    m.target_velocity_mps = read_vec(*t, "velocity_mps", {0, 0, 0}, m.dim);
    for (int a = 0; a < m.dim; ++a)
      if (std::abs(m.target_velocity_mps[a]) > 100) t->fail("velocity_mps", "speeds above 100 m/s are not supported");
    check_wall(m.target.shape, m.cell_size_m, *t);
    t->finish();
  } else {
    m.has_target = false;
  }
  if (!m.has_source && m.liquid_boxes.empty())
    root.fail("source", "missing: a liquid scene needs a source container or /liquid/boxes");
  read_planner(root, m, scene);
  root.finish();
  return m;
}

int liquid_job_frames(const Scene& scene) { return liquid_compile(scene).frames; }

nlohmann::json liquid_summary(const Scene& scene) {
  const LiquidModel m = liquid_compile(scene);
  nlohmann::json res = nlohmann::json::array();
  for (int a = 0; a < m.dim; ++a) res.push_back(m.n[a]);
  const LiquidState s = liquid_init(m);
  return {{"frames", m.frames}, {"dim", m.dim}, {"resolution", res}, {"particles", s.count()}};
}

}  // namespace pliant::liquid
