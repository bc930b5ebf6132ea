// Discrete adjoint of the control forward model (control_forward_model.h): reverse
// sweep through density upwinding, projection and semi-Lagrangian self-advection,
// giving dE/df for E = sum_k w_k ||rho_tk - rho*_k||^2 + r sum_i ||f_i||^2.
#include <stdexcept>
#include <string>

#include "control_forward_model.h"
#include "control_sampling.h"

namespace pliant::smoke {
namespace control_detail {

void ForwardOps::advect_velocity_adjoint(const Vec& u, const Vec& out_bar, Vec& u_bar) const {
  const double s = dt_ / g_.h;
  const double* uc[3] = {u.data() + off_[0], u.data() + off_[1], u.data() + off_[2]};
  double* ub[3] = {u_bar.data() + off_[0], u_bar.data() + off_[1], u_bar.data() + off_[2]};
  for (int a = 0; a < g_.dim; ++a) {
    const FieldLayout& l = lay_[a];
    const long n = long(l.count());
#pragma omp parallel for schedule(static) if (n > 4096)
    for (long e = 0; e < n; ++e) {
      const double ob = out_bar[off_[a] + size_t(e)];
      if (ob == 0.0 || is_wall_face(a, size_t(e))) continue;
      const int i = int(e % l.size[0]), j = int((e / l.size[0]) % l.size[1]),
                k = int(e / (size_t(l.size[0]) * l.size[1]));
      const double x[3] = {i + l.offset[0], j + l.offset[1], k + l.offset[2]};
      double xb[3] = {x[0], x[1], x[2]};
      Stencil su[3];
      for (int d = 0; d < g_.dim; ++d) {
        make_stencil(lay_[d], x[0], x[1], x[2], su[d]);
        xb[d] -= s * apply_stencil(su[d], uc[d]);
      }
      Stencil sb;
      make_stencil(l, xb[0], xb[1], xb[2], sb);
      // The sampled values themselves.
      for (int q = 0; q < sb.count; ++q) {
#pragma omp atomic
        ub[a][sb.idx[q]] += ob * sb.w[q];
      }
      // The backtrace position: d out / d xb_d, then xb_d = x_d - s U_d(x).
      for (int d = 0; d < g_.dim; ++d) {
        double dS = 0;
        for (int q = 0; q < sb.count; ++q) dS += sb.dw[d][q] * uc[a][sb.idx[q]];
        const double Ubar = -s * ob * dS;
        if (Ubar == 0.0) continue;
        for (int q = 0; q < su[d].count; ++q) {
#pragma omp atomic
          ub[d][su[d].idx[q]] += Ubar * su[d].w[q];
        }
      }
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
  const size_t nf = ops.faces(), nc = ops.cells();
  if (int(f.size()) != T) throw std::invalid_argument("control: expected " + std::to_string(T) + " force frames");
  for (const Vec& fi : f)
    if (fi.size() != nf) throw std::invalid_argument("control: force frame has the wrong number of faces");
  const SerialBelow serial(nc);
  TrajectoryD t;
  forward_d(m, ops, f, t);
  double reg = 0;
  for (const Vec& fi : f)
    for (double x : fi) reg += x * x;
  const double E = keyframe_error_d(m, t) + m.r * reg;
  if (!grad) return E;

  grad->assign(T, Vec(nf, 0.0));
  Vec ubar(nf, 0.0), ubar_prev(nf), wbar(nf), rhobar(nc, 0.0), qbar(nc);
  std::vector<Vec> qs;
  const double dt = ops.dt();
  for (int i = T - 1; i >= 0; --i) {
    for (const Keyframe& k : m.keyframes)
      if (k.frame == i + 1)
        for (size_t c = 0; c < nc; ++c) rhobar[c] += 2.0 * k.weight * (t.rho[i + 1][c] - k.density[c]);
    // Density: rho_{i+1} = Up^S(rho_i, u_{i+1}); recompute the sub-step states.
    const int S = t.substeps[i];
    const Vec& u1 = t.u[i + 1];
    qs.resize(S);
    qs[0] = t.rho[i];
    for (int s = 1; s < S; ++s) {
      qs[s].resize(nc);
      ops.upwind_step(u1, dt / S, qs[s - 1], qs[s]);
    }
    for (int s = S - 1; s >= 0; --s) {
      ops.upwind_step_adjoint(u1, dt / S, qs[s], rhobar, qbar, ubar);
      rhobar.swap(qbar);
    }
    // Velocity: u_{i+1} = M P M (A_sl(u_i) + dt f_i); M P M is symmetric.
    wbar = ubar;
    ops.project(wbar);
    Vec& gi = (*grad)[i];
    for (size_t e = 0; e < nf; ++e) gi[e] = dt * wbar[e] + 2.0 * m.r * f[i][e];
    std::fill(ubar_prev.begin(), ubar_prev.end(), 0.0);
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
