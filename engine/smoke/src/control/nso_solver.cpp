#include "nso_solver.h"

#include <algorithm>
#include <cmath>
#include <omp.h>

namespace pliant::smoke {

using control_detail::Vec;

NsoSolver::NsoSolver(const ControlModel& m, control_detail::ForwardOps& ops)
    : m_(m), ops_(ops), T_(m.sim.frames), F_(ops.faces()) {}

SpacetimeMultigrid& NsoSolver::multigrid() {
  if (!mg_) {
    mg_ = std::make_unique<SpacetimeMultigrid>(SpacetimeGrid(ops_.grid(), T_));
    mg_->pre_sweeps = mg_->post_sweeps = 2;
    std::vector<double>().swap(xs_);  // candidate() is the fine level's x from now on
  }
  return *mg_;
}

double* NsoSolver::candidate() {
  if (mg_) return mg_->fine().x.data();
  xs_.resize(size_t(T_) * F_);
  return xs_.data();
}

size_t NsoSolver::bytes() const {
  size_t b = (mg_ ? mg_->bytes() : 0) + xs_.capacity() * sizeof(double);
  for (const Worker& w : workers_) b += (w.a.capacity() + w.b.capacity()) * sizeof(double);
  return b;  // (the workers' ForwardOps are not counted)
}

control_detail::ForwardOps& NsoSolver::worker_ops(int thread) {
  if (thread == 0) return ops_;
  Worker& w = workers_[thread];
  if (!w.ops) w.ops = std::make_unique<control_detail::ForwardOps>(m_, control_detail::kControlPressureTolerance);
  return *w.ops;
}

template <class Frame>
void NsoSolver::for_frames(Frame&& frame) {
  const size_t threads = size_t(std::max(1, omp_get_max_threads()));
  if (workers_.size() < threads) workers_.resize(threads);
  for (size_t k = 0; k < threads; ++k)
    if (workers_[k].a.size() != F_) workers_[k].a.assign(F_, 0.0), workers_[k].b.assign(F_, 0.0);
  // Frames are independent here: one fork/join per pass, each thread with its own
  // ForwardOps (their scratch is not shared); the operators' own loops inside run on one
  // thread (no nested parallelism), so results do not depend on the thread count.
#pragma omp parallel for schedule(dynamic) if (threads > 1 && T_ > 1)
  for (int t = 0; t < T_; ++t) {
    const int k = omp_get_thread_num();
    frame(t, worker_ops(k), workers_[k]);
  }
  for (size_t k = 1; k < workers_.size(); ++k) {
    control_detail::ForwardOps* o = workers_[k].ops.get();
    if (!o) continue;
    ops_.projections += o->projections, ops_.pressure_iterations += o->pressure_iterations;
    ops_.worst_pressure_residual = std::max(ops_.worst_pressure_residual, o->worst_pressure_residual);
    o->projections = o->pressure_iterations = 0;
  }
}

double NsoSolver::energy_flat(const double* x, const std::vector<Vec>& d, double beta) {
  const double dt = ops_.dt();
  frame_ef_.assign(T_, 0.0), frame_ed_.assign(T_, 0.0);
  for_frames([&](int t, control_detail::ForwardOps& ops, Worker& w) {
    const double* xt = x + size_t(t) * F_;
    if (t == 0) {
      std::fill(w.a.begin(), w.a.end(), 0.0);
    } else {
      std::copy(xt - F_, xt, w.b.begin());
      ops.advect_velocity(w.b, w.a);
    }
    double ef = 0, ed = 0;
    for (size_t f = 0; f < F_; ++f) {
      ef += (xt[f] - w.a[f]) * (xt[f] - w.a[f]);
      ed += (xt[f] - d[t][f]) * (xt[f] - d[t][f]);
    }
    frame_ef_[t] = ef, frame_ed_[t] = ed;
  });
  double ef = 0, ed = 0;
  for (int t = 0; t < T_; ++t) ef += frame_ef_[t], ed += frame_ed_[t];
  return m_.r * ef / (dt * dt) + 0.5 * beta * ed;
}

double NsoSolver::energy(const std::vector<Vec>& z, const std::vector<Vec>& d, double beta) {
  double* x = candidate();
  for (int t = 0; t < T_; ++t) std::copy(z[t].begin(), z[t].end(), x + size_t(t) * F_);
  return energy_flat(x, d, beta);
}

NsoStats NsoSolver::solve(std::vector<Vec>& z, const std::vector<Vec>& d, double beta, int vcycles, int lm_steps) {
  NsoStats st;
  const double dt = ops_.dt(), w = 2.0 * m_.r / (dt * dt);
  double E = energy(z, d, beta);
  st.e_before = E;
  if (projected_start) {
    // Start from the per-frame projection P d when it is better: the exact solution for
    // r -> 0 (no dynamics term), and a much better guess than the last z while beta
    // dominates 2r/dt^2, so fewer V-cycles reach the same residual. Built in candidate()
    // (no T*faces copy).
    double* x = candidate();
    for_frames([&](int t, control_detail::ForwardOps& ops, Worker& w) {
      w.b = d[t];
      ops.project(w.b);
      std::copy(w.b.begin(), w.b.end(), x + size_t(t) * F_);
    });
    const double Ep = energy_flat(x, d, beta);
    double ef = 0;
    for (int t = 0; t < T_; ++t) ef += frame_ef_[t];
    // E(z) >= beta/2 ||Pd - d||^2 for every divergence-free z (P d is the closest one),
    // so the optimum is at most the dynamics term r||f(Pd)||^2 below E(Pd).
    st.start_gap = Ep > 0 ? m_.r * ef / (dt * dt) / Ep : 0.0;
    if (Ep < E) {
      for (int t = 0; t < T_; ++t) std::copy(x + size_t(t) * F_, x + size_t(t + 1) * F_, z[t].begin());
      E = Ep;
      st.projected_start = true;
      st.skipped = st.start_gap < skip_gap;
    }
  }
  // vcycles == 0: the projected start alone (bench experiments; scenes ask for >= 1).
  NsoLevel* fine = vcycles > 0 && lm_steps > 0 && !st.skipped ? &multigrid().fine() : nullptr;
  for (int step = 0; step < lm_steps && vcycles > 0 && !st.skipped; ++step) {
    NsoLevel& L = *fine;
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
