// Exact rollout derivatives by forward sensitivities (objective.h:
// sensitivity_jacobian). Every step of a rollout is a converged minimization
//   z_f = argmin_z E(z; x_{f-1}, x_{f-2}, q_{f-1}, u_f(theta)),   z = (q, c, w),
// so by the implicit function theorem on its gradient g(z_f; ...) = 0
//   dz_f/dtheta = -H^{-1} (dg/dx_{f-1} dx_{f-1}/dtheta + dg/dx_{f-2} dx_{f-2}/dtheta
//                          + dg/dq_{f-1} dq_{f-1}/dtheta + dg/du du/dtheta),
// with H the exact Hessian at z_f in the chart R = exp([w]) R_f that reduced_step's
// Newton uses: J^T (M / dt^2 + contact + friction) J + U^T K U + damping + the map's
// curvature contracted with the node forces G_j (zero in Gauss-Newton; here
// sum_j sym(y_j G_j^T) - (G_j . y_j) I for w-w and (R U_jk) x G_j for q-w). The step's
// start positions enter through the inertial target (2 x - x_prev + dt^2 drag / m),
// the friction slip origin and the lagged friction normal force (mu k m depth). All
// theta columns share one LDLT per step. DMP activations are linear in theta (zero
// start, phase independent of theta), so dy_f/dtheta comes from the DMP run on the
// unit vectors. Kept constant (their derivatives dropped): the CCD planes' stiffness
// (active only for targets deeper than a quarter cell), the friction normal of
// sphere obstacles and the curvature of sphere contact. Rotation-strain coordinates:
// dx/dq = R Jq(q) (the map's Jacobian) in J, and the map's curvature contracted with
// the local nodal force dE_el/dl + R^T G (rotation_strain_curvature, the term the
// step's Newton adds too) in the q-q block. The objective's own map from
// frames to residuals (no simulation) is differentiated by central differences
// along each column's state perturbation (its error ~1e-10, far below the checks).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "pliant/soft/fem.h"
#include "pliant/soft/objective.h"
#include "pliant/soft/rotation_strain.h"
#include "serial_eigen.h"
#include "step_targets.h"

namespace pliant::soft {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

// dF/da and dF/dU of drag_force (environment.h) for area vector a and velocity U.
void drag_derivatives(const Environment& env, const Vector3d& a, const Vector3d& U, Matrix3d& dFda, Matrix3d& dFdU) {
  dFda.setZero(), dFdU.setZero();
  const double area = a.norm();
  if (area <= 0) return;
  const Vector3d n = a / area;
  const double rho = env.fluid_density_kg_per_m3, un = n.dot(U), speed = U.norm();
  // -rho/2 C_d max(n.U, 0)^2 a  (a = area n)
  if (un > 0) {
    const Vector3d dun_da = (U - un * n) / area;
    dFda += -0.5 * rho * env.drag_coefficient * (un * un * Matrix3d::Identity() + 2 * un * a * dun_da.transpose());
    dFdU += -rho * env.drag_coefficient * un * a * n.transpose();
  }
  // -rho/2 C_f |a| |U| U
  if (speed > 0) {
    dFda += -0.5 * rho * env.skin_coefficient * speed * U * n.transpose();
    dFdU += -0.5 * rho * env.skin_coefficient * area * (speed * Matrix3d::Identity() + U * U.transpose() / speed);
  }
}

// Buffers of one step's sensitivity, per thread and reused by every step and every
// Jacobian (sizes change only with the character or the parameter count), so a
// rollout's steps allocate nothing once the first Jacobian has sized them.
struct StepSensitivityWork {
  VectorXd x, xp, local, g_el, gl;
  SoftState prev;
  MatrixXd Jq, Tc;  // rotation strain: dlocal/dq, the map's curvature
  StepTargets T;
  MatrixXd J, HJ, H, H_el, Sqw, W, rhs, S;
  std::vector<Matrix3d> Gx;                  // dG_j/dx_{f-1} per node
  std::vector<Matrix3d> drag_a, drag_b, drag_u;  // per boundary face: dF/dA, dF/dB, dF/dv
  Eigen::LDLT<MatrixXd> ldlt;
};

StepSensitivityWork& step_sensitivity_work() {
  thread_local StepSensitivityWork w;
  return w;
}

// Column blocks of the n right-hand sides: fixed width, so every column sees the same
// products whatever the thread count (results do not depend on it), and threads only
// where the work (3N x k per step) pays for a fork/join.
constexpr int kColumnBlock = 8;
int column_threads(int threads, long rows, int columns) {
  const long work = rows * columns;
  if (threads <= 1 || columns <= kColumnBlock || work < 200000) return 1;
  return std::min(threads, (columns + kColumnBlock - 1) / kColumnBlock);
}

// The step's sensitivity into w.S ((r + 6) x k) and w.J (dx_f/dz_f); threads: how
// many the column blocks may use.
void step_sensitivity_into(const Character& ch, const Environment& env, const SimParams& sim, const SoftState& start,
                           const SoftState& s, const MatrixXd& X1, const MatrixXd& X2, const MatrixXd& Q1,
                           const MatrixXd& dU, int threads, StepSensitivityWork& w) {
  const Lattice& lat = ch.lattice;
  const int n = lat.nodes(), r = ch.basis.r(), dof = r + 6, nt = int(X1.cols());
  const double dt = sim.dt_s, idt2 = 1 / (dt * dt), eps = env.friction_eps_m_per_s * dt;
  const double beta = sim.modal_damping_s / dt;
  const MatrixXd& U = ch.basis.U;
  // The step's data, as reduced_step builds it from the start state.
  node_positions(ch, start, w.x);
  w.prev.q = start.q_prev, w.prev.R = start.R_prev, w.prev.c = start.c_prev;
  node_positions(ch, w.prev, w.xp);
  const VectorXd &x = w.x, &xp = w.xp, &local = w.local;
  const StepTargets& T = w.T;
  make_targets(ch, env, dt, x, xp, w.T);
  w.J.resize(3 * n, dof), w.HJ.resize(3 * n, dof), w.W.resize(3 * n, nt), w.rhs.resize(dof, nt), w.S.resize(dof, nt);
  w.Gx.resize(n);
  MatrixXd &J = w.J, &HJ = w.HJ, &H = w.H;

  // Exact Hessian at the converged z_f. Rotation strain: dlocal/dq = Jq(q) in place
  // of U, and the map's curvature below.
  const RotationStrain* rs = ch.rotation_strain.get();
  local_shape(ch, s.q, w.local, rs ? &w.Jq : nullptr);
  const MatrixXd& Jq = rs ? w.Jq : U;
  elastic_reduced(lat, ch.lame, local, ch.cubature, Jq, &w.g_el, &w.H_el);
  if (rs) {
    elastic_energy(lat, ch.lame, local, ch.cubature, &w.gl, nullptr);  // dE_el/dlocal
  }
  Matrix3d Sww = Matrix3d::Zero();
  w.Sqw.setZero(r, 3);
  for (int j = 0; j < n; ++j) {
    const double m = lat.node_mass_kg[j];
    const Vector3d yj = s.R * local.segment<3>(3 * j), xj = yj + s.c;
    Vector3d G = m * idt2 * (xj - T.xt.segment<3>(3 * j));
    Matrix3d Hn = m * idt2 * Matrix3d::Identity();
    Matrix3d& Gx = w.Gx[j];  // dG/dx_{f-1}
    Gx = -2 * m * idt2 * Matrix3d::Identity();
    if (touches(env, T, j, xj)) {
      node_environment(env, T, m, j, xj, eps, &G, &Hn);
      if (T.mu_lambda[j] > 0) {
        // Friction: slip origin x_{f-1} and lagged normal force mu k m depth(x_{f-1}).
        const Vector3d slip = xj - T.x_start.segment<3>(3 * j);
        Vector3d g1 = Vector3d::Zero();
        Matrix3d Hf = Matrix3d::Zero();
        friction_potential(T.mu_lambda[j], T.normal[j], slip, eps, &g1, &Hf);
        g1 /= T.mu_lambda[j];
        Vector3d dmu = Vector3d::Zero();
        const Vector3d xs = T.x_start.segment<3>(3 * j);
        for (const auto& o : env.obstacles) {
          Vector3d nrm;
          if (obstacle_depth(o, xs, &nrm) > 0) dmu -= env.friction * env.contact_stiffness_per_s2 * m * nrm;
        }
        Gx += -Hf + g1 * dmu.transpose();
      }
    }
    if (rs) w.gl.segment<3>(3 * j) += s.R.transpose() * G;  // + the node force, in local axes
    J.block(3 * j, 0, 3, r).noalias() = s.R * Jq.middleRows(3 * j, 3);
    J.block<3, 3>(3 * j, r) = Matrix3d::Identity();
    J.block<3, 3>(3 * j, r + 3) = -cross_matrix(yj);
    HJ.middleRows(3 * j, 3).noalias() = Hn * J.middleRows(3 * j, 3);
    // Second derivatives of x_j(q, c, w) contracted with the node force G.
    Sww += 0.5 * (yj * G.transpose() + G * yj.transpose()) - G.dot(yj) * Matrix3d::Identity();
    for (int k = 0; k < r; ++k) w.Sqw.row(k) += J.block<3, 1>(3 * j, k).cross(G).transpose();
  }
  H.resize(dof, dof);
  H.noalias() = J.transpose() * HJ;
  H.topLeftCorner(r, r) += w.H_el;
  H.topLeftCorner(r, r).diagonal() += beta * ch.basis.omega2;
  if (rs && r > 0) {
    // sum_j (dE/dlocal_j) . d2 local_j / dq2, the term Gauss-Newton drops (the step's
    // Newton adds the same one, rotation_strain_curvature).
    if (rs->reduced)
      rotation_strain_reduced_curvature(*rs->reduced, s.q, w.gl, w.Tc);
    else
      rotation_strain_curvature(lat, *rs, s.q, w.gl, w.Tc);
    H.topLeftCorner(r, r) += w.Tc;
  }
  H.block<3, 3>(r + 3, r + 3) += Sww;
  H.block(0, r + 3, r, 3) += w.Sqw;
  H.block(r + 3, 0, 3, r) += w.Sqw.transpose();
  w.ldlt.compute(H);
  // Drag: the target moves by dt^2 F / (4 m) per face node, so G_j gets -F / 4 and
  // its derivatives through the face's area vector (x_{f-1}) and velocity. Per face
  // dF = dF/dA dA + dF/dB dB + dF/dv dv, with A, B the face's diagonals.
  const double dt_inv4 = 0.25 / dt;
  const int faces = env.water ? int(lat.boundary_faces.size()) : 0;
  w.drag_a.resize(faces), w.drag_b.resize(faces), w.drag_u.resize(faces);
  for (int f = 0; f < faces; ++f) {
    const auto& fc = lat.boundary_faces[f];
    const Vector3d A = x.segment<3>(3 * fc[2]) - x.segment<3>(3 * fc[0]);
    const Vector3d B = x.segment<3>(3 * fc[3]) - x.segment<3>(3 * fc[1]);
    Vector3d vel = Vector3d::Zero();
    for (int c = 0; c < 4; ++c) vel += dt_inv4 * (x.segment<3>(3 * fc[c]) - xp.segment<3>(3 * fc[c]));
    Matrix3d dFda;
    drag_derivatives(env, 0.5 * A.cross(B), vel, dFda, w.drag_u[f]);
    // da = 0.5 (dA x B + A x dB) = 0.5 (-[B] dA + [A] dB)
    w.drag_a[f] = dFda * (-0.5 * cross_matrix(B));
    w.drag_b[f] = dFda * (0.5 * cross_matrix(A));
  }

  // The k right-hand sides, by column blocks: W = dG/dx_{f-1} X1 + dG/dx_{f-2} X2,
  // rhs = J^T W - (damping) Q1 - dU, S = -H^{-1} rhs.
  const int blocks = (nt + kColumnBlock - 1) / kColumnBlock;
  const Eigen::VectorXd& om2 = ch.basis.omega2;
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
  for (int b = 0; b < blocks; ++b) {
    const int c0 = b * kColumnBlock, nc = std::min(kColumnBlock, nt - c0);
    auto Wb = w.W.middleCols(c0, nc);
    for (int j = 0; j < n; ++j) {
      Wb.middleRows<3>(3 * j).noalias() = w.Gx[j] * X1.block(3 * j, c0, 3, nc);
      Wb.middleRows<3>(3 * j) += lat.node_mass_kg[j] * idt2 * X2.block(3 * j, c0, 3, nc);
    }
    // Fixed-capacity 3 x nc blocks: on the stack, no allocation per face.
    using Block3 = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kColumnBlock>;
    Block3 dA(3, nc), dB(3, nc), dv(3, nc), dF(3, nc);
    for (int f = 0; f < faces; ++f) {
      const auto& fc = lat.boundary_faces[f];
      dv.setZero();
      for (int c = 0; c < 4; ++c) dv += dt_inv4 * (X1.block(3 * fc[c], c0, 3, nc) - X2.block(3 * fc[c], c0, 3, nc));
      dA = X1.block(3 * fc[2], c0, 3, nc) - X1.block(3 * fc[0], c0, 3, nc);
      dB = X1.block(3 * fc[3], c0, 3, nc) - X1.block(3 * fc[1], c0, 3, nc);
      dF.noalias() = w.drag_a[f] * dA;
      dF.noalias() += w.drag_b[f] * dB;
      dF.noalias() += w.drag_u[f] * dv;
      for (int c = 0; c < 4; ++c) Wb.middleRows<3>(3 * fc[c]) -= 0.25 * dF;
    }
    auto rb = w.rhs.middleCols(c0, nc);
    rb.noalias() = J.transpose() * Wb;
    rb.topRows(r) -= (beta * om2).asDiagonal() * Q1.middleCols(c0, nc);
    rb.topRows(r) -= dU.middleCols(c0, nc);
    auto Sb = w.S.middleCols(c0, nc);
    Sb.noalias() = w.ldlt.solve(rb);
    Sb = -Sb;
  }
}

}  // namespace

MatrixXd step_sensitivity(const Character& ch, const Environment& env, const SimParams& sim, const SoftState& start,
                          const SoftState& s, const MatrixXd& X1, const MatrixXd& X2, const MatrixXd& Q1,
                          const MatrixXd& dU, MatrixXd* dx_dz) {
  SerialEigenProducts serial;
  StepSensitivityWork& w = step_sensitivity_work();
  const int threads = column_threads(serial.threads, 3L * ch.lattice.nodes(), int(X1.cols()));
  step_sensitivity_into(ch, env, sim, start, s, X1, X2, Q1, dU, threads, w);
  if (dx_dz) *dx_dz = w.J;
  return w.S;
}

namespace {

// Buffers of one Jacobian (rollout frames, per-frame sensitivities, the DMP run on the
// unit vectors), per thread and reused by the next Jacobian of the same size.
struct JacobianWork {
  std::vector<SoftState> frames;
  std::vector<MatrixXd> sens;  // dz_f/dtheta per frame (dof x nt)
  std::vector<DmpState> unit_dmp;
  std::vector<VectorXd> unit_theta;
  MatrixXd X1, X2, Q1, dudt, unit_y;
  VectorXd u;
  SoftState s, start;
};

JacobianWork& jacobian_work() {
  thread_local JacobianWork w;
  return w;
}

// frames perturbed along column i of the sensitivities (t = z + h dz/dtheta_i), with
// consistent previous states (the shuffle term reads them); out keeps its buffers.
void perturbed_frames(const std::vector<SoftState>& frames, const std::vector<MatrixXd>& sens, int i, double h, int r,
                      std::vector<SoftState>& out) {
  out.resize(frames.size());
  for (size_t f = 0; f < frames.size(); ++f) {
    SoftState& t = out[f];
    t = frames[f];
    const auto e = sens[f].col(i);
    t.q += h * e.head(r);
    t.c += h * e.segment<3>(r);
    t.R = rotation_exp(h * e.segment<3>(r + 3)) * frames[f].R;
    if (f) t.q_prev = out[f - 1].q, t.R_prev = out[f - 1].R, t.c_prev = out[f - 1].c;
  }
}

}  // namespace

namespace {

// The rollout half of the pass: frames[f] is the state after step f + 1; returns how
// many steps did not converge. The buffers of `frames` are reused.
int rollout_frames(const Problem& p, const VectorXd& theta, std::vector<SoftState>& frames) {
  const Character& ch = *p.character;
  const double dt = p.sim.dt_s, a_max = max_activation_m(ch, p.dmp);
  JacobianWork& w = jacobian_work();
  SoftState& s = w.s;
  s = initial_state(ch, p.start_offset_m, Vector3d::Zero(), dt);
  DmpState dmp = dmp_init(p.dmp);
  frames.resize(p.frames);
  int unconverged = 0;
  for (int f = 0; f < p.frames; ++f) {
    control_force(ch, dmp_step(p.dmp, theta, dt, dmp), a_max, w.u);
    StepStats st;
    reduced_step(ch, p.env, p.sim, w.u, s, &st);
    if (!st.converged) ++unconverged;
    frames[f] = s;
  }
  return unconverged;
}

// The sensitivity half: dr/dtheta from a rollout's frames (rollout_frames), the same
// arithmetic on the same states as when interleaved with the steps, so the same bits.
MatrixXd jacobian_from_frames(const Problem& p, const VectorXd& theta, const std::vector<SoftState>& frames,
                              VectorXd* r0_out) {
  const Character& ch = *p.character;
  const Lattice& lat = ch.lattice;
  const int n = lat.nodes(), r = ch.basis.r(), nt = int(theta.size()), modes = p.dmp.modes;
  const int F = p.frames, mr = std::min(modes, r);
  const double dt = p.sim.dt_s, a_max = max_activation_m(ch, p.dmp);
  const SerialEigenProducts serial;
  const int threads = column_threads(serial.threads, 3L * n, nt);

  JacobianWork& w = jacobian_work();
  StepSensitivityWork& sw = step_sensitivity_work();
  w.start = initial_state(ch, p.start_offset_m, Vector3d::Zero(), dt);
  DmpState dmp = dmp_init(p.dmp);
  w.unit_dmp.resize(nt);
  w.unit_theta.resize(nt);
  for (int i = 0; i < nt; ++i) {
    w.unit_dmp[i] = dmp;
    w.unit_theta[i].setZero(nt);
    w.unit_theta[i][i] = 1;
  }
  w.sens.resize(F);
  w.X1.setZero(3 * n, nt), w.X2.setZero(3 * n, nt);  // dx/dtheta of frames f-1, f-2
  w.Q1.setZero(r, nt);                                // dq/dtheta of frame f-1
  w.dudt.resize(r, nt), w.unit_y.resize(mr, nt);

  for (int f = 0; f < F; ++f) {
    const VectorXd& y = dmp_step(p.dmp, theta, dt, dmp);
    // dy/dtheta: the DMP (linear in theta) run on the unit vectors.
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
    for (int i = 0; i < nt; ++i) w.unit_y.col(i) = dmp_step(p.dmp, w.unit_theta[i], dt, w.unit_dmp[i]).head(mr);
    w.dudt.setZero();
    for (int k = 0; k < mr; ++k) {
      const double th = std::tanh(y[k] / a_max);
      w.dudt.row(k) = (ch.basis.omega2[k] * (1 - th * th) / ch.mode_scale[k]) * w.unit_y.row(k);
    }
    const SoftState& start = f ? frames[f - 1] : w.start;
    step_sensitivity_into(ch, p.env, p.sim, start, frames[f], w.X1, w.X2, w.Q1, w.dudt, threads, sw);
    w.X2.swap(w.X1);
    const int blocks = (nt + kColumnBlock - 1) / kColumnBlock;
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
    for (int b = 0; b < blocks; ++b) {
      const int c0 = b * kColumnBlock, nc = std::min(kColumnBlock, nt - c0);
      w.X1.middleCols(c0, nc).noalias() = sw.J * sw.S.middleCols(c0, nc);
    }
    w.Q1 = sw.S.topRows(r);
    w.sens[f] = sw.S;
  }

  // dr/dtheta = sum_f dr/dz_f dz_f/dtheta + dr/dtheta|direct: central differences of
  // the frames -> residuals map along each column, a perturbation of ~1e-5 cells.
  const VectorXd r0 = trajectory_residuals(p, frames, theta);
  MatrixXd Jr(r0.size(), nt);
  double radius = 0;
  for (int j = 0; j < n; ++j) radius = std::max(radius, ch.rest_local.segment<3>(3 * j).norm());
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    thread_local std::vector<SoftState> fp, fm;
#pragma omp for schedule(static)
    for (int i = 0; i < nt; ++i) {
      double scale = 1e-300;
      for (int f = 0; f < F; ++f) {
        const MatrixXd& S = w.sens[f];
        for (int k = 0; k < r; ++k) scale = std::max(scale, std::abs(S(k, i)) * ch.mode_scale[k]);
        scale = std::max({scale, S.col(i).segment<3>(r).norm(), S.col(i).segment<3>(r + 3).norm() * radius});
      }
      const double h = std::max(1e-5 * lat.cell_size_m / scale, 0.0);
      perturbed_frames(frames, w.sens, i, h, r, fp);
      perturbed_frames(frames, w.sens, i, -h, r, fm);
      const VectorXd rp = trajectory_residuals(p, fp, theta), rm = trajectory_residuals(p, fm, theta);
      Jr.col(i) = (rp - rm) / (2 * h);
      // Direct dependence: the effort block (the last nt residuals) is sqrt(w) theta.
      Jr(r0.size() - nt + i, i) += std::sqrt(p.obj.w_effort);
    }
  }
  if (r0_out) *r0_out = r0;
  return Jr;
}

}  // namespace

MatrixXd sensitivity_jacobian(const Problem& p, const VectorXd& theta, VectorXd* r_out) {
  const SerialEigenProducts serial;
  JacobianWork& w = jacobian_work();
  const int unconverged = rollout_frames(p, theta, w.frames);
  MatrixXd J = jacobian_from_frames(p, theta, w.frames, r_out);
  if (r_out && unconverged > 0) r_out->setConstant(std::numeric_limits<double>::quiet_NaN());
  return J;
}

JacobianFn problem_jacobian(const Problem& p, const OptimizerSettings& s) {
  if (s.jacobian != JacobianKind::Sensitivity) return {};
  const Problem* pp = &p;
  return [pp](const VectorXd& th, const VectorXd&) {
    MatrixXd J = sensitivity_jacobian(*pp, th);
    if (!J.allFinite()) J.resize(0, 0);  // finite differences instead
    return J;
  };
}

ResidualJacobianFn problem_residual_jacobian(const Problem& p, const OptimizerSettings& s) {
  if (s.jacobian != JacobianKind::Sensitivity || !s.fused_trials) return {};
  const Problem* pp = &p;
  ResidualJacobianFn f = [pp](const VectorXd& th, VectorXd& r) { return sensitivity_jacobian(*pp, th, &r); };
  // The two halves apart: a trial that is rejected never pays for its sensitivities.
  // Each trial owns its frames (60 small states on the spider), so several may wait.
  f.deferred = [pp](const VectorXd& th, VectorXd& r) -> DeferredJacobian {
    auto frames = std::make_shared<std::vector<SoftState>>();
    const int unconverged = rollout_frames(*pp, th, *frames);
    r = trajectory_residuals(*pp, *frames, th);
    if (unconverged > 0) {
      r.setConstant(std::numeric_limits<double>::quiet_NaN());
      return [] { return MatrixXd(); };
    }
    return [pp, th, frames] { return jacobian_from_frames(*pp, th, *frames, nullptr); };
  };
  return f;
}

}  // namespace pliant::soft
