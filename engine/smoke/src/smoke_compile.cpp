// Scene -> SmokeModel. Every default comes from the SmokeModel/Source/ForceField/
// Shape initialisers in smoke.h; this file only reads what the scene overrides.
#include <string>

#include "pliant/core/json_reader.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/control.h"
#include "pliant/smoke/smoke.h"

namespace pliant::smoke {
namespace {

constexpr int kMinCells = 2, kMaxCells = 1024;

// A vector field with exactly `dim` components (2D vectors in a 2D scene).
std::array<double, 3> read_vec(JsonReader& r, std::string_view key, const std::array<double, 3>& def,
                               int dim, double min = -1e300, double max = 1e300) {
  std::vector<double> d(def.begin(), def.begin() + dim);
  const std::vector<double> v = r.numbers(key, d, dim, dim, min, max);
  std::array<double, 3> out{0, 0, 0};
  for (int a = 0; a < dim; ++a) out[a] = v[a];
  return out;
}

// Shape fields of a source / initial-density entry (the caller finishes the reader).
Shape read_shape(JsonReader& r, int dim) {
  Shape s;
  const std::string type = r.choice("shape", s.type == Shape::Sphere ? "sphere" : "box", {"sphere", "box"});
  s.type = type == "sphere" ? Shape::Sphere : Shape::Box;
  s.center_m = read_vec(r, "center_m", s.center_m, dim);
  if (s.type == Shape::Sphere) {
    if (!r.has("radius_m")) r.fail("radius_m", "missing required field for a sphere; expected a number > 0");
    s.radius_m = r.number("radius_m", s.radius_m, 0.0);
    if (s.radius_m <= 0) r.fail("radius_m", "expected a number > 0");
  } else {
    if (!r.has("half_size_m")) r.fail("half_size_m", "missing required field for a box; expected " + std::to_string(dim) + " numbers > 0");
    s.half_size_m = read_vec(r, "half_size_m", s.half_size_m, dim, 0.0);
  }
  return s;
}

double positive(JsonReader& r, std::string_view key, double def) {
  const double x = r.number(key, def);
  if (!(x > 0)) r.fail(key, "expected a number > 0, got " + std::to_string(x));
  return x;
}

}  // namespace

SmokeModel smoke_compile(const Scene& scene) {
  SmokeModel m;
  JsonReader root(scene.doc, scene.file);
  accept_scene_envelope(root);

  auto grid = root.object("grid");
  if (!grid) root.fail("grid", "missing required field; expected an object with \"resolution\"");
  if (!grid->has("resolution"))
    grid->fail("resolution", "missing required field; expected [nx, ny] or [nx, ny, nz]");
  const auto res = grid->integers("resolution", {}, 2, 3, kMinCells, kMaxCells);
  m.dim = int(res.size());
  m.n = {int(res[0]), int(res[1]), m.dim == 3 ? int(res[2]) : 1};
  m.cell_size_m = positive(*grid, "cell_size_m", m.cell_size_m);
  const std::string boundary =
      grid->choice("boundary", m.boundary == Boundary::Closed ? "closed" : "periodic", {"closed", "periodic"});
  m.boundary = boundary == "closed" ? Boundary::Closed : Boundary::Periodic;
  grid->finish();

  if (auto time = root.object("time")) {
    m.dt_s = positive(*time, "dt_s", m.dt_s);
    m.frames = int(time->integer("frames", m.frames, 1, 1000000));
    m.substeps = int(time->integer("substeps", m.substeps, 1, 10000));
    time->finish();
  }

  const std::string adv = root.choice(
      "advection", m.advection == Advection::SemiLagrangian ? "semi_lagrangian" : "upwind",
      {"semi_lagrangian", "upwind"});
  m.advection = adv == "upwind" ? Advection::Upwind : Advection::SemiLagrangian;
  m.buoyancy_m_per_s2 = root.number("buoyancy_m_per_s2", m.buoyancy_m_per_s2);
  m.gravity_m_per_s2 = read_vec(root, "gravity_m_per_s2", m.gravity_m_per_s2, m.dim);

  if (auto p = root.object("pressure")) {
    const std::string solver = p->choice(
        "solver", m.pressure_solver == PressureSolver::MultigridPCG ? "mgpcg" : "jacobi_pcg",
        {"mgpcg", "jacobi_pcg"});
    m.pressure_solver = solver == "mgpcg" ? PressureSolver::MultigridPCG : PressureSolver::JacobiPCG;
    m.pressure_tolerance = p->number("tolerance", m.pressure_tolerance);
    if (!(m.pressure_tolerance > 0 && m.pressure_tolerance < 1))
      p->fail("tolerance", "expected a number in (0, 1), got " + std::to_string(m.pressure_tolerance));
    m.pressure_max_iterations = int(p->integer("max_iterations", m.pressure_max_iterations, 1, 1000000));
    p->finish();
  }

  for (JsonReader& s : root.objects("sources")) {
    Source src;
    src.shape = read_shape(s, m.dim);
    src.density_per_s = s.number("density_per_s", src.density_per_s);
    src.velocity_m_per_s = read_vec(s, "velocity_m_per_s", src.velocity_m_per_s, m.dim);
    src.start_s = s.number("start_s", src.start_s);
    src.end_s = s.number("end_s", src.end_s);
    if (src.end_s < src.start_s) s.fail("end_s", "expected end_s >= start_s");
    s.finish();
    m.sources.push_back(src);
  }

  for (JsonReader& f : root.objects("forces")) {
    ForceField ff;
    const std::string type = f.choice("type", "uniform", {"uniform", "vortex"});
    ff.type = type == "uniform" ? ForceField::Uniform : ForceField::Vortex;
    if (ff.type == ForceField::Uniform) {
      ff.acceleration_m_per_s2 = read_vec(f, "acceleration_m_per_s2", ff.acceleration_m_per_s2, m.dim);
    } else {
      ff.center_m = read_vec(f, "center_m", ff.center_m, m.dim);
      ff.radius_m = positive(f, "radius_m", ff.radius_m > 0 ? ff.radius_m : 0.0);
      ff.strength_per_s = f.number("strength_per_s", ff.strength_per_s);
    }
    f.finish();
    m.forces.push_back(ff);
  }

  for (JsonReader& s : root.objects("initial_density")) {
    m.initial_density.push_back(read_shape(s, m.dim));
    s.finish();
  }

  if (auto out = root.object("output")) {
    m.write_velocity = out->boolean("velocity", m.write_velocity);
    m.write_every = int(out->integer("every", m.write_every, 1, 1000000));
    out->finish();
  }
  // Keyframe control (control.h): its section is checked by control_compile (which
  // compiles the smoke part from a copy without it), so `pliant validate` sees it.
  if (root.has("control")) {
    root.accept("control");
    (void)control_compile(scene);
  }
  root.finish();
  return m;
}

// Frame records the job writes: the initial state, then one per `output.every`.
int smoke_job_frames(const Scene& scene) {
  const SmokeModel m = smoke_compile(scene);
  return 1 + m.frames / m.write_every;
}

}  // namespace pliant::smoke
