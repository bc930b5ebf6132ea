// The control forward model in double precision and its discrete adjoint
// (control.h: u_{i+1} = P(A_sl(u_i, u_i) + dt f_i), rho_{i+1} = A_up(rho_i, u_{i+1})).
//
// Own operators instead of advection.h's float ones, because the adjoint must be
// the exact transpose of what the forward computes (gradient check to 1e-5):
//  * A_sl: first-order (Euler) backtrace x_b = x - (dt/h) U(x) and bi/trilinear
//    sampling with mac_grid.h's layouts (clamped when closed, wrapped when periodic).
//    Its adjoint scatters with the same weights and adds the derivative of the sample
//    w.r.t. the backtrace position (dS/dx_b, zero where the position was clamped)
//    times dx_b/du = -(dt/h) * interpolation weights of U (McNamara et al. 2004).
//  * P: exact projection u - D^T (D D^T)^+ D u (CG to a tight tolerance from a zero
//    start, so P is a fixed symmetric operator and is its own adjoint).
//  * A_up: conservative upwind flux form; the sub-step count S is computed from
//    u_{i+1} in the forward pass and held fixed by the adjoint (piecewise-smooth
//    map; the upwind choice has zero measure of kinks).
// Obstacles: faces touching solid cells are masked (zeroed) before and after P.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "../mac_grid.h"
#include "../pressure_projection.h"
#include "pliant/smoke/control.h"

namespace pliant::smoke::control_detail {

using Vec = std::vector<double>;

struct TrajectoryD {
  std::vector<Vec> rho, u;     // T+1 frames
  std::vector<int> substeps;   // density sub-steps of step i (T entries)
};

class ForwardOps {
 public:
  ForwardOps(const ControlModel& m, double pressure_tolerance);

  const MacGrid& grid() const { return g_; }
  size_t faces() const { return faces_; }
  size_t cells() const { return g_.cells(); }
  size_t face_offset(int axis) const { return off_[axis]; }
  const FieldLayout& layout(int axis) const { return lay_[axis]; }
  bool is_wall_face(int axis, size_t local) const;
  double dt() const { return dt_; }

  // out = A_sl(u) (walls 0); out must not alias u.
  void advect_velocity(const Vec& u, Vec& out) const;
  // u_bar += (d A_sl(u) / d u)^T out_bar.
  void advect_velocity_adjoint(const Vec& u, const Vec& out_bar, Vec& u_bar) const;
  // u = M P M u (M: obstacle mask and walls). Symmetric.
  void project(Vec& u);
  // Sub-steps for the density: dt * max cell outflow / h <= 1.
  int density_substeps(const Vec& u) const;
  // q_out = q - (dt_sub/h) div(F), F = u * q_upwind.
  void upwind_step(const Vec& u, double dt_sub, const Vec& q, Vec& q_out) const;
  // Given q_out_bar: q_bar = (dq_out/dq)^T q_out_bar; u_bar += (dq_out/du)^T q_out_bar.
  void upwind_step_adjoint(const Vec& u, double dt_sub, const Vec& q, const Vec& q_out_bar, Vec& q_bar,
                           Vec& u_bar) const;
  void mask(Vec& u) const;
  double max_divergence(const Vec& u) const;  // 1/s
  // Projection statistics since construction (for metrics and tests).
  long projections = 0, pressure_iterations = 0;
  double worst_pressure_residual = 0;

  // Buffers of forward_d / objective_d that live across evaluations, so an L-BFGS
  // evaluation allocates nothing once they have their sizes (the per-evaluation
  // trajectory was 7-15% of the polish's samples in malloc/free/page faults).
  struct Scratch {
    TrajectoryD trajectory;                 // objective_d's forward trajectory
    Vec rho_tmp;                            // upwind ping-pong buffer
    Vec ubar, ubar_prev, wbar, rhobar, qbar;
    std::vector<Vec> substep_states;        // grows to the most density sub-steps seen
    std::vector<const double*> force_frames;  // the vector overloads' frame pointers
    std::vector<double*> grad_frames;
  };
  Scratch scratch;

 private:
  // Cell on the low / high side of face `local` of component `axis` (-1 at a closed
  // wall), from tables built once (the index arithmetic was half the run time).
  long lo_cell(int axis, size_t local) const { return lo_[off_[axis] + local]; }
  long hi_cell(int axis, size_t local) const { return hi_[off_[axis] + local]; }
  long compute_lo_cell(int axis, size_t local) const;
  long compute_hi_cell(int axis, size_t local) const;
  std::vector<int32_t> lo_, hi_;
  std::vector<int32_t> cell_faces_;   // per cell: global lo and hi face per axis (2*dim)
  mutable std::vector<double> flux_;  // per face scratch of the upwind step and its adjoint
  // advect_velocity_adjoint scatters: one buffer per fixed chunk of faces (not per
  // thread), summed in chunk order, so the result has the same bits on any number of
  // threads (atomics on doubles did not). touched_ = per chunk and component the
  // [first, last) local index written, so zeroing and summing stay near one pass.
  static constexpr int kAdjointChunks = 8;
  mutable std::vector<Vec> chunk_bar_;
  mutable std::array<std::array<std::array<long, 2>, 3>, kAdjointChunks> touched_{};

  MacGrid g_;
  double dt_;
  std::array<FieldLayout, 3> lay_;
  std::array<size_t, 4> off_{0, 0, 0, 0};
  size_t faces_ = 0;
  std::vector<uint8_t> face_mask_;  // 1 = forced to zero (walls, obstacle faces)
  bool has_obstacles_ = false;
  PoissonSolver poisson_;
  double tol_;
  Vec phi_, rhs_;
};

// Runs grids below `threshold` cells on one thread for its lifetime. Every OpenMP
// fork/join (also inside the Poisson solver) costs more than the work on small
// grids, and on an oversubscribed machine libgomp's spinning barriers make it far
// worse: measured on the 2-core build box under load 10, a 64^2 x 40 gradient took
// 0.5 s on 1 thread and 13.6 s on 2 (0.7 s with OMP_WAIT_POLICY=passive); 128^2 x
// 40: 2.6 s vs 24.6 s. Sixth session, at load ~3 (one core free): a 32^3 x 40
// evaluation 1.09 s on 1 thread, 0.61 s on 2 (1.79x, same bits), so 3D grids from 32^3
// run in parallel; 128^2 x 40 was 0.30 vs 0.20 s (1.5x) but stays serial: under load
// it is the case above.
inline constexpr size_t kControlParallelCells = size_t(1) << 15;
class SerialBelow {
 public:
  explicit SerialBelow(size_t cells, size_t threshold = kControlParallelCells);
  ~SerialBelow();
  SerialBelow(const SerialBelow&) = delete;
  SerialBelow& operator=(const SerialBelow&) = delete;

 private:
  int previous_ = 0;
};

// Forward simulation from rest with rho_0 = m.initial_density.
void forward_d(const ControlModel& m, ForwardOps& ops, const std::vector<Vec>& f, TrajectoryD& out);
// The same with f[i] pointing at frame i's faces() forces (no copy of a flat vector).
void forward_d(const ControlModel& m, ForwardOps& ops, const double* const* f, TrajectoryD& out);
// Keyframe term sum_k w_k ||rho_tk - rho*_k||^2 of a trajectory.
double keyframe_error_d(const ControlModel& m, const TrajectoryD& t);
// E(f) and, if grad, dE/df by the discrete adjoint.
double objective_d(const ControlModel& m, ForwardOps& ops, const std::vector<Vec>& f, std::vector<Vec>* grad);
// The same on frame pointers (f[i], grad[i]: faces() doubles each; grad may be null): the
// L-BFGS objective hands its flat x and gradient over without T x faces copies.
double objective_d(const ControlModel& m, ForwardOps& ops, const double* const* f, double* const* grad);

// Default projection tolerance of the control model (tight: the adjoint needs P symmetric).
inline constexpr double kControlPressureTolerance = 1e-10;

std::vector<Vec> to_double(const FaceSeries& f);
FaceSeries to_float(const std::vector<Vec>& f);

}  // namespace pliant::smoke::control_detail
