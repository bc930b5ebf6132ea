// Reduced and full implicit Euler steps (see simulator.h); the character setup is in
// character.cpp, the per-step contact targets in step_targets.cpp.
#include "pliant/soft/simulator.h"

#include "pliant/soft/cubature.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "serial_eigen.h"
#include "step_targets.h"

namespace pliant::soft {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

}  // namespace

SoftState initial_state(const Character& ch, const Vector3d& offset, const Vector3d& v0, double dt) {
  SoftState s;
  s.q = VectorXd::Zero(ch.basis.r());
  s.q_prev = s.q;
  s.c = ch.rest_com + offset;
  s.c_prev = s.c - dt * v0;
  return s;
}

Matrix3d rotation_exp(const Vector3d& w) {
  const double a = w.norm();
  if (a < 1e-300) return Matrix3d::Identity();
  return Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

namespace {

// x = R local(q) + c per node; local is a buffer.
void place_local(const Character& ch, const VectorXd& local, const Matrix3d& R, const Vector3d& c, VectorXd& x) {
  if (x.size() != local.size()) x.resize(local.size());
  for (int j = 0; j < ch.lattice.nodes(); ++j) x.segment<3>(3 * j) = R * local.segment<3>(3 * j) + c;
}

void positions_of(const Character& ch, const VectorXd& q, const Matrix3d& R, const Vector3d& c, VectorXd& local,
                  VectorXd& x) {
  local_shape(ch, q, local);
  place_local(ch, local, R, c, x);
}

// Buffers of one reduced step, reused by every step of the thread (sizes only change
// with the character), so the playback loop allocates nothing.
struct StepWork {
  StepTargets T;
  VectorXd x, xp, local, q_t, q, qn, g, d, g_el, gq, b, gl;
  MatrixXd H, H_el, Lm, ULm, Jrs, JH, MJ, Tc, Hgn, Hkin;
  Eigen::Matrix<double, 3, Eigen::Dynamic> J;
  Eigen::LDLT<MatrixXd> ldlt;
  // Full rotation-strain map: the last step's start shape local(q) with q and the
  // map's id; the next step's q_prev is that q, so its shape is copied, not
  // re-evaluated (one map evaluation per frame; the same bits).
  std::uint64_t prev_map = 0;
  VectorXd prev_q, prev_local;
};

StepWork& step_work() {
  thread_local StepWork w;
  return w;
}

}  // namespace

void node_positions(const Character& ch, const SoftState& s, VectorXd& x) {
  thread_local VectorXd local;
  positions_of(ch, s.q, s.R, s.c, local, x);
}

Vector3d centre_of_mass(const Character& ch, const SoftState& s) {
  // Modes are M-orthogonal to translation and Xbar is centred (the rotation-strain
  // reconstruction is centred explicitly), so the COM is c.
  (void)ch;
  return s.c;
}

void reduced_step(const Character& ch, const Environment& env, const SimParams& sp, const VectorXd& u,
                  SoftState& s, StepStats* stats, const VectorXd* nodal_force) {
  const Lattice& lat = ch.lattice;
  const int n = lat.nodes(), r = ch.basis.r(), dof = r + 6;
  const double dt = sp.dt_s, idt2 = 1.0 / (dt * dt), eps = env.friction_eps_m_per_s * dt;
  const MatrixXd& U = ch.basis.U;
  const VectorXd& om2 = ch.basis.omega2;
  const bool rs = ch.rotation_strain != nullptr;
  const SerialEigenProducts serial;  // small products: Eigen's own threads cost more (serial_eigen.h)
  StepWork& w = step_work();
  const std::uint64_t map_id = (rs && !ch.rotation_strain->reduced) ? ch.rotation_strain->id : 0;
  positions_of(ch, s.q, s.R, s.c, w.local, w.x);
  if (map_id != 0 && w.prev_map == map_id && w.prev_q.size() == s.q_prev.size() && w.prev_q == s.q_prev)
    place_local(ch, w.prev_local, s.R_prev, s.c_prev, w.xp);
  else
    positions_of(ch, s.q_prev, s.R_prev, s.c_prev, w.prev_local, w.xp);  // prev_local: scratch
  if (map_id != 0) {
    w.prev_map = map_id;
    w.prev_q = s.q;
    w.prev_local = w.local;
  }
  StepTargets& T = w.T;
  make_targets(ch, env, dt, w.x, w.xp, T);
  if (nodal_force)
    for (int j = 0; j < n; ++j) T.xt.segment<3>(3 * j) += dt * dt * nodal_force->segment<3>(3 * j) / lat.node_mass_kg[j];
  w.q_t = s.q;
  const VectorXd& q_t = w.q_t;
  const double beta = sp.modal_damping_s / dt;

  w.q = s.q;
  VectorXd& q = w.q;
  Matrix3d R = s.R;
  Vector3d c = s.c;
  if (w.Lm.rows() != 3 * n) w.Lm.resize(3 * n, 3);
  if (w.J.cols() != dof) w.J.resize(3, dof);
  VectorXd& local = w.local;

  bool curvature_on = false;
  // The curvature term is computed once per step (where it turns on) and then kept:
  // it only shapes the Newton direction (the gradient is exact), and z moves little
  // within a step; recomputing it every iteration was half of the playback time.
  bool curvature_fresh = false;
  // Full rotation-strain map: its Jacobian (a 3r-column solve and a per-mode scatter
  // over every Gauss point) is evaluated at the step's first point only and kept for
  // the Hessian (elastic, kinetic and contact blocks); the gradient stays exact
  // through the adjoint (rotation_strain_vjp: one 3-column solve). A line search that
  // fails on the kept Hessian refreshes it. Reduced map and linear basis: every point.
  const bool lag_jacobian = rs && !ch.rotation_strain->reduced && r > 0;
  bool jacobian_stale = true, hessian_at_point = true;
  // Total energy at (q, R, c); with g/H also the gradient and Gauss-Newton Hessian in
  // (dq, dc, dw). Jq = dlocal/dq: U, or the rotation-strain Jacobian.
  auto energy = [&](const VectorXd& q_, const Matrix3d& R_, const Vector3d& c_, VectorXd* g, MatrixXd* H) {
    const bool fresh_jacobian = rs && g && (!lag_jacobian || jacobian_stale);
    if (g) hessian_at_point = !lag_jacobian || fresh_jacobian;
    const bool adjoint_gradient = lag_jacobian && g && !fresh_jacobian;
    local_shape(ch, q_, local, fresh_jacobian ? &w.Jrs : nullptr);
    const MatrixXd& Jq = (rs && g) ? w.Jrs : U;
    // E_el is translation invariant: the local (centred) shape gives the same energy.
    double e;
    if (adjoint_gradient) {
      e = elastic_energy(lat, ch.lame, local, ch.cubature, &w.gl, nullptr);  // nodal; H_el kept
    } else {
      e = elastic_reduced(lat, ch.lame, local, ch.cubature, Jq, g ? &w.g_el : nullptr, H ? &w.H_el : nullptr);
      if (fresh_jacobian && lag_jacobian) jacobian_stale = false;
    }
    e += 0.5 * beta * (q_ - q_t).dot(om2.cwiseProduct(q_ - q_t)) - u.dot(q_);
    Vector3d gc = Vector3d::Zero(), gw = Vector3d::Zero();
    if (g) {
      w.b.setZero(3 * n);  // R^T dE/dx per node, for the modal part
      if (H) {
        H->setZero(dof, dof);
        H->topLeftCorner(r, r) = w.H_el;
        if (rs) {
          // Kinetic Gauss-Newton block Jq^T M Jq / dt^2 (U^T M U = I for the linear map).
          if (!adjoint_gradient) {
            if (w.MJ.rows() != 3 * n || w.MJ.cols() != r) w.MJ.resize(3 * n, r);
            for (int j = 0; j < n; ++j) w.MJ.middleRows<3>(3 * j) = lat.node_mass_kg[j] * Jq.middleRows<3>(3 * j);
            if (w.Hkin.rows() != r || w.Hkin.cols() != r) w.Hkin.resize(r, r);
            w.Hkin.noalias() = idt2 * (Jq.transpose() * w.MJ);
          }
          H->topLeftCorner(r, r) += w.Hkin;
          H->topLeftCorner(r, r).diagonal() += beta * om2;
        } else {
          H->topLeftCorner(r, r).diagonal() += idt2 * VectorXd::Ones(r) + beta * om2;
        }
      }
    }
    Matrix3d inertia = Matrix3d::Zero();
    for (int j = 0; j < n; ++j) {
      const double m = lat.node_mass_kg[j];
      const Vector3d y = R_ * local.segment<3>(3 * j);
      const Vector3d xj = y + c_;
      const Vector3d d = xj - T.xt.segment<3>(3 * j);
      e += 0.5 * m * idt2 * d.squaredNorm();
      Vector3d gj = m * idt2 * d;
      Matrix3d Hj = Matrix3d::Zero();
      const bool env_active = touches(env, T, j, xj);
      if (env_active) e += node_environment(env, T, m, j, xj, eps, g ? &gj : nullptr, H ? &Hj : nullptr);
      if (!g) continue;
      w.b.segment<3>(3 * j) += R_.transpose() * gj;
      gc += gj;
      gw += y.cross(gj);
      if (H) {
        const Matrix3d Y = cross_matrix(y);
        inertia += m * idt2 * Y.transpose() * Y;
        // Kinetic coupling q-w: sum m/dt^2 (R Jq_j)^T (-[y]x) = -Jq^T Lm R^T / dt^2 with
        // block j of Lm = m_j [l_j]x (since R^T [R l]x = [l]x R^T); one product below.
        w.Lm.block<3, 3>(3 * j, 0) = m * cross_matrix(local.segment<3>(3 * j));
        if (env_active) {
          if (r > 0) w.J.leftCols(r).noalias() = R_.lazyProduct(Jq.middleRows(3 * j, 3));
          w.J.block<3, 3>(0, r) = Matrix3d::Identity();
          w.J.block<3, 3>(0, r + 3) = -Y;
          w.JH.noalias() = w.J.transpose().lazyProduct(Hj);
          H->noalias() += w.JH.lazyProduct(w.J);
        }
      }
    }
    if (g) {
      g->resize(dof);
      if (r > 0 && adjoint_gradient) {
        w.gl += w.b;  // dE/dlocal (elastic + kinetic + environment); also the curvature's g
        rotation_strain_vjp(lat, *ch.rotation_strain, q_, w.gl, w.gq);
        g->head(r) = w.gq + beta * om2.cwiseProduct(q_ - q_t) - u;
      } else if (r > 0) {
        w.gq.noalias() = Jq.transpose() * w.b;
        g->head(r) = w.gq + w.g_el + beta * om2.cwiseProduct(q_ - q_t) - u;
      }
      g->segment<3>(r) = gc;
      g->segment<3>(r + 3) = gw;
    }
    if (H && rs && r > 0 && curvature_on && !curvature_fresh) {
      // Exact Hessian: add sum_j (dE/dl_j) . d2l_j/dq2 (the map's curvature), which
      // Gauss-Newton drops; it matters when the elastic force is large (the linear
      // convergence of plain Gauss-Newton then needs hundreds of iterations). Computed
      // once per step, from its second iteration on (closed form per sample, about one
      // Jacobian's cost): RS playback 1.2x faster than turning it on after eight.
      if (!adjoint_gradient) {
        elastic_energy(lat, ch.lame, local, ch.cubature, &w.gl, nullptr);
        w.gl += w.b;
      }
      if (ch.rotation_strain->reduced)
        rotation_strain_reduced_curvature(*ch.rotation_strain->reduced, q_, w.gl, w.Tc);
      else
        rotation_strain_curvature(lat, *ch.rotation_strain, q_, w.gl, w.Tc);
      curvature_fresh = true;
    }
    if (H && rs && r > 0 && curvature_fresh) H->topLeftCorner(r, r) += w.Tc;
    if (H) {
      if (r > 0) {
        w.ULm.noalias() = Jq.transpose() * w.Lm;
        H->block(0, r + 3, r, 3).noalias() -= idt2 * w.ULm.lazyProduct(R_.transpose());
      }
      H->block<3, 3>(r, r) += ch.mass_kg * idt2 * Matrix3d::Identity();
      H->block<3, 3>(r + 3, r + 3) += inertia;
      H->block(r + 3, 0, 3, r) = H->block(0, r + 3, r, 3).transpose();
    }
    return e;
  };

  StepStats st;
  VectorXd& g = w.g;
  MatrixXd& H = w.H;
  VectorXd& d = w.d;
  double e = energy(q, R, c, &g, &H);
  const double size_scale = lat.cell_size_m;
  double radius = 0;
  for (int j = 0; j < n; ++j) radius = std::max(radius, ch.rest_local.segment<3>(3 * j).norm());
  for (int it = 0; it < sp.max_newton; ++it) {
    w.ldlt.compute(H);
    d = w.ldlt.solve(g);
    d = -d;
    if (curvature_fresh && r > 0 && (!d.allFinite() || g.dot(d) >= 0 || w.ldlt.vectorD().minCoeff() <= 0)) {
      // The curvature term made H indefinite: Gauss-Newton step instead.
      w.Hgn = H;
      w.Hgn.topLeftCorner(r, r) -= w.Tc;
      w.ldlt.compute(w.Hgn);
      d = w.ldlt.solve(g);
      d = -d;
    }
    if (!d.allFinite() || g.dot(d) >= 0) d = -g / (H.diagonal().maxCoeff() + 1e-300);  // fall back to gradient
    if (sp.newton_decrement_stop > 0 && std::abs(g.dot(d)) < sp.newton_decrement_stop * std::max(1.0, std::abs(e))) {
      ++st.newton_iterations;  // opt-in: the energy cannot confirm a smaller step
      st.converged = true;
      break;
    }
    double alpha = 1, e_new = e;
    VectorXd& qn = w.qn;
    Matrix3d Rn;
    Vector3d cn;
    bool accepted = false;
    for (int ls = 0; ls < 30; ++ls) {
      qn = q + alpha * d.head(r);
      cn = c + alpha * d.segment<3>(r);
      Rn = rotation_exp(alpha * d.segment<3>(r + 3)) * R;
      e_new = energy(qn, Rn, cn, nullptr, nullptr);
      if (e_new <= e + 1e-4 * alpha * g.dot(d)) {
        accepted = true;
        break;
      }
      alpha *= 0.5;
    }
    ++st.newton_iterations;
    // Step size in metres: modal amplitudes scaled by their largest node displacement.
    double step = alpha * (d.segment<3>(r).norm() + d.segment<3>(r + 3).norm() * radius);
    for (int k = 0; k < r; ++k) step = std::max(step, alpha * std::abs(d[k]) * ch.mode_scale[k]);
    st.final_step = step;
    if (!accepted && !hessian_at_point) {
      // The kept Jacobian's Hessian gave no decrease: rebuild it here and retry.
      jacobian_stale = true;
      e = energy(q, R, c, &g, &H);
      continue;
    }
    if (!accepted) {
      st.converged = std::abs(g.dot(d)) < 1e-12 * std::max(1.0, std::abs(e));
      break;
    }
    q = qn, R = Rn, c = cn;
    // Re-orthonormalize R against drift.
    Eigen::JacobiSVD<Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
    R = svd.matrixU() * svd.matrixV().transpose();
    if (rs && it >= 1) curvature_on = true;
    // Converged: nothing after the loop reads e, g or H, so the accepted point's
    // gradient and Hessian (one of the ~3-11 per step) are not evaluated.
    if (step < sp.newton_tol * size_scale) {
      st.converged = true;
      break;
    }
    e = energy(q, R, c, &g, &H);
  }
  // Good enough when the last step moved less than 1e-5 cells (quasi-Newton
  // iterations converge linearly; the strict tolerance is for validation runs).
  if (!st.converged && st.final_step < 1e-5 * size_scale) st.converged = true;
  if (!q.allFinite() || !c.allFinite() || !R.allFinite())
    throw std::runtime_error("soft: non-finite state at frame " + std::to_string(s.frame + 1) +
                             " (field q/c/R); reduce dt_s or the contact stiffness");
  s.q_prev = s.q, s.R_prev = s.R, s.c_prev = s.c;
  s.q = q, s.R = R, s.c = c;
  s.frame += 1;
  s.time_s += dt;
  if (stats) *stats = st;
}

void full_step(const Character& ch, const Environment& env, const SimParams& sp, const VectorXd& f, VectorXd& x,
               VectorXd& x_prev, StepStats* stats) {
  const Lattice& lat = ch.lattice;
  const int n = lat.nodes();
  const double dt = sp.dt_s, idt2 = 1.0 / (dt * dt), eps = env.friction_eps_m_per_s * dt;
  StepTargets T;
  make_targets(ch, env, dt, x, x_prev, T);
  VectorXd y = x;
  auto energy = [&](const VectorXd& z, VectorXd* g, Eigen::SparseMatrix<double>* H) {
    double e = elastic_energy(lat, ch.lame, z, CellWeights{}, g, H);
    if (f.size()) {
      e -= f.dot(z);
      if (g) *g -= f;
    }
    std::vector<Eigen::Triplet<double>> trip;
    for (int j = 0; j < n; ++j) {
      const double m = lat.node_mass_kg[j];
      const Vector3d xj = z.segment<3>(3 * j), d = xj - T.xt.segment<3>(3 * j);
      e += 0.5 * m * idt2 * d.squaredNorm();
      Vector3d gj = m * idt2 * d;
      Matrix3d Hj = m * idt2 * Matrix3d::Identity();
      if (touches(env, T, j, xj)) e += node_environment(env, T, m, j, xj, eps, &gj, &Hj);
      if (g) g->segment<3>(3 * j) += gj;
      if (H)
        for (int a = 0; a < 3; ++a)
          for (int b2 = 0; b2 < 3; ++b2) trip.emplace_back(3 * j + a, 3 * j + b2, Hj(a, b2));
    }
    if (H) {
      Eigen::SparseMatrix<double> D(3 * n, 3 * n);
      D.setFromTriplets(trip.begin(), trip.end());
      *H += D;
    }
    return e;
  };
  StepStats st;
  VectorXd g;
  Eigen::SparseMatrix<double> H;
  double e = energy(y, &g, &H);
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> llt;
  for (int it = 0; it < sp.max_newton; ++it) {
    VectorXd d;
    double shift = 0;
    for (int tries = 0; tries < 8; ++tries) {
      Eigen::SparseMatrix<double> A = H;
      if (shift > 0)
        for (int j = 0; j < n; ++j)
          for (int a = 0; a < 3; ++a) A.coeffRef(3 * j + a, 3 * j + a) += shift * lat.node_mass_kg[j] * idt2;
      llt.compute(A);
      if (llt.info() == Eigen::Success) {
        d = -llt.solve(g);
        if (d.allFinite() && g.dot(d) < 0) break;
      }
      shift = shift == 0 ? 1e-3 : shift * 10;
      d.resize(0);
    }
    if (d.size() == 0) d = -g;
    double alpha = 1, e_new = e;
    bool accepted = false;
    VectorXd yn;
    for (int ls = 0; ls < 30; ++ls) {
      yn = y + alpha * d;
      e_new = energy(yn, nullptr, nullptr);
      if (e_new <= e + 1e-4 * alpha * g.dot(d)) {
        accepted = true;
        break;
      }
      alpha *= 0.5;
    }
    ++st.newton_iterations;
    st.final_step = alpha * d.cwiseAbs().maxCoeff();
    if (!accepted) break;
    y = yn;
    e = energy(y, &g, &H);
    if (st.final_step < sp.newton_tol * lat.cell_size_m) {
      st.converged = true;
      break;
    }
  }
  if (!y.allFinite()) throw std::runtime_error("soft: non-finite full state (field x)");
  x_prev = x;
  x = y;
  if (stats) *stats = st;
}

}  // namespace pliant::soft
