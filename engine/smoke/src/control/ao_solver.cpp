#include "ao_solver.h"

#include <cmath>

namespace pliant::smoke {

using control_detail::Vec;
using Series = std::vector<Vec>;

namespace {
double dot(const Series& a, const Series& b) {
  double s = 0;
  for (size_t t = 0; t < a.size(); ++t)
    for (size_t e = 0; e < a[t].size(); ++e) s += a[t][e] * b[t][e];
  return s;
}
void axpy(double alpha, const Series& x, Series& y) {
  for (size_t t = 0; t < x.size(); ++t)
    for (size_t e = 0; e < x[t].size(); ++e) y[t][e] += alpha * x[t][e];
}
}  // namespace

AoSolver::AoSolver(const ControlModel& m, control_detail::ForwardOps& ops)
    : m_(m), ops_(ops), T_(m.sim.frames) {
  const size_t C = ops.cells();
  rho_.assign(T_ + 1, Vec(C, 0.0));
  sub_.resize(T_);
  substeps_.assign(T_, 1);
  keyframe_of_.assign(T_ + 1, -1);
  for (size_t k = 0; k < m.keyframes.size(); ++k)
    if (m.keyframes[k].frame >= 0 && m.keyframes[k].frame <= T_) keyframe_of_[m.keyframes[k].frame] = int(k);
  lam_.assign(C, 0.0);
  lam_prev_.assign(C, 0.0);
  tmp_.assign(C, 0.0);
}

double AoSolver::evaluate(const Series& u, const Series& c, double beta, Series* grad, double* keyframe_error) {
  const double dt = ops_.dt();
  const size_t C = ops_.cells();
  for (size_t e = 0; e < C; ++e) rho_[0][e] = m_.initial_density[e];
  double kf = 0;
  for (int i = 0; i < T_; ++i) {
    const int S = ops_.density_substeps(u[i]);
    substeps_[i] = S;
    if (int(sub_[i].size()) < S) sub_[i].resize(S, Vec(C));
    Vec& r = rho_[i + 1];
    r = rho_[i];
    for (int s = 0; s < S; ++s) {
      sub_[i][s] = r;
      ops_.upwind_step(u[i], dt / S, sub_[i][s], r);
    }
    if (keyframe_of_[i + 1] >= 0) {
      const Keyframe& k = m_.keyframes[keyframe_of_[i + 1]];
      double s2 = 0;
      for (size_t e = 0; e < C; ++e) s2 += (r[e] - k.density[e]) * (r[e] - k.density[e]);
      kf += k.weight * s2;
    }
  }
  double reg = 0;
  for (int i = 0; i < T_; ++i)
    for (size_t e = 0; e < u[i].size(); ++e) reg += (u[i][e] - c[i][e]) * (u[i][e] - c[i][e]);
  if (keyframe_error) *keyframe_error = kf;
  if (grad) {
    std::fill(lam_.begin(), lam_.end(), 0.0);
    for (int i = T_ - 1; i >= 0; --i) {
      Vec& g = (*grad)[i];
      for (size_t e = 0; e < g.size(); ++e) g[e] = beta * (u[i][e] - c[i][e]);
      if (keyframe_of_[i + 1] >= 0) {
        const Keyframe& k = m_.keyframes[keyframe_of_[i + 1]];
        for (size_t e = 0; e < C; ++e) lam_[e] += 2.0 * k.weight * (rho_[i + 1][e] - k.density[e]);
      }
      const int S = substeps_[i];
      for (int s = S - 1; s >= 0; --s) {
        ops_.upwind_step_adjoint(u[i], dt / S, sub_[i][s], lam_, tmp_, g);
        lam_.swap(tmp_);
      }
    }
  }
  // Divergence penalty 0.5 w sum (net outflow)^2 and its gradient, in one pass
  // after the adjoint pass (which overwrites grad).
  double divj = 0;
  if (div_penalty > 0) {
    const MacGrid& g = ops_.grid();
    for (int i = 0; i < T_; ++i) {
      const double* ui = u[i].data();
      double* gi = grad ? (*grad)[i].data() : nullptr;
      for (int k = 0; k < g.n[2]; ++k)
        for (int j = 0; j < g.n[1]; ++j)
          for (int ii = 0; ii < g.n[0]; ++ii) {
            double d = 0;
            for (int a = 0; a < g.dim; ++a)
              d += ui[ops_.face_offset(a) + g.face_hi(a, ii, j, k)] - ui[ops_.face_offset(a) + g.face_lo(a, ii, j, k)];
            divj += d * d;
            if (!gi) continue;
            for (int a = 0; a < g.dim; ++a) {
              gi[ops_.face_offset(a) + g.face_hi(a, ii, j, k)] += div_penalty * d;
              gi[ops_.face_offset(a) + g.face_lo(a, ii, j, k)] -= div_penalty * d;
            }
          }
    }
  }
  return kf + 0.5 * beta * reg + 0.5 * div_penalty * divj;
}

AoStats AoSolver::solve(Series& u, const Series& c, double beta, int iterations) {
  AoStats st;
  Series g(T_), gn(T_), d(T_), un(T_);
  for (int i = 0; i < T_; ++i) g[i].assign(u[i].size(), 0.0), gn[i] = g[i], d[i] = g[i], un[i] = u[i];
  double J = evaluate(u, c, beta, &g);
  ++st.evaluations;
  st.j_before = J;
  // Fresh memory per solve: a resumed run (memory not checkpointed) then repeats an
  // uninterrupted one exactly. (Keeping pairs across solves, y corrected for the beta
  // change, gained ~10% keyframe error per ADMM iteration in a 64^2 x 40 trial.)
  std::vector<std::pair<Series, Series>> mem;  // (s, y) pairs
  std::vector<double> rho;
  for (int it = 0; it < iterations; ++it) {
    // Two-loop recursion: d = -H g.
    for (int i = 0; i < T_; ++i) d[i] = g[i];
    std::vector<double> alpha(mem.size());
    for (int k = int(mem.size()) - 1; k >= 0; --k) {
      alpha[k] = rho[k] * dot(mem[k].first, d);
      axpy(-alpha[k], mem[k].second, d);
    }
    double gamma;
    if (mem.empty()) {
      const double gg = std::sqrt(dot(g, g));
      if (gg == 0) break;
      gamma = 1.0 / std::max(gg, beta);  // first step: at most unit length, or 1/beta Newton on the prox term
      gamma = std::min(gamma, 1.0 / beta);
    } else {
      gamma = dot(mem.back().first, mem.back().second) / dot(mem.back().second, mem.back().second);
    }
    for (auto& v : d)
      for (double& x : v) x *= gamma;
    for (size_t k = 0; k < mem.size(); ++k) {
      const double b = rho[k] * dot(mem[k].second, d);
      axpy(alpha[k] - b, mem[k].first, d);
    }
    for (auto& v : d)
      for (double& x : v) x = -x;
    double gd = dot(g, d);
    if (!(gd < 0)) {  // not a descent direction: restart with steepest descent
      mem.clear(), rho.clear();
      for (int i = 0; i < T_; ++i)
        for (size_t e = 0; e < d[i].size(); ++e) d[i][e] = -g[i][e] / beta;
      gd = dot(g, d);
      if (!(gd < 0)) break;
    }
    double step = 1.0, Jn = J;
    bool ok = false;
    for (int ls = 0; ls < 12; ++ls) {
      for (int i = 0; i < T_; ++i)
        for (size_t e = 0; e < u[i].size(); ++e) un[i][e] = u[i][e] + step * d[i][e];
      Jn = evaluate(un, c, beta, &gn);
      ++st.evaluations;
      if (Jn <= J + 1e-4 * step * gd) {
        ok = true;
        break;
      }
      step *= 0.3;
    }
    if (ok && mem.empty() && step == 1.0) {
      // Expand while J keeps falling (un/gn hold the best point so far).
      Series ub = un, gb = gn;
      double Jb = Jn;
      for (int ex = 0; ex < 12; ++ex) {
        step *= 4.0;
        for (int i = 0; i < T_; ++i)
          for (size_t e = 0; e < u[i].size(); ++e) un[i][e] = u[i][e] + step * d[i][e];
        const double Je = evaluate(un, c, beta, &gn);
        ++st.evaluations;
        if (!(Je < Jb)) break;
        Jb = Je, ub = un, gb = gn;
      }
      un.swap(ub), gn.swap(gb);
      Jn = Jb;
    }
    if (!ok) {
      if (mem.empty()) break;  // steepest descent failed too: at a kink or converged
      mem.clear(), rho.clear();  // stale curvature across an upwind switch: restart
      continue;
    }
    Series sv(T_), yv(T_);
    for (int i = 0; i < T_; ++i) {
      sv[i].resize(u[i].size()), yv[i].resize(u[i].size());
      for (size_t e = 0; e < u[i].size(); ++e) sv[i][e] = un[i][e] - u[i][e], yv[i][e] = gn[i][e] - g[i][e];
    }
    const double sy = dot(sv, yv);
    if (sy > 1e-16) {
      mem.emplace_back(std::move(sv), std::move(yv));
      rho.push_back(1.0 / sy);
      if (mem.size() > 6) mem.erase(mem.begin()), rho.erase(rho.begin());
    }
    u.swap(un);
    g.swap(gn);
    J = Jn;
    ++st.steps;
  }
  st.j_after = evaluate(u, c, beta, nullptr, &st.keyframe_error);
  return st;
}

}  // namespace pliant::smoke
