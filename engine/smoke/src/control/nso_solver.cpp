#include "nso_solver.h"

#include <algorithm>
#include <cmath>

namespace pliant::smoke {

using control_detail::Vec;

NsoSolver::NsoSolver(const ControlModel& m, control_detail::ForwardOps& ops)
    : m_(m), ops_(ops), T_(m.sim.frames), F_(ops.faces()) {
  mg_ = std::make_unique<SpacetimeMultigrid>(SpacetimeGrid(ops.grid(), T_));
  mg_->pre_sweeps = mg_->post_sweeps = 2;
  a_.assign(F_, 0.0);
}

double NsoSolver::energy(const std::vector<Vec>& z, const std::vector<Vec>& d, double beta) {
  const double dt = ops_.dt();
  double ef = 0, ed = 0;
  for (int t = 0; t < T_; ++t) {
    if (t == 0) std::fill(a_.begin(), a_.end(), 0.0);
    else ops_.advect_velocity(z[t - 1], a_);
    for (size_t f = 0; f < F_; ++f) {
      ef += (z[t][f] - a_[f]) * (z[t][f] - a_[f]);
      ed += (z[t][f] - d[t][f]) * (z[t][f] - d[t][f]);
    }
  }
  return m_.r * ef / (dt * dt) + 0.5 * beta * ed;
}

NsoStats NsoSolver::solve(std::vector<Vec>& z, const std::vector<Vec>& d, double beta, int vcycles, int lm_steps) {
  NsoStats st;
  const double dt = ops_.dt(), w = 2.0 * m_.r / (dt * dt);
  double E = energy(z, d, beta);
  st.e_before = E;
  if (projected_start) {
    // Start from the per-frame projection P d when it is better: the exact solution for
    // r -> 0 (no dynamics term), and a much better guess than the last z while beta
    // dominates 2r/dt^2, so fewer V-cycles reach the same residual.
    std::vector<Vec>& pd = pd_;
    pd.resize(T_);
    for (int t = 0; t < T_; ++t) {
      pd[t] = d[t];
      ops_.project(pd[t]);
    }
    const double Ep = energy(pd, d, beta);
    if (Ep < E) {
      for (int t = 0; t < T_; ++t) z[t] = pd[t];
      E = Ep;
      st.projected_start = true;
    }
  }
  NsoLevel& L = mg_->fine();
  std::vector<Vec> zn = z;
  for (int step = 0; step < lm_steps; ++step) {
    bool accepted = false;
    for (int attempt = 0; attempt < 3 && !accepted; ++attempt) {
      for (int t = 0; t < T_; ++t)
        for (size_t f = 0; f < F_; ++f) {
          const size_t e = t * F_ + f;
          L.zbar[e] = z[t][f];
          L.x[e] = z[t][f];
          L.F[e] = beta * d[t][f] + mu_ * z[t][f];
        }
      std::fill(L.G.begin(), L.G.end(), 0.0);
      // The multipliers start from zero on every solve: a warm start from the last
      // solve would be solver state outside the ADMM checkpoint (resume must repeat
      // the uninterrupted run), and d changes a lot between outer iterations anyway.
      std::fill(L.q.begin(), L.q.end(), 0.0);
      mg_->setup(dt, w, beta + mu_);
      double prev = L.residual();
      std::vector<double> factors;
      for (int c = 0; c < vcycles; ++c) {
        const double res = mg_->vcycle();
        factors.push_back(prev > 0 ? res / prev : 0.0);
        prev = res;
      }
      for (int t = 0; t < T_; ++t)
        for (size_t f = 0; f < F_; ++f) zn[t][f] = L.x[t * F_ + f];
      const double En = energy(zn, d, beta);
      if (En <= E) {
        accepted = true;
        z.swap(zn);
        E = En;
        st.vcycle_factors = factors;
        mu_ = mu_ * 0.25 < 1e-3 * w ? 0.0 : mu_ * 0.25;
      } else {
        ++st.rejected;
        mu_ = std::max(4.0 * mu_, 0.05 * w);
      }
    }
    if (!accepted) break;
    ++st.lm_steps;
  }
  st.e_after = E;
  return st;
}

}  // namespace pliant::smoke
