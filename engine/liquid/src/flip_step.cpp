// One FLIP substep (Algorithm 1 of the seed): particle-to-grid, forces,
// implicit viscosity, pressure projection with the moving container's wall
// velocity, grid-to-particle (FLIP/PIC blend), RK2 advection, push-out of
// solids (the walls: flip_solids.cpp). And the frame loop with CFL substeps and
// reseeding.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

#include "container_mesh.h"
#include "flip_grid.h"

namespace pliant::liquid {
namespace {

// Scratch per thread, rebuilt when the grid or the static target changes (a
// planner may simulate many models in turn, or several at once on threads).
FlipWorkspace& workspace(const LiquidModel& m) {
  thread_local std::unique_ptr<FlipWorkspace> w;
  thread_local std::vector<double> key;
  const auto& t = m.target;
  std::vector<double> k = {double(m.dim), double(m.n[0]), double(m.n[1]), double(m.n[2]), m.cell_size_m,
                           m.domain_min_m[0], m.domain_min_m[1], m.domain_min_m[2], double(m.has_target),
                           t.pose.position_m[0], t.pose.position_m[1], t.pose.position_m[2], t.pose.tilt_rad,
                           double(t.shape.type), t.shape.radius_m, t.shape.depth_m, t.shape.height_m,
                           t.shape.wall_m, t.shape.neck_radius_m, t.shape.body_height_m,
                           m.target_velocity_mps[0], m.target_velocity_mps[1], m.target_velocity_mps[2],
                           double(m.has_source), double(reinterpret_cast<uintptr_t>(t.shape.mesh.get()))};
  if (!w || k != key) {
    w = std::make_unique<FlipWorkspace>();
    key = std::move(k);
  }
  return *w;
}

// Counting sort of particles by cell; fills cell_start (size cells+1), order, particle_cell.
void sort_particles(const FlipGrid& g, const LiquidState& s, FlipWorkspace& w) {
  const int np = int(s.count()), nc = g.cells();
  w.particle_cell.resize(np);
#pragma omp parallel for schedule(static) if (worth_threads(8LL * np))
  for (int p = 0; p < np; ++p) {
    int idx[3] = {0, 0, 0};
    const int dims[3] = {g.nx, g.ny, g.nz};
    for (int a = 0; a < g.dim; ++a)
      idx[a] = std::clamp(int(std::floor((s.x[3 * p + a] - g.lo[a]) / g.h)), 0, dims[a] - 1);
    w.particle_cell[p] = g.cell(idx[0], idx[1], idx[2]);
  }
  w.cell_start.assign(nc + 1, 0);
  for (int p = 0; p < np; ++p) ++w.cell_start[w.particle_cell[p] + 1];
  for (int c = 0; c < nc; ++c) w.cell_start[c + 1] += w.cell_start[c];
  w.cell_fill.assign(w.cell_start.begin(), w.cell_start.end() - 1);
  w.order.resize(np);
  for (int p = 0; p < np; ++p) w.order[w.cell_fill[w.particle_cell[p]]++] = p;
}

// Particle-to-grid by slabs of 3 layers along the slowest axis: a particle in
// layer L writes layers L-1..L+1, so even slabs never touch each other, nor do
// odd ones; no atomics. Also the liquid level set phi = min |x_c - x_p| - R.
void particles_to_grid(const FlipGrid& g, const LiquidState& s, FlipWorkspace& w) {
  for (int c = 0; c < g.dim; ++c) {
    w.vel[c].resize(g.faces(c));
    w.weight[c].assign(2 * size_t(g.faces(c)), 0.f);  // interleaved (sum w v, sum w): one cache line per corner
    w.valid[c].resize(g.faces(c));
  }
  const float R = float(0.6 * g.h);
  w.phi_liquid.assign(g.cells(), float(9 * g.h * g.h));
  const int axis = g.dim - 1;
  const int layers = axis == 2 ? g.nz : g.ny;
  const int plane = axis == 2 ? g.nx * g.ny : g.nx;
  constexpr int T = 3;
  const int slabs = (layers + T - 1) / T;
  const GridMap gm(g);
  for (int colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(dynamic, 1) if (worth_threads(g.cells()))
    for (int sl = colour; sl < slabs; sl += 2) {
      const int c0 = sl * T * plane, c1 = std::min(layers, (sl + 1) * T) * plane;
      for (int o = w.cell_start[c0]; o < w.cell_start[c1]; ++o) {
        const int p = w.order[o];
        const float* x = &s.x[3 * p];
        const float* v = &s.v[3 * p];
        GridSamples gs;
        gm.samples(x, &gs);
        for (int c = 0; c < g.dim; ++c) {
          const Stencil st = stencil_of(gm, gs, c);
          float* acc = w.weight[c].data() + 2 * size_t(st.base);
          const float tx = st.t[0], ty = st.t[1], vc = v[c];
          const float wy[2] = {1 - ty, ty};
          const float wz[2] = {g.dim == 3 ? 1 - st.t[2] : 1.f, st.t[2]};
          const int nk = g.dim == 3 ? 2 : 1;
          for (int dk = 0; dk < nk; ++dk)
            for (int dj = 0; dj < 2; ++dj) {
              float* a = acc + 2 * (dj * st.sy + dk * st.sz);
              const float w1 = wy[dj] * wz[dk], w0 = w1 * (1 - tx), w1x = w1 * tx;
              a[0] += w0 * vc, a[1] += w0;
              a[2] += w1x * vc, a[3] += w1x;
            }
        }
        // Liquid level set at the particle's cell and its 2 dim face neighbours
        // (the ghost-fluid theta only pairs face-adjacent cells).
        const int cell = w.particle_cell[p];
        const int cidx[3] = {cell % g.nx, (cell / g.nx) % g.ny, cell / (g.nx * g.ny)};
        const int cdim[3] = {g.nx, g.ny, g.nz};
        const int cst[3] = {1, g.nx, g.nx * g.ny};
        float rel[3] = {0, 0, 0};  // particle relative to its cell centre
        for (int a = 0; a < g.dim; ++a) rel[a] = x[a] - float(g.lo[a] + (cidx[a] + 0.5) * g.h);
        float d2c = 0;
        for (int a = 0; a < g.dim; ++a) d2c += rel[a] * rel[a];
        w.phi_liquid[cell] = std::min(w.phi_liquid[cell], d2c);  // squared distance until the end
        const float hf = float(g.h);
        for (int a = 0; a < g.dim; ++a)
          for (int sg = -1; sg <= 1; sg += 2) {
            const int ni = cidx[a] + sg;
            if (ni < 0 || ni >= cdim[a]) continue;
            const float da = rel[a] - sg * hf;
            const float d2 = d2c - rel[a] * rel[a] + da * da;
            float& phi = w.phi_liquid[cell + sg * cst[a]];
            phi = std::min(phi, d2);
          }
      }
    }
  }
  const int nc = g.cells();
#pragma omp parallel for schedule(static) if (worth_threads_light(g.cells()))
  for (int ci = 0; ci < nc; ++ci) w.phi_liquid[ci] = std::sqrt(w.phi_liquid[ci]) - R;
  for (int c = 0; c < g.dim; ++c) {
    const int n = g.faces(c);
#pragma omp parallel for schedule(static) if (worth_threads_light(g.cells()))
    for (int f = 0; f < n; ++f) {
      const float wt = w.weight[c][2 * size_t(f) + 1];
      w.valid[c][f] = wt > 1e-6f;
      w.vel[c][f] = wt > 1e-6f ? w.weight[c][2 * size_t(f)] / wt : 0.f;
    }
  }
}

// Adds particles to interior fluid cells that have fewer than half the nominal
// count (FLIP thins out in stretching flow; Ando et al. style reseeding).
void reseed(const FlipGrid& g, const LiquidModel& m, LiquidState& s, FlipWorkspace& w) {
  sort_particles(g, s, w);
  const int nominal = g.dim == 3 ? m.particles_per_axis * m.particles_per_axis * m.particles_per_axis
                                 : m.particles_per_axis * m.particles_per_axis;
  const int dims[3] = {g.nx, g.ny, g.nz};
  std::mt19937 rng(uint32_t(m.seed * 7919 + s.frame));
  std::uniform_real_distribution<float> U(0.f, 1.f);
  const Pose pose = source_pose_at(m, s.time_s), tpose = target_pose_at(m, s.time_s);
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const int ci = g.cell(i, j, k);
        const int count = w.cell_start[ci + 1] - w.cell_start[ci];
        if (count == 0 || count >= nominal / 2) continue;
        const int idx[3] = {i, j, k};
        const int st[3] = {1, g.nx, g.nx * g.ny};
        bool interior = true;
        for (int a = 0; a < g.dim && interior; ++a)
          for (int sg = -1; sg <= 1 && interior; sg += 2) {
            const int ni = idx[a] + sg;
            if (ni < 0 || ni >= dims[a]) continue;
            const int nb = ci + sg * st[a];
            if (w.cell_start[nb + 1] == w.cell_start[nb]) interior = false;
          }
        if (!interior) continue;
        bool src;
        if (solid_sdf(m, pose, tpose, g.cell_pos(i, j, k), &src) < g.h) continue;
        for (int add = count; add < nominal / 2; ++add) {
          float x[3] = {float(g.lo[0] + (i + U(rng)) * g.h), float(g.lo[1] + (j + U(rng)) * g.h),
                        g.dim == 3 ? float(g.lo[2] + (k + U(rng)) * g.h) : 0.f};
          // Velocity: the mean of the cell's particles.
          float v[3] = {0, 0, 0};
          for (int o = w.cell_start[ci]; o < w.cell_start[ci + 1]; ++o)
            for (int a = 0; a < 3; ++a) v[a] += s.v[3 * w.order[o] + a] / count;
          s.x.insert(s.x.end(), x, x + 3);
          s.v.insert(s.v.end(), v, v + 3);
        }
      }
}

}  // namespace

FlipGrid model_grid(const LiquidModel& m) {
  FlipGrid g;
  g.dim = m.dim;
  g.nx = m.n[0], g.ny = m.n[1], g.nz = m.dim == 3 ? m.n[2] : 1;
  g.h = m.cell_size_m;
  g.lo = m.domain_min_m;
  if (m.dim == 2) g.lo[2] = 0;
  return g;
}

Pose source_pose_at(const LiquidModel& m, double t) {
  return m.source_path.keys.empty() ? m.source.pose : m.source_path.at(t);
}

Pose target_pose_at(const LiquidModel& m, double t) {
  Pose p = m.target.pose;
  for (int a = 0; a < 3; ++a) p.position_m[a] += m.target_velocity_mps[a] * t;
  return p;
}

void liquid_substep(const LiquidModel& m, LiquidState& s, double dt, StepStats* stats) {
  const FlipGrid g = model_grid(m);
  FlipWorkspace& w = workspace(m);
  const int np = int(s.count());
  double clock = omp_get_wtime();
  auto lap = [&](double* acc) {
    const double now = omp_get_wtime();
    if (stats) *acc += now - clock;
    clock = now;
  };
  StepStats local;
  StepStats& acc = stats ? *stats : local;
  build_solids(g, m, w, s.time_s + dt);
  lap(&acc.solids_s);
  sort_particles(g, s, w);
  particles_to_grid(g, s, w);
  w.fluid.assign(g.cells(), 0);
  for (int c = 0; c < g.cells(); ++c) w.fluid[c] = w.cell_start[c + 1] > w.cell_start[c];
  extrapolate(g, w, 2);
  set_solid_faces(g, w);
  for (int c = 0; c < g.dim; ++c) w.vel_old[c] = w.vel[c];
  for (int c = 0; c < g.dim; ++c) {
    const float dv = float(m.gravity_m_per_s2[c] * dt);
    const int n = g.faces(c);
#pragma omp parallel for schedule(static) if (worth_threads_light(g.cells()))
    for (int f = 0; f < n; ++f)
      if (w.open[c][f] > 0) w.vel[c][f] += dv;
  }
  lap(&acc.transfer_s);
  apply_viscosity(g, m, w, dt);
  lap(&acc.viscosity_s);
  const int iters = project_pressure(g, m, w, dt);
  lap(&acc.pressure_s);
  extrapolate(g, w, 3);
  set_solid_faces(g, w);
  lap(&acc.transfer_s);
  // Grid to particles (FLIP/PIC blend) and RK2 advection in the new field.
  const float flip = float(m.flip_ratio);
  const GridMap gm(g);
  const Pose pose_end = source_pose_at(m, s.time_s + dt), tpose_end = target_pose_at(m, s.time_s + dt);
  double vmax = 0;
#pragma omp parallel for schedule(static) reduction(max : vmax) if (worth_threads(8LL * np))
  for (int o = 0; o < np; ++o) {
    const int p = w.order[o];  // cell order: neighbouring particles read the same faces
    float* x = &s.x[3 * p];
    float* v = &s.v[3 * p];
    float vn[3] = {0, 0, 0}, xm[3] = {x[0], x[1], x[2]}, vm[3] = {0, 0, 0};
    GridSamples gs;
    gm.samples(x, &gs);
    for (int c = 0; c < g.dim; ++c) {
      const Stencil st = stencil_of(gm, gs, c);
      vn[c] = sample(g.dim, st, w.vel[c].data());
      const float vo = sample(g.dim, st, w.vel_old[c].data());
      v[c] = flip * (v[c] + vn[c] - vo) + (1 - flip) * vn[c];
      xm[c] = x[c] + float(0.5 * dt) * vn[c];
    }
    gm.samples(xm, &gs);
    for (int c = 0; c < g.dim; ++c) vm[c] = sample(g.dim, stencil_of(gm, gs, c), w.vel[c].data());
    for (int c = 0; c < g.dim; ++c) x[c] += float(dt) * vm[c];
    push_out(g, m, pose_end, tpose_end, s.time_s + dt, x, v);
    double sp = 0;
    for (int c = 0; c < g.dim; ++c) sp += double(v[c]) * v[c];
    vmax = std::max(vmax, sp);
  }
  lap(&acc.advect_s);
  s.time_s += dt;
  ++s.substeps;
  if (stats) {
    ++stats->substeps;
    stats->pressure_iterations += iters;
    stats->max_speed = std::max(stats->max_speed, std::sqrt(vmax));
  }
}

void liquid_step(const LiquidModel& m, LiquidState& s, StepStats* stats) {
  const FlipGrid g = model_grid(m);
  const double t_end = (s.frame + 1) * m.dt_s;
  const double gmag = std::sqrt(m.gravity_m_per_s2[0] * m.gravity_m_per_s2[0] +
                                m.gravity_m_per_s2[1] * m.gravity_m_per_s2[1] +
                                m.gravity_m_per_s2[2] * m.gravity_m_per_s2[2]);
  const double wall_reach = container_reach(m.source.shape);
  while (t_end - s.time_s > 1e-9) {
    double vmax = 0;
    const int np = int(s.count());
#pragma omp parallel for schedule(static) reduction(max : vmax) if (worth_threads_light(8LL * np))
    for (int p = 0; p < np; ++p) {
      double sp = 0;
      for (int c = 0; c < 3; ++c) sp += double(s.v[3 * p + c]) * s.v[3 * p + c];
      vmax = std::max(vmax, sp);
    }
    Vec3 lin;
    double tilt_rate;
    m.source_path.velocity(s.time_s, &lin, &tilt_rate);
    const Vec3& vt = m.target_velocity_mps;
    const double wall = std::max(std::sqrt(lin[0] * lin[0] + lin[1] * lin[1] + lin[2] * lin[2]) +
                                     std::abs(tilt_rate) * wall_reach,
                                 std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]));
    // Bridson's bound: u_max + sqrt(5 h |g|) keeps gravity's kick inside the CFL.
    const double speed = std::max(std::sqrt(vmax), wall) + std::sqrt(5 * g.h * gmag) + 1e-6;
    double dt = std::max(m.cfl * g.h / speed, m.dt_s / m.max_substeps);
    const double remaining = t_end - s.time_s;
    if (dt >= remaining) dt = remaining;
    else if (dt > 0.5 * remaining) dt = 0.5 * remaining;  // two even steps instead of a sliver
    liquid_substep(m, s, dt, stats);
  }
  s.time_s = t_end;
  ++s.frame;
  for (size_t i = 0; i < s.v.size(); ++i)
    if (!std::isfinite(s.v[i]) || !std::isfinite(s.x[i]))
      throw std::runtime_error("liquid: frame " + std::to_string(s.frame) +
                               ": non-finite particle velocity or position (particle " +
                               std::to_string(i / 3) + ")");
  if (m.reseed) reseed(g, m, s, workspace(m));
}

LiquidState liquid_init(const LiquidModel& m) {
  const FlipGrid g = model_grid(m);
  LiquidState s;
  std::mt19937 rng(uint32_t(m.seed));
  const int ppa = m.particles_per_axis;
  const double sub = g.h / ppa;
  std::uniform_real_distribution<double> J(-0.25 * sub, 0.25 * sub);
  const Pose pose = source_pose_at(m, 0);
  auto inside = [&](const Vec3& x) {
    for (const auto& b : m.liquid_boxes) {
      bool in = true;
      for (int a = 0; a < m.dim; ++a) in = in && x[a] >= b.first[a] && x[a] <= b.second[a];
      if (in) return true;
    }
    if (m.has_source && m.fill_fraction > 0) {
      const Vec3 l = pose.to_local(x);
      if (m.source.shape.in_cavity(l, m.dim) && l[1] < m.fill_fraction * m.source.shape.height_m) return true;
    }
    return false;
  };
  const int nk = g.dim == 3 ? g.nz * ppa : 1;
  for (int k = 0; k < nk; ++k)
    for (int j = 0; j < g.ny * ppa; ++j)
      for (int i = 0; i < g.nx * ppa; ++i) {
        Vec3 x{g.lo[0] + (i + 0.5) * sub + J(rng), g.lo[1] + (j + 0.5) * sub + J(rng),
               g.dim == 3 ? g.lo[2] + (k + 0.5) * sub + J(rng) : 0.0};
        if (!inside(x)) continue;
        bool src;
        if (solid_sdf(m, pose, m.target.pose, x, &src) < 0.25 * g.h) continue;
        for (int a = 0; a < 3; ++a) s.x.push_back(float(x[a]));
      }
  s.v.assign(s.x.size(), 0.f);
  // Liquid in a container starts with the container's motion.
  for (size_t p = 0; p < s.count(); ++p) {
    const Vec3 x{s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]};
    if (m.has_source && m.source.shape.in_cavity(pose.to_local(x), m.dim)) {
      const Vec3 v = source_point_velocity(m, 0, pose, x);
      for (int a = 0; a < m.dim; ++a) s.v[3 * p + a] = float(v[a]);
    } else if (m.has_target && m.target.shape.in_cavity(m.target.pose.to_local(x), m.dim)) {
      for (int a = 0; a < m.dim; ++a) s.v[3 * p + a] = float(m.target_velocity_mps[a]);
    }
  }
  return s;
}

std::array<double, 3> liquid_fractions(const LiquidModel& m, const LiquidState& s) {
  const Pose pose = source_pose_at(m, s.time_s), tpose = target_pose_at(m, s.time_s);
  const size_t n = s.count();
  size_t in_target = 0, in_source = 0;
  for (size_t p = 0; p < n; ++p) {
    const Vec3 x{s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]};
    if (m.has_target && m.target.shape.in_cavity(tpose.to_local(x), m.dim)) ++in_target;
    else if (m.has_source && m.source.shape.in_cavity(pose.to_local(x), m.dim)) ++in_source;
  }
  if (n == 0) return {0, 0, 0};
  return {double(in_target) / n, double(n - in_target - in_source) / n, double(in_source) / n};
}

Record liquid_frame_record(const LiquidModel& m, const LiquidState& s) {
  Record r;
  r.kind = RecordKind::Frame;
  r.index = s.frame;
  r.time_s = s.time_s;
  const uint32_t n = uint32_t(s.count()), d = uint32_t(m.dim);
  Field pos{"particles", {n, d}, {}}, speed{"speed", {n}, {}};
  pos.data.resize(size_t(n) * d);
  speed.data.resize(n);
  for (uint32_t p = 0; p < n; ++p) {
    float s2 = 0;
    for (uint32_t a = 0; a < d; ++a) pos.data[p * d + a] = s.x[3 * p + a], s2 += s.v[3 * p + a] * s.v[3 * p + a];
    speed.data[p] = std::sqrt(s2);
  }
  r.fields.push_back(std::move(pos));
  r.fields.push_back(std::move(speed));
  const auto sp = source_pose_at(m, s.time_s).as_array();
  const auto tp = target_pose_at(m, s.time_s).as_array();
  r.fields.push_back(Field{"source_pose", {7}, std::vector<float>(sp.begin(), sp.end())});
  r.fields.push_back(Field{"target_pose", {7}, std::vector<float>(tp.begin(), tp.end())});
  const auto fr = liquid_fractions(m, s);
  r.fields.push_back(Field{"fractions", {3}, {float(fr[0]), float(fr[1]), float(fr[2])}});
  return r;
}

}  // namespace pliant::liquid
