// One frame of the forward simulation: `substeps` sub-steps of
//   sources -> forces -> advect velocity -> project -> advect density
// (the order of Pan & Manocha's u_{i+1} = P(A(u_i, u_i) + dt f_i),
//  rho_{i+1} = A(rho_i, u_{i+1}); ALGORITHMS.md section 2).
#include <algorithm>
#include <memory>

#include <omp.h>

#include "advection.h"
#include "forces.h"
#include "pliant/smoke/smoke.h"
#include "smoke_workspace.h"

namespace pliant::smoke {

MacGrid model_grid(const SmokeModel& m) {
  MacGrid g;
  g.dim = m.dim;
  g.n = m.n;
  if (m.dim == 2) g.n[2] = 1;
  g.h = m.cell_size_m;
  g.periodic = m.boundary == Boundary::Periodic;
  return g;
}

SmokeWorkspace::SmokeWorkspace(const MacGrid& g) : grid(g), poisson(g) {
  u0.resize(g.face_count(0));
  v0.resize(g.face_count(1));
  w0.resize(g.face_count(2));
  density_tmp.resize(g.cells());
  size_t faces = 0;
  for (int a = 0; a < 3; ++a) faces = std::max(faces, g.face_count(a));
  face_tmp.resize(faces);
  phi.assign(g.cells(), 0.0);
  rhs.assign(g.cells(), 0.0);
}

bool SmokeWorkspace::fits(const MacGrid& g) const {
  return g.dim == grid.dim && g.n == grid.n && g.periodic == grid.periodic;
}

SmokeWorkspace& smoke_workspace(const MacGrid& g) {
  thread_local std::unique_ptr<SmokeWorkspace> ws;
  if (!ws || !ws->fits(g)) ws = std::make_unique<SmokeWorkspace>(g);
  ws->grid = g;  // h may differ; buffers do not depend on it
  return *ws;
}

SmokeState smoke_init(const SmokeModel& m) {
  const MacGrid g = model_grid(m);
  SmokeState s;
  s.density.assign(g.cells(), 0.0f);
  s.u.assign(g.face_count(0), 0.0f);
  s.v.assign(g.face_count(1), 0.0f);
  s.w.assign(g.face_count(2), 0.0f);
  s.pressure.assign(g.cells(), 0.0f);
  for (const Shape& sh : m.initial_density) fill_shape(g, sh, s.density.data());
  return s;
}

void smoke_step(const SmokeModel& m, SmokeState& s, StepStats* stats) {
  const MacGrid g = model_grid(m);
  SmokeWorkspace& ws = smoke_workspace(g);
  const double dt = m.dt_s / m.substeps;
  const PoissonMethod method =
      m.pressure_solver == PressureSolver::MultigridPCG ? PoissonMethod::MultigridPCG : PoissonMethod::JacobiPCG;
  FaceVelocityMut vel{s.u.data(), s.v.data(), g.dim == 3 ? s.w.data() : nullptr};
  FaceVelocityMut frozen{ws.u0.data(), ws.v0.data(), g.dim == 3 ? ws.w0.data() : nullptr};
  std::copy(s.pressure.begin(), s.pressure.end(), ws.phi.begin());  // warm start

  StepStats st;
  double max_div = 0;
  StepTimings& tm = ws.timings;
  for (int sub = 0; sub < m.substeps; ++sub) {
    double t0 = omp_get_wtime();
    // Sources are active on [start_s, end_s).
    for (const Source& src : m.sources)
      if (s.time_s >= src.start_s && s.time_s < src.end_s) apply_source(g, src, dt, s.density.data(), vel);
    add_buoyancy(g, m.buoyancy_m_per_s2, s.density.data(), dt, vel);
    add_uniform_acceleration(g, m.gravity_m_per_s2, dt, vel);
    for (const ForceField& f : m.forces) {
      if (f.type == ForceField::Uniform) add_uniform_acceleration(g, f.acceleration_m_per_s2, dt, vel);
      else add_vortex(g, f, dt, vel);
    }

    double t1 = omp_get_wtime();
    tm.forces_s += t1 - t0;
    // Advect velocity by itself (frozen copy as the advecting field).
    std::copy(s.u.begin(), s.u.end(), ws.u0.begin());
    std::copy(s.v.begin(), s.v.end(), ws.v0.begin());
    std::copy(s.w.begin(), s.w.end(), ws.w0.begin());
    if (m.advection == Advection::Upwind) advect_upwind_velocity(g, frozen, dt, vel, ws.face_tmp.data());
    else advect_semi_lagrangian_velocity(g, frozen, dt, vel);

    t0 = omp_get_wtime();
    tm.advect_velocity_s += t0 - t1;
    const ProjectionStats ps = project(g, ws.poisson, method, m.pressure_tolerance, m.pressure_max_iterations,
                                       vel, ws.phi.data(), ws.rhs.data());
    st.pressure_iterations += ps.iterations;
    st.pressure_residual = std::max(st.pressure_residual, ps.relative_residual);
    max_div = std::max(max_div, ps.max_divergence_after);

    t1 = omp_get_wtime();
    tm.project_s += t1 - t0;
    if (m.advection == Advection::Upwind) {
      advect_upwind_cells(g, vel, dt, s.density.data(), ws.density_tmp.data());
    } else {
      advect_semi_lagrangian_cells(g, vel, dt, s.density.data(), ws.density_tmp.data());
      s.density.swap(ws.density_tmp);  // swap keeps both buffers; no allocation
    }
    tm.advect_density_s += omp_get_wtime() - t1;
    tm.substeps += 1;
    s.time_s += dt;
  }
  std::transform(ws.phi.begin(), ws.phi.end(), s.pressure.begin(), [](double p) { return float(p); });
  s.frame += 1;
  s.time_s = s.frame * m.dt_s;  // no drift from summing sub-steps

  if (stats) {
    double total = 0;
    const size_t n = s.density.size();
    const float* d = s.density.data();
#pragma omp parallel for schedule(static) reduction(+ : total)
    for (size_t c = 0; c < n; ++c) total += d[c];
    st.max_divergence = max_div;
    st.total_density = total;
    *stats = st;
  }
}

}  // namespace pliant::smoke
