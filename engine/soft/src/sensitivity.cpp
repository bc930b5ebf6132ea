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
// sphere obstacles and the curvature of sphere contact. The objective's own map from
// frames to residuals (no simulation) is differentiated by central differences
// along each column's state perturbation (its error ~1e-10, far below the checks).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "pliant/soft/objective.h"
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

// The state perturbed along the tangent direction e = (dq, dc, dw) scaled by h.
SoftState perturbed(const SoftState& s, const Eigen::Ref<const VectorXd>& e, double h, int r) {
  SoftState t = s;
  t.q += h * e.head(r);
  t.c += h * e.segment<3>(r);
  t.R = rotation_exp(h * e.segment<3>(r + 3)) * s.R;
  return t;
}

}  // namespace

MatrixXd step_sensitivity(const Character& ch, const Environment& env, const SimParams& sim, const SoftState& start,
                          const SoftState& s, const MatrixXd& X1, const MatrixXd& X2, const MatrixXd& Q1,
                          const MatrixXd& dU, MatrixXd* dx_dz) {
  if (ch.rotation_strain) return MatrixXd();
  const Lattice& lat = ch.lattice;
  const int n = lat.nodes(), r = ch.basis.r(), dof = r + 6, nt = int(X1.cols());
  const double dt = sim.dt_s, idt2 = 1 / (dt * dt), eps = env.friction_eps_m_per_s * dt;
  const double beta = sim.modal_damping_s / dt;
  const MatrixXd& U = ch.basis.U;
  // The step's data, as reduced_step builds it from the start state.
  VectorXd x, xp, local, g_el;
  node_positions(ch, start, x);
  SoftState sp = start;
  sp.q = start.q_prev, sp.R = start.R_prev, sp.c = start.c_prev;
  node_positions(ch, sp, xp);
  StepTargets T;
  make_targets(ch, env, dt, x, xp, T);
  MatrixXd J(3 * n, dof), HJ(3 * n, dof), H(dof, dof), H_el, W(3 * n, nt);

  // Exact Hessian at the converged z_f.
  local_shape(ch, s.q, local);
  elastic_reduced(lat, ch.lame, local, ch.cubature, U, &g_el, &H_el);
  Matrix3d Sww = Matrix3d::Zero();
  MatrixXd Sqw = MatrixXd::Zero(r, 3);
  W.setZero();
  for (int j = 0; j < n; ++j) {
    const double m = lat.node_mass_kg[j];
    const Vector3d yj = s.R * local.segment<3>(3 * j), xj = yj + s.c;
    Vector3d G = m * idt2 * (xj - T.xt.segment<3>(3 * j));
    Matrix3d Hn = m * idt2 * Matrix3d::Identity();
    Matrix3d Gx = -2 * m * idt2 * Matrix3d::Identity();  // dG/dx_{f-1}
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
    J.block(3 * j, 0, 3, r).noalias() = s.R * U.middleRows(3 * j, 3);
    J.block<3, 3>(3 * j, r) = Matrix3d::Identity();
    J.block<3, 3>(3 * j, r + 3) = -cross_matrix(yj);
    HJ.middleRows(3 * j, 3).noalias() = Hn * J.middleRows(3 * j, 3);
    // Second derivatives of x_j(q, c, w) contracted with the node force G.
    Sww += 0.5 * (yj * G.transpose() + G * yj.transpose()) - G.dot(yj) * Matrix3d::Identity();
    for (int k = 0; k < r; ++k) Sqw.row(k) += J.block<3, 1>(3 * j, k).cross(G).transpose();
    W.middleRows(3 * j, 3).noalias() = Gx * X1.middleRows(3 * j, 3) + m * idt2 * X2.middleRows(3 * j, 3);
  }
  H.noalias() = J.transpose() * HJ;
  H.topLeftCorner(r, r) += H_el;
  H.topLeftCorner(r, r).diagonal() += beta * ch.basis.omega2;
  H.block<3, 3>(r + 3, r + 3) += Sww;
  H.block(0, r + 3, r, 3) += Sqw;
  H.block(r + 3, 0, 3, r) += Sqw.transpose();
  // Drag: the target moves by dt^2 F / (4 m) per face node, so G_j gets -F / 4 and
  // its derivatives through the face's area vector (x_{f-1}) and velocity.
  if (env.water) {
    const double dt_inv4 = 0.25 / dt;
    for (const auto& fc : lat.boundary_faces) {
      const Vector3d A = x.segment<3>(3 * fc[2]) - x.segment<3>(3 * fc[0]);
      const Vector3d B = x.segment<3>(3 * fc[3]) - x.segment<3>(3 * fc[1]);
      const Vector3d a = 0.5 * A.cross(B);
      Vector3d vel = Vector3d::Zero();
      for (int c = 0; c < 4; ++c) vel += dt_inv4 * (x.segment<3>(3 * fc[c]) - xp.segment<3>(3 * fc[c]));
      Matrix3d dFda, dFdU;
      drag_derivatives(env, a, vel, dFda, dFdU);
      // da = 0.5 (dA x B + A x dB) = 0.5 (-[B] dA + [A] dB)
      const Matrix3d Bx = 0.5 * cross_matrix(B), Ax = 0.5 * cross_matrix(A);
      MatrixXd dF = dFda * (-Bx * (X1.middleRows(3 * fc[2], 3) - X1.middleRows(3 * fc[0], 3)) +
                            Ax * (X1.middleRows(3 * fc[3], 3) - X1.middleRows(3 * fc[1], 3)));
      MatrixXd dv = MatrixXd::Zero(3, nt);
      for (int c = 0; c < 4; ++c) dv += dt_inv4 * (X1.middleRows(3 * fc[c], 3) - X2.middleRows(3 * fc[c], 3));
      dF.noalias() += dFdU * dv;
      for (int c = 0; c < 4; ++c) W.middleRows(3 * fc[c], 3) -= 0.25 * dF;
    }
  }
  MatrixXd rhs = J.transpose() * W;
  rhs.topRows(r) -= (beta * ch.basis.omega2).asDiagonal() * Q1;
  rhs.topRows(r) -= dU;
  MatrixXd S = -H.ldlt().solve(rhs);
  if (dx_dz) *dx_dz = std::move(J);
  return S;
}

MatrixXd sensitivity_jacobian(const Problem& p, const VectorXd& theta, VectorXd* r_out) {
  const Character& ch = *p.character;
  if (ch.rotation_strain) return MatrixXd();  // finite differences (optimizer.h)
  const Lattice& lat = ch.lattice;
  const int n = lat.nodes(), r = ch.basis.r(), nt = int(theta.size()), modes = p.dmp.modes;
  const double dt = p.sim.dt_s, a_max = max_activation_m(ch, p.dmp);

  SoftState s = initial_state(ch, p.start_offset_m, Vector3d::Zero(), dt);
  DmpState dmp = dmp_init(p.dmp);
  std::vector<DmpState> unit_dmp(nt, dmp);
  std::vector<VectorXd> unit_theta(nt, VectorXd::Zero(nt));
  for (int i = 0; i < nt; ++i) unit_theta[i][i] = 1;

  std::vector<SoftState> frames;
  std::vector<MatrixXd> sens;  // dz_f/dtheta per frame (dof x nt)
  frames.reserve(p.frames), sens.reserve(p.frames);
  MatrixXd X1 = MatrixXd::Zero(3 * n, nt), X2 = X1;  // dx/dtheta of frames f-1, f-2
  MatrixXd Q1 = MatrixXd::Zero(r, nt);               // dq/dtheta of frame f-1
  VectorXd u;
  MatrixXd dudt(r, nt), J;
  int unconverged = 0;

  for (int f = 0; f < p.frames; ++f) {
    const VectorXd y = dmp_step(p.dmp, theta, dt, dmp);
    control_force(ch, y, a_max, u);
    dudt.setZero();
    for (int i = 0; i < nt; ++i) {
      const VectorXd& yi = dmp_step(p.dmp, unit_theta[i], dt, unit_dmp[i]);
      for (int k = 0; k < std::min(modes, r); ++k) {
        const double th = std::tanh(y[k] / a_max);
        dudt(k, i) = ch.basis.omega2[k] * (1 - th * th) / ch.mode_scale[k] * yi[k];
      }
    }
    const SoftState start = s;
    StepStats st;
    reduced_step(ch, p.env, p.sim, u, s, &st);
    if (!st.converged) ++unconverged;
    MatrixXd S = step_sensitivity(ch, p.env, p.sim, start, s, X1, X2, Q1, dudt, &J);
    X2.swap(X1);
    X1.noalias() = J * S;
    Q1 = S.topRows(r);
    frames.push_back(s);
    sens.push_back(std::move(S));
  }

  // dr/dtheta = sum_f dr/dz_f dz_f/dtheta + dr/dtheta|direct: central differences of
  // the frames -> residuals map along each column, a perturbation of ~1e-5 cells.
  const VectorXd r0 = trajectory_residuals(p, frames, theta);
  MatrixXd Jr(r0.size(), nt);
  double radius = 0;
  for (int j = 0; j < n; ++j) radius = std::max(radius, ch.rest_local.segment<3>(3 * j).norm());
  std::vector<SoftState> fp(frames.size()), fm(frames.size());
  for (int i = 0; i < nt; ++i) {
    double scale = 1e-300;
    for (const MatrixXd& S : sens) {
      for (int k = 0; k < r; ++k) scale = std::max(scale, std::abs(S(k, i)) * ch.mode_scale[k]);
      scale = std::max({scale, S.col(i).segment<3>(r).norm(), S.col(i).segment<3>(r + 3).norm() * radius});
    }
    const double h = std::max(1e-5 * lat.cell_size_m / scale, 0.0);
    for (size_t f = 0; f < frames.size(); ++f) {
      fp[f] = perturbed(frames[f], sens[f].col(i), h, r);
      fm[f] = perturbed(frames[f], sens[f].col(i), -h, r);
      // Consistent previous states (the shuffle term reads them).
      if (f) {
        const SoftState &prev_p = fp[f - 1], &prev_m = fm[f - 1];
        fp[f].q_prev = prev_p.q, fp[f].R_prev = prev_p.R, fp[f].c_prev = prev_p.c;
        fm[f].q_prev = prev_m.q, fm[f].R_prev = prev_m.R, fm[f].c_prev = prev_m.c;
      }
    }
    const VectorXd rp = trajectory_residuals(p, fp, theta), rm = trajectory_residuals(p, fm, theta);
    Jr.col(i) = (rp - rm) / (2 * h);
    // Direct dependence: the effort block (the last nt residuals) is sqrt(w) theta.
    Jr(r0.size() - nt + i, i) += std::sqrt(p.obj.w_effort);
  }
  if (r_out) {
    *r_out = r0;
    if (unconverged > 0) r_out->setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  return Jr;
}

JacobianFn problem_jacobian(const Problem& p, const OptimizerSettings& s) {
  if (s.jacobian != JacobianKind::Sensitivity || p.character->rotation_strain) return {};
  const Problem* pp = &p;
  return [pp](const VectorXd& th, const VectorXd&) {
    MatrixXd J = sensitivity_jacobian(*pp, th);
    if (!J.allFinite()) J.resize(0, 0);  // finite differences instead
    return J;
  };
}

}  // namespace pliant::soft
