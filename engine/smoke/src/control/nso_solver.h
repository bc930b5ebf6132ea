// NSO subproblem of the ADMM (Navier-Stokes optimisation; Pan & Manocha 2017):
//   min_z  E(z) = r sum_i ||(z_{i+1} - A(z_i, z_i)) / dt||^2 + (beta/2) sum_i ||z_i - d_i||^2,
//   s.t.   div z_i = 0,   z_0 = 0 (rest),   d = u + lambda (AO velocity plus dual),
// A = control_forward's semi-Lagrangian self-advection (Euler backtrace,
// ForwardOps::advect_velocity), so the forces f_i = (z_{i+1} - A z_i)/dt re-simulate z.
// The force's gradient part is not discounted here (E counts ||z_{i+1} - A z_i||^2, not
// its divergence-free part); the forces handed out are projected (admm_solver.cpp), so
// the reported control energy is <= the E minimised here.
// Levenberg-Marquardt around the spacetime FAS multigrid: each LM step linearises A
// at the current z (Picard: backtraces frozen, nso_advection_stencil.h), adds the
// damping (mu/2)||z - zbar||^2 and runs `vcycles` FAS V-cycles on the KKT system;
// the step is accepted when the true nonlinear E decreases, else mu grows and the
// step is retried (at most 3 tries), so E never increases.
// Threads: the per-frame work (projections of the start, energies) runs frame-parallel,
// one ForwardOps per thread and one fork/join per pass. The operators' own fine-grained
// loops cost more in fork/joins than they save on an oversubscribed machine (64^2 x 40
// NSO solve: 4 s on 1 thread, 61 s on 2 at load average 15). The multigrid has its own
// threshold (kSpacetimeOmpMinWork).
// Start: z = P d (per-frame projection) when its E is below the warm start's. With the
// scenes' small r (2r/dt^2 << beta) P d is nearly the solution, and one or two V-cycles
// then suffice (measured on circle-to-square 32^2 x 20: with 1 V-cycle per solve and no
// projected start LM rejected every step and ADMM stalled at E = 63; with it E = 11.5).
#pragma once
#include <memory>
#include <vector>

#include "control_forward_model.h"
#include "spacetime_multigrid.h"

namespace pliant::smoke {

struct NsoStats {
  double e_before = 0, e_after = 0;
  std::vector<double> vcycle_factors;  // residual ratio of each V-cycle of the accepted step
  int lm_steps = 0, rejected = 0;
  bool projected_start = false;  // started from P d (NsoSolver::projected_start)
  // Dynamics share r||f(Pd)||^2 / E(Pd) of the projected start (an upper bound on the
  // relative gain any divergence-free z can make over P d); -1 when not computed.
  double start_gap = -1;
  bool skipped = false;  // multigrid skipped (start_gap < skip_gap)
};

class NsoSolver {
 public:
  NsoSolver(const ControlModel& m, control_detail::ForwardOps& ops);
  // z (T frames, frames 1..T) is the warm start and receives the result.
  NsoStats solve(std::vector<control_detail::Vec>& z, const std::vector<control_detail::Vec>& d, double beta,
                 int vcycles, int lm_steps = 1);
  double energy(const std::vector<control_detail::Vec>& z, const std::vector<control_detail::Vec>& d,
                double beta);
  // Built on first use (a solve that does not skip it), so ADMM runs whose every solve
  // skips never hold it (~2.6 GB at 64^3 x 40).
  SpacetimeMultigrid& multigrid();
  // Bytes held by the solver (multigrid levels and scratch), for memory reports.
  size_t bytes() const;
  // Levenberg-Marquardt damping carried to the next solve (ControlState::nso_damping).
  double damping() const { return mu_; }
  void set_damping(double mu) { mu_ = mu; }
  // Try z = P d (per-frame projection of the target) as the start when its energy is lower.
  bool projected_start = true;
  // Skip the multigrid when the projected start's start_gap is below this (0: never).
  double skip_gap = 0;

 private:
  const ControlModel& m_;
  control_detail::ForwardOps& ops_;
  int T_;
  size_t F_;
  struct Worker {
    std::unique_ptr<control_detail::ForwardOps> ops;  // threads > 0 (thread 0: ops_)
    control_detail::Vec a, b;                         // one frame each
  };
  control_detail::ForwardOps& worker_ops(int thread);
  // frame(t, ops, worker) for t = 0..T-1, frame-parallel.
  template <class Frame>
  void for_frames(Frame&& frame);
  // E of the fine level's x (T*faces, frame-major): the candidate z without a copy.
  double energy_flat(const double* x, const std::vector<control_detail::Vec>& d, double beta);
  // T*faces doubles for a candidate z: the multigrid's fine x once it exists, else xs_.
  double* candidate();


  std::unique_ptr<SpacetimeMultigrid> mg_;  // null until the first multigrid solve
  std::vector<double> xs_;                  // candidate() while there is no multigrid
  std::vector<Worker> workers_;
  std::vector<double> frame_ef_, frame_ed_;  // per-frame energy terms (summed in order)
  double mu_ = 0;
};

}  // namespace pliant::smoke
