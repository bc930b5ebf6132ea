#include "nso_solver.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace pliant::smoke {

using control_detail::Vec;

NsoSolver::NsoSolver(const ControlModel& m, control_detail::ForwardOps& ops)
    : m_(m), ops_(ops), T_(m.sim.frames), F_(ops.faces()) {
  mg_ = std::make_unique<SpacetimeMultigrid>(SpacetimeGrid(ops.grid(), T_));
  mg_->pre_sweeps = mg_->post_sweeps = 2;
  a_.assign(F_, 0.0);
  b_.assign(F_, 0.0);
}

size_t NsoSolver::bytes() const { return mg_->bytes() + (a_.capacity() + b_.capacity()) * sizeof(double); }

double NsoSolver::energy_flat(const double* x, const std::vector<Vec>& d, double beta) {
  const control_detail::SerialBelow serial(ops_.cells());
  const double dt = ops_.dt();
  double ef = 0, ed = 0;
  for (int t = 0; t < T_; ++t) {
    const double* xt = x + size_t(t) * F_;
    if (t == 0) {
      std::fill(a_.begin(), a_.end(), 0.0);
    } else {
      std::copy(xt - F_, xt, b_.begin());
      ops_.advect_velocity(b_, a_);
    }
    for (size_t f = 0; f < F_; ++f) {
      ef += (xt[f] - a_[f]) * (xt[f] - a_[f]);
      ed += (xt[f] - d[t][f]) * (xt[f] - d[t][f]);
    }
  }
  return m_.r * ef / (dt * dt) + 0.5 * beta * ed;
}

double NsoSolver::energy(const std::vector<Vec>& z, const std::vector<Vec>& d, double beta) {
  const control_detail::SerialBelow serial(ops_.cells());
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
  NsoLevel& L = mg_->fine();
  if (projected_start) {
    // Start from the per-frame projection P d when it is better: the exact solution for
    // r -> 0 (no dynamics term), and a much better guess than the last z while beta
    // dominates 2r/dt^2, so fewer V-cycles reach the same residual. Built in the fine
    // level's x (no T*faces copy).
    std::optional<control_detail::SerialBelow> serial(std::in_place, ops_.cells());
    for (int t = 0; t < T_; ++t) {
      b_ = d[t];
      ops_.project(b_);
      std::copy(b_.begin(), b_.end(), L.x.begin() + size_t(t) * F_);
    }
    serial.reset();
    const double Ep = energy_flat(L.x.data(), d, beta);
    if (Ep < E) {
      for (int t = 0; t < T_; ++t) std::copy(L.x.begin() + size_t(t) * F_, L.x.begin() + size_t(t + 1) * F_, z[t].begin());
      E = Ep;
      st.projected_start = true;
    }
  }
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
      const double En = energy_flat(L.x.data(), d, beta);
      if (En <= E) {
        accepted = true;
        for (int t = 0; t < T_; ++t) std::copy(L.x.begin() + size_t(t) * F_, L.x.begin() + size_t(t + 1) * F_, z[t].begin());
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
