// Spacetime LM with the physics-violation term and the adaptive DMP penalty (see
// spacetime.h).
#include "pliant/soft/spacetime.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>

namespace pliant::soft {

namespace {

// Body radius: metres per radian of a floating-frame rotation.
double body_radius(const Character& ch) {
  double L = 0;
  for (int j = 0; j < ch.lattice.nodes(); ++j) L = std::max(L, ch.rest_local.segment<3>(3 * j).norm());
  return std::max(L, 1e-6);
}

Eigen::Vector3d rotation_log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// DMP activations (saturated, metres) of theta for every frame: modes x frames.
Eigen::MatrixXd dmp_activations(const Problem& p, const Eigen::VectorXd& theta) {
  const double a_max = max_activation_m(*p.character, p.dmp);
  Eigen::MatrixXd a(p.dmp.modes, p.frames);
  DmpState d = dmp_init(p.dmp);
  for (int f = 0; f < p.frames; ++f) {
    const Eigen::VectorXd& y = dmp_step(p.dmp, theta, p.sim.dt_s, d);
    for (int k = 0; k < p.dmp.modes; ++k) a(k, f) = a_max * std::tanh(y[k] / a_max);
  }
  return a;
}

// Modal force of activations a (metres) on the controlled modes: omega^2 a / s.
Eigen::VectorXd activation_force(const Character& ch, const Eigen::VectorXd& a) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(ch.basis.r());
  for (int k = 0; k < std::min<int>(int(a.size()), ch.basis.r()); ++k)
    u[k] = ch.basis.omega2[k] * a[k] / ch.mode_scale[k];
  return u;
}

// State (q, R, c) of frame f in {-1, 0, 1, ..}: -1 and 0 are the fixed initial
// state's previous and current values, f >= 1 the unknowns.
struct FrameRef {
  const Eigen::VectorXd* q;
  const Eigen::Matrix3d* R;
  const Eigen::Vector3d* c;
};

FrameRef frame_ref(const SoftState& s0, const SpacetimeVars& v, int f) {
  if (f <= -1) return {&s0.q_prev, &s0.R_prev, &s0.c_prev};
  if (f == 0) return {&s0.q, &s0.R, &s0.c};
  const SoftState& s = v.frames[size_t(f - 1)];
  return {&s.q, &s.R, &s.c};
}

// One implicit step from frames f-2, f-1 under activations a; returns the state.
SoftState step_from(const Problem& p, const FrameRef& prev2, const FrameRef& prev1, const Eigen::VectorXd& a,
                    int f) {
  SoftState s;
  s.frame = f - 1;
  s.time_s = (f - 1) * p.sim.dt_s;
  s.q = *prev1.q, s.R = *prev1.R, s.c = *prev1.c;
  s.q_prev = *prev2.q, s.R_prev = *prev2.R, s.c_prev = *prev2.c;
  reduced_step(*p.character, p.env, p.sim, activation_force(*p.character, a), s);
  return s;
}

// z_f minus the stepped state, in metres.
Eigen::VectorXd violation(const Character& ch, double L, const FrameRef& z, const SoftState& stepped) {
  const int r = ch.basis.r();
  Eigen::VectorXd out(r + 6);
  for (int k = 0; k < r; ++k) out[k] = ((*z.q)[k] - stepped.q[k]) * ch.mode_scale[k];
  out.segment<3>(r) = L * rotation_log(*z.R * stepped.R.transpose());
  out.segment<3>(r + 3) = *z.c - stepped.c;
  return out;
}

// Keeps every frame's *_prev fields equal to the previous frame's values.
void link_frames(const SoftState& s0, double dt, SpacetimeVars& v) {
  for (size_t f = 0; f < v.frames.size(); ++f) {
    const SoftState& prev = f == 0 ? s0 : v.frames[f - 1];
    SoftState& s = v.frames[f];
    s.q_prev = prev.q, s.R_prev = prev.R, s.c_prev = prev.c;
    s.frame = int(f) + 1;
    s.time_s = (f + 1) * dt;
  }
}

SoftState start_state(const Problem& p) {
  return initial_state(*p.character, p.start_offset_m, Eigen::Vector3d::Zero(), p.sim.dt_s);
}

// The states of the rollout under v's activations (physics violation zero).
void project_states(const Problem& p, SpacetimeVars& v) {
  SoftState s = start_state(p);
  for (int f = 0; f < p.frames; ++f) {
    reduced_step(*p.character, p.env, p.sim, activation_force(*p.character, v.act.col(f)), s);
    v.frames[size_t(f)] = s;
  }
}

// Inverse right Jacobian of SO(3) at phi: d log(exp([phi]) exp([d])) / dd at d = 0.
Eigen::Matrix3d so3_right_jacobian_inverse(const Eigen::Vector3d& phi) {
  const double t = phi.norm();
  const Eigen::Matrix3d P = cross_matrix(phi);
  const double c = t < 1e-4 ? 1.0 / 12 + t * t / 720 : 1 / (t * t) - (1 + std::cos(t)) / (2 * t * std::sin(t));
  return Eigen::Matrix3d::Identity() + 0.5 * P + c * P * P;
}

// d x_j / d z for one frame state in spacetime's chart (q in metres via mode_scale,
// rotation exp([d / L]) R, translation): 3N x (r + 6).
void position_derivative(const Character& ch, double L, const SoftState& s, Eigen::MatrixXd& X) {
  const int n = ch.lattice.nodes(), r = ch.basis.r();
  Eigen::VectorXd local;
  local_shape(ch, s.q, local);
  X.resize(3 * n, r + 6);
  for (int j = 0; j < n; ++j) {
    for (int k = 0; k < r; ++k)
      X.block<3, 1>(3 * j, k) = s.R * ch.basis.U.block<3, 1>(3 * j, k) / ch.mode_scale[k];
    X.block<3, 3>(3 * j, r) = -cross_matrix(s.R * local.segment<3>(3 * j)) / L;
    X.block<3, 3>(3 * j, r + 3) = Eigen::Matrix3d::Identity();
  }
}

// Physics rows of frame f (fr = f + 1) from the exact step derivatives (sensitivity.cpp:
// step_sensitivity): columns z_{fr-1}, z_{fr-2}, a_f of violation(z_fr, step(...)) as
// (r + 6) x (2 (r + 6) + m); empty when the step has no exact derivative.
Eigen::MatrixXd exact_step_block(const Problem& p, double L, const SoftState& start, const SoftState& prev,
                                 const SoftState& stepped, const FrameRef& z) {
  const Character& ch = *p.character;
  // position_derivative is written for the linear map (dx/dq = R U): rotation-strain
  // steps keep the difference blocks.
  if (ch.rotation_strain) return Eigen::MatrixXd();
  const int r = ch.basis.r(), ns = r + 6, m = p.dmp.modes, k = 2 * ns + m, n = ch.lattice.nodes();
  Eigen::MatrixXd X1 = Eigen::MatrixXd::Zero(3 * n, k), X2 = X1, Q1 = Eigen::MatrixXd::Zero(r, k),
                  dU = Eigen::MatrixXd::Zero(r, k), Xs;
  position_derivative(ch, L, start, Xs);
  X1.leftCols(ns) = Xs;
  position_derivative(ch, L, prev, Xs);
  X2.middleCols(ns, ns) = Xs;
  for (int i = 0; i < r; ++i) Q1(i, i) = 1 / ch.mode_scale[i];
  for (int i = 0; i < std::min(m, r); ++i) dU(i, 2 * ns + i) = ch.basis.omega2[i] / ch.mode_scale[i];
  const Eigen::MatrixXd S = step_sensitivity(ch, p.env, p.sim, start, stepped, X1, X2, Q1, dU);
  if (S.rows() != ns || !S.allFinite()) return Eigen::MatrixXd();
  // violation = [(q_z - q) s ; L log(R_z R^T) ; c_z - c] with R = exp([dw]) R_stepped:
  // L log(A exp(-[dw])), A = R_z R_stepped^T, moves by -L Jr^-1(log A) dw.
  Eigen::MatrixXd D(ns, k);
  for (int i = 0; i < r; ++i) D.row(i) = -ch.mode_scale[i] * S.row(i);
  const Eigen::Matrix3d Jri = so3_right_jacobian_inverse(rotation_log(*z.R * stepped.R.transpose()));
  D.middleRows<3>(r) = -L * Jri * S.middleRows<3>(r + 3);
  D.middleRows<3>(r + 3) = -S.middleRows<3>(r);
  return D;
}

}  // namespace

int spacetime_state_size(const Problem& p) { return p.character->basis.r() + 6; }

int spacetime_unknowns(const Problem& p) {
  return p.frames * (spacetime_state_size(p) + p.dmp.modes) + p.dmp.parameters();
}

SpacetimeVars spacetime_from_rollout(const Problem& p, const Eigen::VectorXd& theta) {
  SpacetimeVars v;
  v.theta = theta;
  v.act = dmp_activations(p, theta);
  // Step with the activation force (equal to simulate()'s control force).
  SoftState s = start_state(p);
  for (int f = 0; f < p.frames; ++f) {
    reduced_step(*p.character, p.env, p.sim, activation_force(*p.character, v.act.col(f)), s);
    v.frames.push_back(s);
  }
  return v;
}

SpacetimeVars spacetime_apply(const Problem& p, const SpacetimeVars& v, const Eigen::VectorXd& dz) {
  const Character& ch = *p.character;
  const int r = ch.basis.r(), ns = r + 6, T = p.frames, m = p.dmp.modes;
  const double L = body_radius(ch);
  SpacetimeVars out = v;
  for (int f = 0; f < T; ++f) {
    SoftState& s = out.frames[size_t(f)];
    const auto d = dz.segment(f * ns, ns);
    for (int k = 0; k < r; ++k) s.q[k] += d[k] / ch.mode_scale[k];
    s.R = rotation_exp(d.segment<3>(r) / L) * s.R;
    s.c += d.segment<3>(r + 3);
  }
  for (int f = 0; f < T; ++f) out.act.col(f) += dz.segment(T * ns + f * m, m);
  out.theta += dz.tail(v.theta.size());
  link_frames(start_state(p), p.sim.dt_s, out);
  return out;
}

Eigen::VectorXd physics_violation(const Problem& p, const SpacetimeVars& v, int f) {
  const SoftState s0 = start_state(p);
  const int fr = f + 1;  // frames[f] is the state after step f + 1
  const SoftState stepped =
      step_from(p, frame_ref(s0, v, fr - 2), frame_ref(s0, v, fr - 1), v.act.col(f), fr);
  return violation(*p.character, body_radius(*p.character), frame_ref(s0, v, fr), stepped);
}

Eigen::VectorXd spacetime_residuals(const Problem& p, const SpacetimeVars& v, double w_physics, double w_dmp) {
  const int ns = spacetime_state_size(p), T = p.frames, m = p.dmp.modes;
  const Eigen::VectorXd task = trajectory_residuals(p, v.frames, v.theta);
  Eigen::VectorXd r(T * ns + T * m + task.size());
  const double sp = std::sqrt(w_physics), sd = std::sqrt(w_dmp);
  // Frames are independent given the unknowns: steps in parallel.
#pragma omp parallel for schedule(dynamic, 1)
  for (int f = 0; f < T; ++f) r.segment(f * ns, ns) = sp * physics_violation(p, v, f);
  const Eigen::MatrixXd a = dmp_activations(p, v.theta);
  for (int f = 0; f < T; ++f) r.segment(T * ns + f * m, m) = sd * (v.act.col(f) - a.col(f));
  r.tail(task.size()) = task;
  return r;
}

Eigen::MatrixXd spacetime_jacobian(const Problem& p, const SpacetimeVars& v, double w_physics, double w_dmp,
                                   double h, JacobianKind kind) {
  const Character& ch = *p.character;
  const int r = ch.basis.r(), ns = r + 6, T = p.frames, m = p.dmp.modes, P = int(v.theta.size());
  const int n = T * (ns + m) + P;
  const double L = body_radius(ch), sp = std::sqrt(w_physics), sd = std::sqrt(w_dmp);
  const SoftState s0 = start_state(p);
  const Eigen::VectorXd task0 = trajectory_residuals(p, v.frames, v.theta);
  const int nt = int(task0.size()), rows = T * (ns + m) + nt;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(rows, n);
  // A unit step of unknown `col` (only frame-state and activation columns).
  auto unit = [&](int col) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    e[col] = h;
    return e;
  };
  // Physics blocks: frame f's violation depends on z_f (no step needed), z_{f-1},
  // z_{f-2} and a_f: exact step derivatives (one step and one solve per frame), or
  // one step per column (finite differences).
#pragma omp parallel for schedule(dynamic, 1)
  for (int f = 0; f < T; ++f) {
    const int fr = f + 1;
    const SoftState base = step_from(p, frame_ref(s0, v, fr - 2), frame_ref(s0, v, fr - 1), v.act.col(f), fr);
    const Eigen::VectorXd r0 = violation(ch, L, frame_ref(s0, v, fr), base);
    Eigen::MatrixXd D;
    if (kind == JacobianKind::Sensitivity) {
      SoftState start = base;  // the step's start: z_{fr-1} with z_{fr-2} as previous
      const FrameRef a = frame_ref(s0, v, fr - 1), b = frame_ref(s0, v, fr - 2);
      start.q = *a.q, start.R = *a.R, start.c = *a.c;
      start.q_prev = *b.q, start.R_prev = *b.R, start.c_prev = *b.c;
      SoftState prev = start;
      prev.q = *b.q, prev.R = *b.R, prev.c = *b.c;
      D = exact_step_block(p, L, start, prev, base, frame_ref(s0, v, fr));
    }
    std::vector<int> cols;
    for (int g = std::max(1, fr - 2); g <= fr; ++g)
      for (int i = 0; i < ns; ++i) cols.push_back((g - 1) * ns + i);
    for (int k = 0; k < m; ++k) cols.push_back(T * ns + f * m + k);
    for (int col : cols) {
      const bool own = col >= f * ns && col < (f + 1) * ns;
      if (D.size() && !own) {
        // D's columns: z_{fr-1}, z_{fr-2}, a_f.
        const int dc = col >= T * ns ? 2 * ns + (col - T * ns - f * m)
                                     : (col / ns == fr - 2 ? 0 : ns) + col % ns;
        J.block(f * ns, col, ns, 1) = sp * D.col(dc);
        continue;
      }
      const SpacetimeVars vp = spacetime_apply(p, v, unit(col));
      const SoftState st =
          own ? base : step_from(p, frame_ref(s0, vp, fr - 2), frame_ref(s0, vp, fr - 1), vp.act.col(f), fr);
      J.block(f * ns, col, ns, 1) = sp * (violation(ch, L, frame_ref(s0, vp, fr), st) - r0) / h;
    }
  }
  // DMP blocks: identity in a, differences of DMP rollouts in theta (linear ODE, then tanh).
  for (int i = 0; i < T * m; ++i) J(T * ns + i, T * ns + i) = sd;
  const Eigen::MatrixXd a0 = dmp_activations(p, v.theta);
  for (int j = 0; j < P; ++j) {
    Eigen::VectorXd th = v.theta;
    const double ht = 1e-7 * std::max(1.0, std::abs(th[j]));
    th[j] += ht;
    const Eigen::MatrixXd a1 = dmp_activations(p, th);
    for (int f = 0; f < T; ++f) J.block(T * ns + f * m, T * (ns + m) + j, m, 1) = -sd * (a1.col(f) - a0.col(f)) / ht;
  }
  // Task blocks: every frame state and theta.
#pragma omp parallel for schedule(dynamic, 4)
  for (int col = 0; col < T * ns + P; ++col) {
    const bool is_theta = col >= T * ns;
    const int c = is_theta ? T * (ns + m) + (col - T * ns) : col;
    double step = h;
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    if (is_theta) step = 1e-7 * std::max(1.0, std::abs(v.theta[col - T * ns]));
    e[c] = step;
    const SpacetimeVars vp = spacetime_apply(p, v, e);
    J.block(T * (ns + m), c, nt, 1) = (trajectory_residuals(p, vp.frames, vp.theta) - task0) / step;
  }
  return J;
}

void spacetime_optimize(const Problem& p, const SpacetimeSettings& s, OptimizerState& st,
                        const IterationFn& on_iteration, SpacetimeReport* report, SpacetimeCarry* carry) {
  SpacetimeReport local;
  SpacetimeReport& rep = report ? *report : local;
  SpacetimeCarry local_carry;
  SpacetimeCarry& c = carry ? *carry : local_carry;
  const Character& ch = *p.character;
  const int ns = spacetime_state_size(p), T = p.frames, m = p.dmp.modes;
  const double a_max = max_activation_m(ch, p.dmp);
  if (st.theta.size() == 0) st.theta = initial_theta(p);
  auto resimulated = [&](const Eigen::VectorXd& th) {
    const Eigen::VectorXd r = residuals(p, th);
    return r.allFinite() ? 0.5 * r.squaredNorm() : std::numeric_limits<double>::infinity();
  };
  // A restored checkpoint: st holds the best theta and its objective, c the point.
  const bool restored = !c.vars.frames.empty();
  double best = restored ? st.objective : resimulated(st.theta);
  if (st.history.empty()) st.history.push_back(best);
  const double f_initial = st.history.front();
  st.objective = best;
  Eigen::VectorXd best_theta = st.theta;

  SpacetimeVars& v = c.vars;
  double& w_dmp = c.w_dmp;
  auto merit_of = [&](const SpacetimeVars& x, Eigen::VectorXd* res) {
    try {
      *res = spacetime_residuals(p, x, s.w_physics, w_dmp);
    } catch (const std::runtime_error&) {  // a step turned non-finite: reject
      return std::numeric_limits<double>::infinity();
    }
    rep.steps += T;
    return res->allFinite() ? 0.5 * res->squaredNorm() : std::numeric_limits<double>::infinity();
  };
  auto record = [&](const Eigen::VectorXd& res) {
    rep.merit.push_back(0.5 * res.squaredNorm());
    rep.physics_violation.push_back(res.head(T * ns).norm() / std::sqrt(s.w_physics * T));
    rep.dmp_mismatch.push_back(res.segment(T * ns, T * m).norm() / std::sqrt(w_dmp * T));
    rep.w_dmp.push_back(w_dmp);
  };
  Eigen::VectorXd& res = c.res;
  double& merit = c.merit;
  double& lambda = c.lambda;
  if (!restored) {
    v = spacetime_from_rollout(p, st.theta);
    w_dmp = s.w_dmp_initial;
    merit = merit_of(v, &res);
    record(res);
    rep.resimulated.push_back(best);
    lambda = s.lambda_initial;
    c.stopped = false;
  }
  while (st.iteration < s.max_iterations && !c.stopped) {
    if (best <= s.tolerance * f_initial) break;
    const Eigen::MatrixXd Jd = spacetime_jacobian(p, v, s.w_physics, w_dmp, s.fd_step_m, s.jacobian);
    const bool exact = s.jacobian == JacobianKind::Sensitivity && !ch.rotation_strain;  // one step + solve per frame
    for (int f = 0; f < T; ++f) rep.steps += exact ? 1 : 1 + std::min(f, 2) * ns + m;
    const Eigen::SparseMatrix<double> J = Jd.sparseView();
    const Eigen::SparseMatrix<double> JtJ = Eigen::SparseMatrix<double>(J.transpose()) * J;
    const Eigen::VectorXd g = J.transpose() * res;
    const double f0 = merit;
    bool accepted = false;
    for (int tries = 0; tries < 10 && !accepted; ++tries) {
      Eigen::SparseMatrix<double> A = JtJ;
      for (int i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += lambda * (JtJ.coeff(i, i) + 1e-9);
      Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
      if (ldlt.info() != Eigen::Success) {
        lambda *= 4;
        continue;
      }
      const Eigen::VectorXd dz = ldlt.solve(-g);
      SpacetimeVars vn = spacetime_apply(p, v, dz);
      if (s.project) {
        try {
          project_states(p, vn);
        } catch (const std::runtime_error&) {
          lambda *= 4;
          continue;
        }
      }
      Eigen::VectorXd rn;
      const double fn = merit_of(vn, &rn);
      if (fn < f0) {
        v = vn, res = rn, merit = fn, accepted = true;
        lambda = std::max(lambda / 3, 1e-9);
      } else {
        lambda *= 4;
      }
    }
    // Adaptive DMP penalty (Algorithm 6): when LM stalls at this weight, raise it so
    // the activations move back into the DMP's span; stop raising once the DMP
    // reproduces them.
    const double dmp_rms = res.segment(T * ns, T * m).norm() / std::sqrt(w_dmp * T);
    const bool stalled = !accepted || (f0 - merit) < s.stall * f0;
    if (stalled && w_dmp < s.w_dmp_max && dmp_rms > s.dmp_tolerance * a_max) {
      w_dmp = std::min(w_dmp * s.w_dmp_factor, s.w_dmp_max);
      merit = merit_of(v, &res);
      lambda = s.lambda_initial;
    }
    ++st.iteration;
    record(res);
    const double fr = resimulated(v.theta);
    rep.resimulated.push_back(fr);
    if (fr < best) best = fr, best_theta = v.theta;
    st.theta = best_theta;
    st.objective = best;
    st.lambda = lambda;
    st.history.push_back(best);
    st.step_kinds.push_back(accepted ? "spacetime" : "spacetime-rejected");
    st.evaluations = rep.steps / std::max(1, T) + int(rep.resimulated.size());
    // Before on_iteration: a checkpoint taken there must know the run ends here.
    c.stopped = !accepted && w_dmp >= s.w_dmp_max;
    if (on_iteration && !on_iteration(st)) break;
  }
}

}  // namespace pliant::soft
