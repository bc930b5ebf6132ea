// Rotation-strain map (rotation_strain.h): the adjoint products, (dx/dz)^T g by one
// 3-column solve and its derivative in z (the curvature term of the exact Hessian).
#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <stdexcept>

#include "pliant/soft/fem.h"
#include "pliant/soft/rotation_strain.h"
#include "rotation_strain_workspace.h"

namespace pliant::soft {

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Scalars of the left Jacobian J(v) = I + a [v]x + b [v]x^2 and of its derivative
// along d: dJ[d] = al (v.d) [v]x + a [d]x + be (v.d) [v]x^2 + b ([d]x [v]x + [v]x [d]x),
// al = a'(t)/t, be = b'(t)/t (series below t = 0.1: the closed forms cancel).
struct JacobianScalars {
  double a, b, al, be;
};

JacobianScalars jacobian_scalars(double t2) {
  JacobianScalars k;
  if (t2 < 1e-2) {
    const double t4 = t2 * t2, t6 = t4 * t2;
    k.a = 0.5 - t2 / 24 + t4 / 720 - t6 / 40320;
    k.b = 1.0 / 6 - t2 / 120 + t4 / 5040 - t6 / 362880;
    k.al = -1.0 / 12 + t2 / 180 - t4 / 6720 + t6 / 453600;
    k.be = -1.0 / 60 + t2 / 1260 - t4 / 60480 + t6 / 4989600;
  } else {
    const double t = std::sqrt(t2), s = std::sin(t), c = std::cos(t);
    k.a = (1 - c) / t2;
    k.b = (t - s) / (t2 * t);
    k.al = (t * s - 2 * (1 - c)) / (t2 * t2);
    k.be = ((1 - c) / (t2 * t) - 3 * (t - s) / (t2 * t2)) / t;
  }
  return k;
}

// The reconstruction's adjoint: lambda = L^-1 P^T g (3 columns of n, in w.X), with
// P^T g = g - mass_fraction (sum_j g_j) per coordinate; the map is evaluated at z
// first (per-sample E, J, F). Shared by the vjp and the curvature.
const double* adjoint_multipliers(RsWork& w, const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                                  const Eigen::VectorXd& g, const RsEval*& ev) {
  ev = &rs_evaluate(w, lat, rs, z);
  const int n = rs.nodes;
  w.ensure(w.B, n, 3);
  double* b = static_cast<double*>(w.B->x);
  for (int s = 0; s < 3; ++s) {
    double sum = 0;
    for (int j = 0; j < n; ++j) sum += g[3 * j + s];
    for (int j = 0; j < n; ++j) b[size_t(s) * size_t(n) + size_t(j)] = g[3 * j + s] - rs.mass_fraction[j] * sum;
  }
  rs_solve(w, *rs.factor, w.B, &w.X, &w.Y, &w.E);
  return static_cast<const double*>(w.X->x);
}

// A cell's multipliers Lc(s, a) = lambda(ids[a], s), gathered once for its 8 samples;
// grad lambda at sample q is Lc G_q.
Eigen::Matrix<double, 3, 8> adjoint_cell(const double* lam, int n, const std::array<int, 8>& ids) {
  Eigen::Matrix<double, 3, 8> Lc;
  for (int a = 0; a < 8; ++a)
    for (int s = 0; s < 3; ++s) Lc(s, a) = lam[size_t(s) * size_t(n) + size_t(ids[a])];
  return Lc;
}

Vector3d axial2(const Matrix3d& A) { return Vector3d(A(2, 1) - A(1, 2), A(0, 2) - A(2, 0), A(1, 0) - A(0, 1)); }


}  // namespace

void rotation_strain_vjp(const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                         const Eigen::VectorXd& g, Eigen::VectorXd& out) {
  if (!rs.factor || z.size() != rs.r || lat.nodes() != rs.nodes || g.size() != 3 * rs.nodes)
    throw std::invalid_argument("rotation_strain_vjp: sizes do not match");
  RsWork& w = rs_work();
  const int n = rs.nodes, r = rs.r, ncell = int(lat.cells.size());
  const auto& G = gauss_shape_gradients(lat.cell_size_m);
  const double vol = rs.sample_volume;
  const RsEval* ev = nullptr;
  const double* lam = adjoint_multipliers(w, lat, rs, z, g, ev);
  // <dF_k, Lam> = (J w_k) . axial(Lam F^T) + <s_k, E^T Lam> ([u]x : A = u . axial),
  // and with w_k, s_k the skew/symmetric parts of H_k = grad U_k this is <H_k, T>,
  // T = [J^T axial(Lam F^T)]x / 2 + sym(E^T Lam); sum_i vol <H_ik, T_i> = U_k . t with
  // t the nodal scatter of vol T_i G_i^T (one gemv with U instead of rot, strain).
  w.t.setZero(3 * n);
  for (int e = 0; e < ncell; ++e) {
    const auto& ids = lat.cells[e];
    Eigen::Matrix<double, 3, 8> Tc = Eigen::Matrix<double, 3, 8>::Zero();
    const Eigen::Matrix<double, 3, 8> Lc = adjoint_cell(lam, n, ids);
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * e + q;
      const Matrix3d Lam = Lc * G[q];
      const Vector3d ax = ev->Js[i].transpose() * axial2(Lam * ev->Fs[i].transpose());
      const Matrix3d A2 = ev->Es[i].transpose() * Lam;
      const Matrix3d T = 0.5 * (cross_matrix(ax) + A2 + A2.transpose());
      Tc.noalias() += T * G[q].transpose();
    }
    for (int a = 0; a < 8; ++a) w.t.segment<3>(3 * ids[a]) += vol * Tc.col(a);
  }
  if (out.size() != r) out.resize(r);
  out.noalias() = rs.U.transpose() * w.t;
}

void rotation_strain_curvature(const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                               const Eigen::VectorXd& g, Eigen::MatrixXd& curvature) {
  if (!rs.factor || z.size() != rs.r || lat.nodes() != rs.nodes || g.size() != 3 * rs.nodes)
    throw std::invalid_argument("rotation_strain_curvature: sizes do not match");
  RsWork& w = rs_work();
  const int n = rs.nodes, r = rs.r, ncell = int(lat.cells.size());
  const auto& G = gauss_shape_gradients(lat.cell_size_m);
  const double vol = rs.sample_volume;
  const RsEval* ev = nullptr;
  const double* lam = adjoint_multipliers(w, lat, rs, z, g, ev);
  // d/dz_a of <dF_k, Lam> (Lam fixed: the solve does not depend on z), closed form:
  //   (dJ[w_a] w_k) . ax1 + (J w_k) . axial(Lam dF_a^T) + <s_k, -E^T [J w_a]x Lam>,
  // ax1 = axial(Lam F^T), dF_a = [J w_a]x F + E s_a. Every term is linear in (w_a, s_a),
  // so per sample three small matrices map them to the factors of w_k (w.Yc) and s_k
  // (w.Bc), contracted by two products at the end:
  //   dJ[d]^T ax1 = Ym d, Ym = (be v x (v x ax1) - al v x ax1) v^T + a [ax1]x - b ([v]x [ax1]x + [v x ax1]x);
  //   axial(Lam dF_a^T) = -(tr(A1) I - A1^T) J w_a + Q s_a  (A1 = Lam F^T; M^T [u]x + [u]x M = [(tr M - M) u]x);
  //   -E^T [J w_a]x Lam = -[E^T J w_a]x (E^T Lam)  (E a rotation).
  if (w.Yc.rows() != 3 * rs.samples || w.Yc.cols() != r) w.Yc.resize(3 * rs.samples, r);
  if (w.Bc.rows() != 9 * rs.samples || w.Bc.cols() != r) w.Bc.resize(9 * rs.samples, r);
  static const int km[3] = {2, 0, 1}, jm[3] = {1, 2, 0};  // axial(X)_m = X(km, jm) - X(jm, km)
  for (int e = 0; e < ncell; ++e) {
    const Eigen::Matrix<double, 3, 8> Lc = adjoint_cell(lam, n, lat.cells[e]);
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * e + q;
      const Matrix3d Lam = Lc * G[q];
      const Matrix3d &E = ev->Es[i], &J = ev->Js[i], &F = ev->Fs[i];
      const Vector3d v = ev->v.segment<3>(3 * i);
      const JacobianScalars c = jacobian_scalars(v.squaredNorm());
      const Matrix3d A1 = Lam * F.transpose();
      const Vector3d ax1 = axial2(A1);
      const Vector3d v_ax1 = v.cross(ax1), v_v_ax1 = v.cross(v_ax1);
      const Matrix3d Xa = cross_matrix(ax1);
      Matrix3d Ym = (c.be * v_v_ax1 - c.al * v_ax1) * v.transpose() + c.a * Xa;
      Ym.noalias() -= c.b * (cross_matrix(v) * Xa);
      Ym -= c.b * cross_matrix(v_ax1);
      Matrix3d K1 = -A1.transpose();
      K1.diagonal().array() += A1.trace();
      Matrix3d Y3 = Ym;
      Y3.noalias() -= J.transpose() * (K1 * J);
      Eigen::Matrix<double, 3, 9> Q;
      for (int m = 0; m < 3; ++m)
        for (int qq = 0; qq < 3; ++qq)
          for (int pp = 0; pp < 3; ++pp)
            Q(m, pp + 3 * qq) = Lam(km[m], pp) * E(jm[m], qq) - Lam(jm[m], pp) * E(km[m], qq);
      const Eigen::Matrix<double, 3, 9> Y9 = J.transpose() * Q;
      const Matrix3d M2 = E.transpose() * Lam, EJ = E.transpose() * J;
      Eigen::Matrix<double, 9, 3> B93;
      for (int col = 0; col < 3; ++col) B93.middleRows<3>(3 * col) = cross_matrix(M2.col(col)) * EJ;
      w.Yc.middleRows<3>(3 * i).noalias() = vol * (Y3.lazyProduct(rs.rot.middleRows<3>(3 * i)) +
                                                   Y9.lazyProduct(rs.strain.middleRows<9>(9 * i)));
      w.Bc.middleRows<9>(9 * i).noalias() = vol * B93.lazyProduct(rs.rot.middleRows<3>(3 * i));
    }
  }
  if (curvature.rows() != r || curvature.cols() != r) curvature.resize(r, r);
  curvature.noalias() = rs.rot.transpose() * w.Yc;
  curvature.noalias() += rs.strain.transpose() * w.Bc;
  for (int a = 0; a < r; ++a)
    for (int k = a + 1; k < r; ++k) curvature(k, a) = curvature(a, k) = 0.5 * (curvature(k, a) + curvature(a, k));
}

}  // namespace pliant::soft
