// Discrete adjoint of the control forward model (control_forward_model.h): reverse
// sweep through density upwinding, projection and semi-Lagrangian self-advection,
// giving dE/df for E = sum_k w_k ||rho_tk - rho*_k||^2 + r sum_i ||f_i||^2.
#include <algorithm>
#include <climits>
#include <stdexcept>
#include <string>

#include "control_forward_model.h"
#include "control_sampling.h"

namespace pliant::smoke {
namespace control_detail {

void ForwardOps::advect_velocity_adjoint(const Vec& u, const Vec& out_bar, Vec& u_bar) const {
  const double s = dt_ / g_.h;
  const int dim = g_.dim;
  const double* uc[3] = {u.data() + off_[0], u.data() + off_[1], u.data() + off_[2]};
  if (chunk_bar_.size() != size_t(kAdjointChunks) || chunk_bar_[0].size() != faces_)
    chunk_bar_.assign(kAdjointChunks, Vec(faces_, 0.0));  // first call only; kept zero between calls
  // Scatter: chunk c takes the c-th slice of every component's faces (contiguous in
  // the slowest index, so it writes a narrow band) into its own buffer.
#pragma omp parallel for schedule(dynamic, 1) if (faces_ > 16384)
  for (int c = 0; c < kAdjointChunks; ++c) {
    double* cb = chunk_bar_[size_t(c)].data();
    double* ub[3] = {cb + off_[0], cb + off_[1], cb + off_[2]};
    long first[3] = {LONG_MAX, LONG_MAX, LONG_MAX}, last[3] = {0, 0, 0};
    auto touch = [&](int d, size_t idx) {
      first[d] = std::min(first[d], long(idx));
      last[d] = std::max(last[d], long(idx) + 1);
    };
    for (int a = 0; a < dim; ++a) {
      const FieldLayout& l = lay_[a];
      const long n = long(l.count());
      const long e0 = n * c / kAdjointChunks, e1 = n * (c + 1) / kAdjointChunks;
      for (long e = e0; e < e1; ++e) {
        const double ob = out_bar[off_[a] + size_t(e)];
        if (ob == 0.0 || is_wall_face(a, size_t(e))) continue;
        const int i = int(e % l.size[0]), j = int((e / l.size[0]) % l.size[1]),
                  k = int(e / (size_t(l.size[0]) * l.size[1]));
        const double x[3] = {i + l.offset[0], j + l.offset[1], k + l.offset[2]};
        double xb[3] = {x[0], x[1], x[2]};
        Stencil su[3];
        for (int d = 0; d < dim; ++d) {
          make_stencil(lay_[d], x[0], x[1], x[2], su[d]);
          xb[d] -= s * apply_stencil(su[d], uc[d]);
        }
        Stencil sb;
        make_stencil(l, xb[0], xb[1], xb[2], sb);
        // The sampled values themselves.
        for (int q = 0; q < sb.count; ++q) {
          ub[a][sb.idx[q]] += ob * sb.w[q];
          touch(a, sb.idx[q]);
        }
        // The backtrace position: d out / d xb_d, then xb_d = x_d - s U_d(x).
        for (int d = 0; d < dim; ++d) {
          double dS = 0;
          for (int q = 0; q < sb.count; ++q) dS += sb.dw[d][q] * uc[a][sb.idx[q]];
          const double Ubar = -s * ob * dS;
          if (Ubar == 0.0) continue;
          for (int q = 0; q < su[d].count; ++q) {
            ub[d][su[d].idx[q]] += Ubar * su[d].w[q];
            touch(d, su[d].idx[q]);
          }
        }
      }
    }
    for (int d = 0; d < 3; ++d) touched_[size_t(c)][size_t(d)] = {first[d], last[d]};
  }
  // Gather: u_bar += chunk buffers in chunk order, and leave the buffers zero.
  for (int d = 0; d < dim; ++d) {
    const long n = long(lay_[d].count());
    double* ubd = u_bar.data() + off_[d];
#pragma omp parallel for schedule(static) if (n > 16384)
    for (long e = 0; e < n; ++e) {
      double v = ubd[e];
      for (int c = 0; c < kAdjointChunks; ++c) {
        const auto& t = touched_[size_t(c)][size_t(d)];
        if (e < t[0] || e >= t[1]) continue;
        double& x = chunk_bar_[size_t(c)][off_[d] + size_t(e)];
        v += x;
        x = 0.0;
      }
      ubd[e] = v;
    }
  }
}

void ForwardOps::upwind_step_adjoint(const Vec& u, double dt_sub, const Vec& q, const Vec& qob, Vec& q_bar,
                                     Vec& u_bar) const {
  // Per face: Fbar = k (qob[hi] - qob[lo]) (q_out[lo] -= k F, q_out[hi] += k F);
  // u_bar += Fbar * q_upwind; the upwind cell gets Fbar * u.
  const double kk = dt_sub / g_.h;
  const long nf = long(faces_);
  double* Fb = flux_.data();
  const int32_t* lo = lo_.data();
  const int32_t* hi = hi_.data();
#pragma omp parallel for schedule(static) if (nf > 16384)
  for (long e = 0; e < nf; ++e) {
    if (lo[e] < 0 || hi[e] < 0) {
      Fb[e] = 0.0;
      continue;
    }
    const double v = u[size_t(e)];
    const double qL = q[size_t(lo[e])], qH = q[size_t(hi[e])];
    Fb[e] = kk * (qob[size_t(hi[e])] - qob[size_t(lo[e])]);
    // At v == 0 (fluid at rest) the flux has a kink; take the mean of the one-sided
    // derivatives so the first L-BFGS step from rest sees both neighbours.
    const double up = v > 0 ? qL : (v < 0 ? qH : 0.5 * (qL + qH));
    u_bar[size_t(e)] += Fb[e] * up;
  }
  const int nd = 2 * g_.dim;
  const long nc = long(g_.cells());
  const int32_t* cf = cell_faces_.data();
#pragma omp parallel for schedule(static) if (nc > 4096)
  for (long c = 0; c < nc; ++c) {
    double qb = qob[size_t(c)];
    for (int a = 0; a < nd; a += 2) {
      const int32_t fl = cf[c * nd + a], fh = cf[c * nd + a + 1];
      const double vh = u[size_t(fh)], vl = u[size_t(fl)];
      if (vh > 0) qb += Fb[fh] * vh;   // c is the upwind side of its high face
      if (!(vl > 0)) qb += Fb[fl] * vl;  // ... and of its low face
    }
    q_bar[size_t(c)] = qb;
  }
}

double objective_d(const ControlModel& m, ForwardOps& ops, const std::vector<Vec>& f, std::vector<Vec>* grad) {
  const int T = m.sim.frames;
  const size_t nf = ops.faces();
  if (int(f.size()) != T) throw std::invalid_argument("control: expected " + std::to_string(T) + " force frames");
  for (const Vec& fi : f)
    if (fi.size() != nf) throw std::invalid_argument("control: force frame has the wrong number of faces");
  ForwardOps::Scratch& w = ops.scratch;
  w.force_frames.resize(size_t(T));
  for (int i = 0; i < T; ++i) w.force_frames[size_t(i)] = f[size_t(i)].data();
  if (grad) {
    grad->resize(T);
    w.grad_frames.resize(size_t(T));
    for (int i = 0; i < T; ++i) {
      (*grad)[size_t(i)].resize(nf);
      w.grad_frames[size_t(i)] = (*grad)[size_t(i)].data();
    }
  }
  return objective_d(m, ops, w.force_frames.data(), grad ? w.grad_frames.data() : nullptr);
}

double objective_d(const ControlModel& m, ForwardOps& ops, const double* const* f, double* const* grad) {
  const int T = m.sim.frames;
  const size_t nf = ops.faces(), nc = ops.cells();
  const SerialBelow serial(nc);
  ForwardOps::Scratch& w = ops.scratch;
  TrajectoryD& t = w.trajectory;
  forward_d(m, ops, f, t);
  double reg = 0;
  for (int i = 0; i < T; ++i) {
    const double* p = f[i];
    reg += fixed_order_sum(nf, [p](size_t e) { return p[e] * p[e]; });
  }
  const double E = keyframe_error_d(m, t) + m.r * reg;
  if (!grad) return E;

  // Every entry of grad, wbar and qbar is written below; ubar and rhobar accumulate.
  Vec &ubar = w.ubar, &ubar_prev = w.ubar_prev, &wbar = w.wbar, &rhobar = w.rhobar, &qbar = w.qbar;
  ubar.assign(nf, 0.0);
  ubar_prev.resize(nf);
  wbar.resize(nf);
  rhobar.assign(nc, 0.0);
  qbar.resize(nc);
  std::vector<Vec>& qs = w.substep_states;
  const double dt = ops.dt();
  const bool parallel_faces = nf > 16384, parallel_cells = nc > 16384;
  for (int i = T - 1; i >= 0; --i) {
    for (const Keyframe& k : m.keyframes)
      if (k.frame == i + 1) {
        const double* r = t.rho[i + 1].data();
        const float* target = k.density.data();
        double* rb = rhobar.data();
        const double w2 = 2.0 * k.weight;
#pragma omp parallel for schedule(static) if (parallel_cells)
        for (size_t c = 0; c < nc; ++c) rb[c] += w2 * (r[c] - target[c]);
      }
    // Density: rho_{i+1} = Up^S(rho_i, u_{i+1}); recompute the sub-step states
    // (state s = 0 is rho_i itself).
    const int S = t.substeps[i];
    const Vec& u1 = t.u[i + 1];
    if (int(qs.size()) < S) qs.resize(S);
    for (int s = 1; s < S; ++s) {
      qs[s].resize(nc);
      ops.upwind_step(u1, dt / S, s == 1 ? t.rho[i] : qs[s - 1], qs[s]);
    }
    for (int s = S - 1; s >= 0; --s) {
      ops.upwind_step_adjoint(u1, dt / S, s == 0 ? t.rho[i] : qs[s], rhobar, qbar, ubar);
      rhobar.swap(qbar);
    }
    // Velocity: u_{i+1} = M P M (A_sl(u_i) + dt f_i); M P M is symmetric.
    {
      const double* src = ubar.data();
      double* dst = wbar.data();
      double* prev = ubar_prev.data();
#pragma omp parallel for schedule(static) if (parallel_faces)
      for (size_t e = 0; e < nf; ++e) {
        dst[e] = src[e];
        prev[e] = 0.0;
      }
    }
    ops.project(wbar);
    {
      double* gi = grad[i];
      const double* fi = f[i];
      const double* wb = wbar.data();
      const double r2 = 2.0 * m.r;
#pragma omp parallel for schedule(static) if (parallel_faces)
      for (size_t e = 0; e < nf; ++e) gi[e] = dt * wb[e] + r2 * fi[e];
    }
    if (i > 0) ops.advect_velocity_adjoint(t.u[i], wbar, ubar_prev);  // u_0 is fixed (rest)
    ubar.swap(ubar_prev);
  }
  return E;
}

}  // namespace control_detail

double control_objective(const ControlModel& m, const FaceSeries& f, FaceSeries* grad) {
  using namespace control_detail;
  ForwardOps ops(m, kControlPressureTolerance);
  if (!grad) return objective_d(m, ops, to_double(f), nullptr);
  std::vector<Vec> g;
  const double E = objective_d(m, ops, to_double(f), &g);
  *grad = to_float(g);
  return E;
}

}  // namespace pliant::smoke
