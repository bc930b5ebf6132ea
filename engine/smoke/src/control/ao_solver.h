// AO subproblem of the ADMM (advection optimisation; Pan & Manocha 2017, Sec. 3.3):
//   min_u  J(u) = sum_k w_k ||rho_{t_k}(u) - rho*_k||^2 + (beta/2) sum_i ||u_i - c_i||^2,
//   rho_{i+1} = A_up(rho_i, u_{i+1}),  rho_0 given,  c = z - lambda (NSO velocity minus dual).
// A_up is the conservative first-order upwind operator of control_forward (flux form,
// sub-stepped for positivity), not semi-Lagrangian, so density is conserved and does
// not pop. u is unconstrained (no divergence condition: that lives in NSO).
// Fixed-point iteration (the paper's Eq. 3.6): each outer step freezes the upwind
// directions and the sub-step counts at the current u (A_up is then bilinear in
// (rho, u), J smooth), and takes quasi-Newton steps on that model; the gradient comes
// from the adjoint of the density advection only (ForwardOps::upwind_step_adjoint),
// cheap next to the full-model adjoint the L-BFGS baseline needs. Steps use L-BFGS
// (two-loop recursion, memory 6) with an Armijo backtracking line search on the true
// J, and the directions are re-frozen after every accepted step, so `iterations`
// fixed-point steps are run, each one quasi-Newton step. Without curvature pairs the
// line search also expands the step (x4 while J keeps falling): the steepest-descent
// scale 1/|g| is far too short for this objective.
#pragma once
#include <vector>

#include "control_forward_model.h"

namespace pliant::smoke {

struct AoStats {
  double j_before = 0, j_after = 0, keyframe_error = 0;
  int steps = 0, evaluations = 0;
};

class AoSolver {
 public:
  AoSolver(const ControlModel& m, control_detail::ForwardOps& ops);
  // u (T frames, frames 1..T) is the warm start and receives the result.
  AoStats solve(std::vector<control_detail::Vec>& u, const std::vector<control_detail::Vec>& c, double beta,
                int iterations);
  // J and its gradient (grad may be null); also fills the density trajectory.
  double evaluate(const std::vector<control_detail::Vec>& u, const std::vector<control_detail::Vec>& c,
                  double beta, std::vector<control_detail::Vec>* grad, double* keyframe_error = nullptr);
  // Weight gamma of (gamma/2) sum_i ||h div u_i||^2 added to J (0 = the plain AO). The
  // term vanishes at ADMM consensus (u = z, div z = 0), so the solution set is unchanged;
  // it stops AO from fitting keyframes with compressive flows NSO cannot follow.
  double div_penalty = 0;
  // rho_0..rho_T of the last evaluate().
  const std::vector<control_detail::Vec>& density() const { return rho_; }

 private:
  const ControlModel& m_;
  control_detail::ForwardOps& ops_;
  int T_;
  std::vector<control_detail::Vec> rho_;               // T+1 frames
  std::vector<std::vector<control_detail::Vec>> sub_;  // per step: states before each sub-step
  std::vector<int> substeps_;
  std::vector<int> keyframe_of_;                       // frame -> keyframe index or -1
  control_detail::Vec lam_, lam_prev_, tmp_;
};

}  // namespace pliant::smoke
