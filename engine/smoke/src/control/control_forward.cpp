// Forward pass of the control model (control_forward_model.h): operators, the
// double-precision trajectory and the public float control_forward.
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "control_forward_model.h"
// after control.h: smoke_workspace.h needs SmokeModel declared
#include "../smoke_workspace.h"
#include "control_sampling.h"

namespace pliant::smoke {
namespace control_detail {

ForwardOps::ForwardOps(const ControlModel& m, double pressure_tolerance)
    : g_(model_grid(m.sim)), dt_(m.sim.dt_s), poisson_(g_), tol_(pressure_tolerance) {
  for (int a = 0; a < 3; ++a) {
    lay_[a] = g_.face_layout(a);
    off_[a + 1] = off_[a] + lay_[a].count();
  }
  faces_ = off_[3];
  lo_.assign(faces_, -1);
  hi_.assign(faces_, -1);
  for (int a = 0; a < g_.dim; ++a)
    for (size_t e = 0; e < lay_[a].count(); ++e) {
      lo_[off_[a] + e] = int32_t(compute_lo_cell(a, e));
      hi_[off_[a] + e] = int32_t(compute_hi_cell(a, e));
    }
  const int dim = g_.dim;
  cell_faces_.resize(g_.cells() * 2 * dim);
  for (int k = 0; k < g_.n[2]; ++k)
    for (int j = 0; j < g_.n[1]; ++j)
      for (int i = 0; i < g_.n[0]; ++i)
        for (int a = 0; a < dim; ++a) {
          const size_t c = g_.cell(i, j, k);
          cell_faces_[c * 2 * dim + 2 * a] = int32_t(off_[a] + g_.face_lo(a, i, j, k));
          cell_faces_[c * 2 * dim + 2 * a + 1] = int32_t(off_[a] + g_.face_hi(a, i, j, k));
        }
  flux_.assign(faces_, 0.0);
  face_mask_.assign(faces_, 0);
  has_obstacles_ = !m.solid.empty();
  for (int a = 0; a < g_.dim; ++a) {
    const size_t n = lay_[a].count();
    for (size_t e = 0; e < n; ++e) {
      const long lo = lo_cell(a, e), hi = hi_cell(a, e);
      bool masked = lo < 0 || hi < 0;
      if (has_obstacles_ && !masked) masked = m.solid[size_t(lo)] || m.solid[size_t(hi)];
      face_mask_[off_[a] + e] = masked;
    }
  }
  phi_.assign(g_.cells(), 0.0);
  rhs_.assign(g_.cells(), 0.0);
}

bool ForwardOps::is_wall_face(int axis, size_t local) const {
  return lo_cell(axis, local) < 0 || hi_cell(axis, local) < 0;
}

long ForwardOps::compute_lo_cell(int axis, size_t e) const {
  const FieldLayout& l = lay_[axis];
  std::array<int, 3> c{int(e % l.size[0]), int((e / l.size[0]) % l.size[1]), int(e / (size_t(l.size[0]) * l.size[1]))};
  if (c[axis] == 0) {
    if (!g_.periodic) return -1;
    c[axis] = g_.n[axis] - 1;
  } else {
    c[axis] -= 1;
  }
  return long(g_.cell(c[0], c[1], c[2]));
}

long ForwardOps::compute_hi_cell(int axis, size_t e) const {
  const FieldLayout& l = lay_[axis];
  std::array<int, 3> c{int(e % l.size[0]), int((e / l.size[0]) % l.size[1]), int(e / (size_t(l.size[0]) * l.size[1]))};
  if (c[axis] == g_.n[axis]) return -1;  // only reachable when closed
  return long(g_.cell(c[0], c[1], c[2]));
}

void ForwardOps::mask(Vec& u) const {
  const size_t n = faces_;
  const uint8_t* mk = face_mask_.data();
  double* p = u.data();
#pragma omp parallel for schedule(static) if (n > 4096)
  for (size_t e = 0; e < n; ++e)
    if (mk[e]) p[e] = 0.0;
}

void ForwardOps::advect_velocity(const Vec& u, Vec& out) const {
  const double s = dt_ / g_.h;
  const double* uc[3] = {u.data() + off_[0], u.data() + off_[1], u.data() + off_[2]};
  for (int a = 0; a < g_.dim; ++a) {
    const FieldLayout& l = lay_[a];
    const long n = long(l.count());
#pragma omp parallel for schedule(static) if (n > 4096)
    for (long e = 0; e < n; ++e) {
      const size_t ge = off_[a] + size_t(e);
      if (is_wall_face(a, size_t(e))) {
        out[ge] = 0.0;
        continue;
      }
      const int i = int(e % l.size[0]), j = int((e / l.size[0]) % l.size[1]),
                k = int(e / (size_t(l.size[0]) * l.size[1]));
      const double x[3] = {i + l.offset[0], j + l.offset[1], k + l.offset[2]};
      double xb[3] = {x[0], x[1], x[2]};
      Stencil st;
      for (int d = 0; d < g_.dim; ++d) {
        make_stencil(lay_[d], x[0], x[1], x[2], st);
        xb[d] -= s * apply_stencil(st, uc[d]);
      }
      make_stencil(l, xb[0], xb[1], xb[2], st);
      out[ge] = apply_stencil(st, uc[a]);
    }
  }
  for (size_t e = off_[g_.dim]; e < faces_; ++e) out[e] = 0.0;
}

void ForwardOps::project(Vec& u) {
  mask(u);
  const double h = g_.h;
  const MacGrid& g = g_;
  double* rhs = rhs_.data();
  const double* uc[3] = {u.data() + off_[0], u.data() + off_[1], u.data() + off_[2]};
  double bmax = 0;
#pragma omp parallel for collapse(2) schedule(static) reduction(max : bmax) if (g.cells() > 4096)
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i) {
        double net = 0;
        for (int a = 0; a < g.dim; ++a) net += uc[a][g.face_hi(a, i, j, k)] - uc[a][g.face_lo(a, i, j, k)];
        const double b = -h * net;  // -h^2 div(u)
        rhs[g.cell(i, j, k)] = b;
        bmax = std::max(bmax, std::abs(b));
      }
  if (bmax == 0) return;
  std::fill(phi_.begin(), phi_.end(), 0.0);  // zero start: P stays one fixed linear map
  const PoissonStats ps = poisson_.solve(PoissonMethod::MultigridPCG, rhs, phi_.data(), tol_, 300);
  ++projections;
  pressure_iterations += ps.iterations;
  worst_pressure_residual = std::max(worst_pressure_residual, ps.relative_residual);
  for (int a = 0; a < g.dim; ++a) {
    const long n = long(lay_[a].count());
    double* ua = u.data() + off_[a];
#pragma omp parallel for schedule(static) if (n > 4096)
    for (long e = 0; e < n; ++e) {
      const long lo = lo_cell(a, size_t(e)), hi = hi_cell(a, size_t(e));
      if (lo < 0 || hi < 0) continue;
      ua[e] -= (phi_[size_t(hi)] - phi_[size_t(lo)]) / h;
    }
  }
  mask(u);
}

double ForwardOps::max_divergence(const Vec& u) const {
  const MacGrid& g = g_;
  const double* uc[3] = {u.data() + off_[0], u.data() + off_[1], u.data() + off_[2]};
  double m = 0;
#pragma omp parallel for collapse(2) schedule(static) reduction(max : m) if (g.cells() > 4096)
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i) {
        double net = 0;
        for (int a = 0; a < g.dim; ++a) net += uc[a][g.face_hi(a, i, j, k)] - uc[a][g.face_lo(a, i, j, k)];
        m = std::max(m, std::abs(net) / g.h);
      }
  return m;
}

int ForwardOps::density_substeps(const Vec& u) const {
  const MacGrid& g = g_;
  const double* uc[3] = {u.data() + off_[0], u.data() + off_[1], u.data() + off_[2]};
  double worst = 0;
#pragma omp parallel for collapse(2) schedule(static) reduction(max : worst) if (g.cells() > 4096)
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i) {
        double out = 0;
        for (int a = 0; a < g.dim; ++a) {
          out += std::max(0.0, uc[a][g.face_hi(a, i, j, k)]);
          out += std::max(0.0, -uc[a][g.face_lo(a, i, j, k)]);
        }
        worst = std::max(worst, out);
      }
  const double need = dt_ * worst / g.h;
  return std::clamp(int(std::ceil(need - 1e-12)), 1, 1000);
}

void ForwardOps::upwind_step(const Vec& u, double dt_sub, const Vec& q, Vec& q_out) const {
  // Flux per face once (F = u * q_upwind, 0 at closed walls), then each cell sums
  // the fluxes through its faces.
  const double kk = dt_sub / g_.h;
  const long nf = long(faces_);
  double* F = flux_.data();
  const int32_t* lo = lo_.data();
  const int32_t* hi = hi_.data();
#pragma omp parallel for schedule(static) if (nf > 16384)
  for (long e = 0; e < nf; ++e) {
    if (lo[e] < 0 || hi[e] < 0) {
      F[e] = 0.0;
      continue;
    }
    const double v = u[size_t(e)];
    F[e] = v * (v > 0 ? q[size_t(lo[e])] : q[size_t(hi[e])]);
  }
  const int nd = 2 * g_.dim;
  const long nc = long(g_.cells());
  const int32_t* cf = cell_faces_.data();
#pragma omp parallel for schedule(static) if (nc > 4096)
  for (long c = 0; c < nc; ++c) {
    double net = 0;
    for (int a = 0; a < nd; a += 2) net += F[cf[c * nd + a + 1]] - F[cf[c * nd + a]];
    q_out[size_t(c)] = q[size_t(c)] - kk * net;
  }
}

SerialBelow::SerialBelow(size_t cells, size_t threshold) {
  if (cells >= threshold) return;
  previous_ = omp_get_max_threads();
  omp_set_num_threads(1);
}
SerialBelow::~SerialBelow() {
  if (previous_ > 0) omp_set_num_threads(previous_);
}

void forward_d(const ControlModel& m, ForwardOps& ops, const std::vector<Vec>& f, TrajectoryD& out) {
  std::vector<const double*>& fp = ops.scratch.force_frames;
  fp.resize(f.size());
  for (size_t i = 0; i < f.size(); ++i) fp[i] = f[i].data();
  forward_d(m, ops, fp.data(), out);
}

void forward_d(const ControlModel& m, ForwardOps& ops, const double* const* f, TrajectoryD& out) {
  const SerialBelow serial(ops.cells());
  const int T = m.sim.frames;
  const size_t nf = ops.faces(), nc = ops.cells();
  // Sizes only: every entry below is written (no allocation when `out` is reused).
  out.rho.resize(T + 1);
  out.u.resize(T + 1);
  out.substeps.assign(T, 1);
  out.rho[0].assign(m.initial_density.begin(), m.initial_density.end());
  out.rho[0].resize(nc, 0.0);
  out.u[0].assign(nf, 0.0);
  Vec& tmp = ops.scratch.rho_tmp;
  tmp.resize(nc);
  const double dt = ops.dt();
  for (int i = 0; i < T; ++i) {
    Vec& w = out.u[i + 1];
    w.resize(nf);
    ops.advect_velocity(out.u[i], w);
    const double* fi = f[i];
    double* wp = w.data();
#pragma omp parallel for schedule(static) if (nf > 16384)
    for (size_t e = 0; e < nf; ++e) wp[e] += dt * fi[e];
    ops.project(w);
    const int S = ops.density_substeps(w);
    out.substeps[i] = S;
    Vec& r = out.rho[i + 1];
    r.resize(nc);
    ops.upwind_step(w, dt / S, out.rho[i], r);
    for (int s = 1; s < S; ++s) {
      ops.upwind_step(w, dt / S, r, tmp);
      r.swap(tmp);
    }
  }
}

double keyframe_error_d(const ControlModel& m, const TrajectoryD& t) {
  double e = 0;
  for (const Keyframe& k : m.keyframes) {
    const double* r = t.rho[k.frame].data();
    const float* target = k.density.data();
    const double s = fixed_order_sum(t.rho[k.frame].size(), [&](size_t c) {
      const double d = r[c] - target[c];
      return d * d;
    });
    e += k.weight * s;
  }
  return e;
}

std::vector<Vec> to_double(const FaceSeries& f) {
  std::vector<Vec> out(f.size());
  for (size_t i = 0; i < f.size(); ++i) out[i].assign(f[i].begin(), f[i].end());
  return out;
}

FaceSeries to_float(const std::vector<Vec>& f) {
  FaceSeries out(f.size());
  for (size_t i = 0; i < f.size(); ++i) {
    out[i].resize(f[i].size());
    std::transform(f[i].begin(), f[i].end(), out[i].begin(), [](double x) { return float(x); });
  }
  return out;
}

}  // namespace control_detail

Trajectory control_forward(const ControlModel& m, const FaceSeries& f) {
  using namespace control_detail;
  ForwardOps ops(m, kControlPressureTolerance);
  TrajectoryD t;
  forward_d(m, ops, to_double(f), t);
  Trajectory out;
  out.density = to_float(t.rho);
  out.velocity = to_float(t.u);
  return out;
}

}  // namespace pliant::smoke
