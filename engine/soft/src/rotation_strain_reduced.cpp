// Rotation-strain map (rotation_strain.h): the opt-in reduced reconstruction, POD of
// the nonlinear remainder beyond U plus cell cubature (training in
// rotation_strain_reduce; playback in rotation_strain_reduced_positions/_curvature).
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "pliant/soft/cubature.h"
#include "pliant/soft/fem.h"
#include "pliant/soft/rotation_strain.h"
#include "rotation_strain_workspace.h"

namespace pliant::soft {

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Remainder N = exp([v]x)(I + S) - I - [v]x - S of one sample (9 values, column-major)
// and, with dN, its derivatives in z (9 x r, column k at dN + 9 * stride * k).
void sample_remainder(const Vector3d& v, const Matrix3d& Sv, const double* rot, const double* strain, int rows3,
                      int r, double* N, double* dN, int ld) {
  Matrix3d E, J;
  exp_and_jacobian(v, &E, dN ? &J : nullptr);
  const Matrix3d ES = E * (Matrix3d::Identity() + Sv);
  Eigen::Map<Matrix3d> Nm(N);
  Nm = ES - Matrix3d::Identity() - cross_matrix(v) - Sv;
  if (!dN) return;
  for (int k = 0; k < r; ++k) {
    const Vector3d wk = Eigen::Map<const Vector3d>(rot + size_t(k) * size_t(rows3));
    const Eigen::Map<const Matrix3d> sk(strain + size_t(k) * size_t(3 * rows3));
    Eigen::Map<Eigen::Matrix<double, 9, 1>> dNk(dN + size_t(k) * size_t(ld));
    const Matrix3d dF = cross_matrix(J * wk) * ES + E * sk - cross_matrix(wk) - sk;
    dNk = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dF.data());
  }
}

struct RsReducedWork {
  Eigen::VectorXd v, sv, nvec, c, lc, lam;
  Eigen::MatrixXd dN, D;
};

RsReducedWork& reduced_work() {
  thread_local RsReducedWork w;
  return w;
}

}  // namespace

std::shared_ptr<const RsReduced> rotation_strain_reduce(const Lattice& lat, const RotationStrain& rs,
                                                        const Eigen::MatrixXd& U, const Eigen::VectorXd& rest_local,
                                                        const std::vector<Eigen::VectorXd>& poses,
                                                        const RsReductionSettings& st) {
  const int n = rs.nodes, r = rs.r, ncell = int(lat.cells.size()), P = int(poses.size());
  if (U.rows() != 3 * n || U.cols() != r || rest_local.size() != 3 * n)
    throw std::invalid_argument("rotation_strain_reduce: basis and lattice do not match");
  auto red = std::make_shared<RsReduced>();
  red->r = r;
  red->rest = rest_local;
  Eigen::VectorXd m3(3 * n);
  for (int j = 0; j < n; ++j) m3.segment<3>(3 * j).setConstant(lat.node_mass_kg[j]);

  // Infinitesimal rotations about the centroid, M-orthonormal. The reduced map is kept
  // M-orthogonal to them (as the linear modes are: Sum m_j Xbar_j x x_j = 0), so net
  // rotation is the floating frame's alone; the full map lets z rotate the body too,
  // a near-gauge valley with R in which quasi-static steps drift (a symmetric T bend
  // sits on an unstable equilibrium: any asymmetry turns R and the shape away).
  Eigen::MatrixXd Rf(3 * n, 3);
  for (int j = 0; j < n; ++j)
    for (int a = 0; a < 3; ++a) Rf.block<3, 1>(3 * j, a) = Vector3d::Unit(a).cross(rest_local.segment<3>(3 * j));
  for (int a = 0; a < 3; ++a) {
    Eigen::VectorXd v = Rf.col(a);
    for (int b2 = 0; b2 < a; ++b2) v -= Rf.col(b2) * Rf.col(b2).dot(m3.cwiseProduct(v));
    Rf.col(a) = v / std::sqrt(std::max(v.dot(m3.cwiseProduct(v)), 1e-300));
  }
  // 1. What exact reconstructions hold beyond Xbar + U z, M-projected off U and the
  // rotations; POD.
  Eigen::MatrixXd Dx(3 * n, P);
  std::vector<double> deform(P);
  Eigen::VectorXd x;
  for (int p = 0; p < P; ++p) {
    rotation_strain_positions(lat, rs, poses[p], x);
    Eigen::VectorXd d = x - rest_local;
    deform[p] = std::sqrt(d.dot(m3.cwiseProduct(d)));
    d -= U * poses[p];
    d -= U * (U.transpose() * m3.cwiseProduct(d));
    d -= Rf * (Rf.transpose() * m3.cwiseProduct(d));
    Dx.col(p) = d;
  }
  Eigen::MatrixXd V(3 * n, 0);
  if (P > 0) {
    const Eigen::MatrixXd Gm = Dx.transpose() * m3.asDiagonal() * Dx;
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Gm);
    const double total = std::max(Gm.trace(), 1e-300);
    double left = total;
    int keep = 0;
    for (int k = P - 1; k >= 0 && keep < st.max_basis; --k) {
      if (left <= st.basis_tolerance * st.basis_tolerance * total || es.eigenvalues()[k] <= 1e-14 * total) break;
      left -= es.eigenvalues()[k];
      ++keep;
    }
    V.resize(3 * n, keep);
    for (int k = 0; k < keep; ++k) V.col(k) = Dx * es.eigenvectors().col(P - 1 - k);
    // M-orthonormal against U and each other (two Gram-Schmidt passes).
    for (int pass = 0; pass < 2; ++pass)
      for (int k = 0; k < keep; ++k) {
        Eigen::VectorXd v = V.col(k);
        v -= U * (U.transpose() * m3.cwiseProduct(v));
        v -= Rf * (Rf.transpose() * m3.cwiseProduct(v));
        for (int l = 0; l < k; ++l) v -= V.col(l) * V.col(l).dot(m3.cwiseProduct(v));
        V.col(k) = v / std::sqrt(std::max(v.dot(m3.cwiseProduct(v)), 1e-300));
      }
  }
  const int m = int(V.cols()), K = r + m;
  red->m = m;
  red->W.resize(3 * n, K);
  red->W << U, V;
  for (int p = 0; p < P; ++p) {
    const Eigen::VectorXd d = Dx.col(p);
    const Eigen::VectorXd e = d - V * (V.transpose() * m3.cwiseProduct(d));
    red->basis_error = std::max(red->basis_error, std::sqrt(e.dot(m3.cwiseProduct(e))) / std::max(deform[p], 1e-300));
  }

  // 2. Z = L^-1 M W per coordinate (N x 3K, column 3k + s), one solve.
  RsWork& w = rs_work();
  w.ensure(w.BJ, n, 3 * K);
  double* bz = static_cast<double*>(w.BJ->x);
  for (int k = 0; k < K; ++k)
    for (int s = 0; s < 3; ++s)
      for (int j = 0; j < n; ++j) bz[size_t(3 * k + s) * size_t(n) + size_t(j)] = lat.node_mass_kg[j] * red->W(3 * j + s, k);
  rs_solve(w, *rs.factor, w.BJ, &w.XJ, &w.YJ, &w.EJ);
  const Eigen::Map<const Eigen::MatrixXd> Z(static_cast<const double*>(w.XJ->x), n, 3 * K);
  const auto& G = gauss_shape_gradients(lat.cell_size_m);
  const double vol = rs.sample_volume;
  // C_i (K x 9) of sample i = 8 e + q: C(k, 3c + s) = vol sum_a Z(ids[a], 3k + s) G_q(a, c).
  auto sample_operator = [&](int e, int q, Eigen::Ref<Eigen::MatrixXd> Ci) {
    const auto& ids = lat.cells[e];
    for (int k = 0; k < K; ++k)
      for (int s = 0; s < 3; ++s)
        for (int c = 0; c < 3; ++c) {
          double acc = 0;
          for (int a = 0; a < 8; ++a) acc += Z(ids[a], 3 * k + s) * G[q](a, c);
          Ci(k, 3 * c + s) = vol * acc;
        }
  };
  Eigen::MatrixXd Call(K, 9 * rs.samples);
  for (int e = 0; e < ncell; ++e)
    for (int q = 0; q < 8; ++q) sample_operator(e, q, Call.middleCols(9 * (8 * e + q), 9));

  // 3. Cell cubature on (c, dc/dz) over the poses; rows of a pose scaled to unit norm
  // per block. Jacobian rows for every third pose (more on big lattices): the fit's
  // cost grows with rows x cells^2.
  const int jstride = std::max<long>(3, long(P) * K * (r + 1) * ncell / 20000000L + 1);
  int rows = 0;
  for (int p = 0; p < P; ++p) rows += K + (p % jstride == 0 ? K * r : 0);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, ncell);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(rows);
  Eigen::VectorXd N9(9);
  Eigen::MatrixXd dN9(9, r), cell_c(K, 1), cell_D(K, r);
  int row = 0;
  for (int p = 0; p < P; ++p) {
    const bool jac = p % jstride == 0;
    const Eigen::VectorXd v = rs.rot * poses[p], sv = rs.strain * poses[p];
    Eigen::MatrixXd blockc(K, ncell), blockD(K * r, ncell);
    for (int e = 0; e < ncell; ++e) {
      cell_c.setZero();
      cell_D.setZero();
      for (int q = 0; q < 8; ++q) {
        const int i = 8 * e + q;
        sample_remainder(v.segment<3>(3 * i), Eigen::Map<const Matrix3d>(sv.data() + 9 * i), rs.rot.data() + 3 * i,
                         rs.strain.data() + 9 * i, int(rs.rot.rows()), r, N9.data(), jac ? dN9.data() : nullptr, 9);
        const auto Ci = Call.middleCols(9 * i, 9);
        cell_c.noalias() += Ci * N9;
        if (jac) cell_D.noalias() += Ci * dN9;
      }
      blockc.col(e) = cell_c;
      if (jac) blockD.col(e) = Eigen::Map<const Eigen::VectorXd>(cell_D.data(), K * r);
    }
    const Eigen::VectorXd tc = blockc.rowwise().sum();
    const double sc = 1.0 / std::max(tc.norm(), 1e-300);
    A.middleRows(row, K) = sc * blockc;
    b.segment(row, K) = sc * tc;
    row += K;
    if (jac) {
      const Eigen::VectorXd tD = blockD.rowwise().sum();
      const double sd = 1.0 / std::max(tD.norm(), 1e-300);
      A.middleRows(row, K * r) = sd * blockD;
      b.segment(row, K * r) = sd * tD;
      row += K * r;
    }
  }
  const CellWeights cw = greedy_cubature(A, b, st.cubature_tolerance, st.max_cells, &red->cubature_error);
  red->cells = cw.cells;
  red->weights = cw.weights;
  const int S1 = 8 * int(cw.cells.size());
  red->C.resize(K, 9 * S1);
  red->rot.resize(3 * S1, r);
  red->strain.resize(9 * S1, r);
  for (size_t t = 0; t < cw.cells.size(); ++t)
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * cw.cells[t] + q, o = 8 * int(t) + q;
      red->C.middleCols(9 * o, 9) = cw.weights[t] * Call.middleCols(9 * i, 9);
      red->rot.middleRows(3 * o, 3) = rs.rot.middleRows(3 * i, 3);
      red->strain.middleRows(9 * o, 9) = rs.strain.middleRows(9 * i, 9);
    }
  red->hstep.resize(r);
  for (int a = 0; a < r; ++a) {
    const double big = std::max(rs.rot.col(a).cwiseAbs().maxCoeff(), rs.strain.col(a).cwiseAbs().maxCoeff());
    red->hstep[a] = 1e-4 / std::max(big, 1e-300);
  }
  return red;
}

void rotation_strain_reduced_positions(const RsReduced& red, const Eigen::VectorXd& z, Eigen::VectorXd& x,
                                       Eigen::MatrixXd* jacobian) {
  const int r = red.r, K = r + red.m, S1 = int(red.rot.rows()) / 3;
  if (z.size() != r) throw std::invalid_argument("rotation_strain_reduced_positions: z needs one value per mode");
  RsReducedWork& w = reduced_work();
  w.v.resize(3 * S1);
  w.sv.resize(9 * S1);
  w.nvec.resize(9 * S1);
  if (jacobian && (w.dN.rows() != 9 * S1 || w.dN.cols() != r)) w.dN.resize(9 * S1, r);
  w.v.noalias() = red.rot * z;
  w.sv.noalias() = red.strain * z;
  for (int t = 0; t < S1; ++t)
    sample_remainder(w.v.segment<3>(3 * t), Eigen::Map<const Matrix3d>(w.sv.data() + 9 * t), red.rot.data() + 3 * t,
                     red.strain.data() + 9 * t, 3 * S1, r, w.nvec.data() + 9 * t,
                     jacobian ? w.dN.data() + 9 * t : nullptr, 9 * S1);
  w.c.resize(K);
  w.c.noalias() = red.C * w.nvec;
  w.c.head(r) += z;
  if (x.size() != red.rest.size()) x.resize(red.rest.size());
  x = red.rest;
  x.noalias() += red.W * w.c;
  if (jacobian) {
    if (w.D.rows() != K || w.D.cols() != r) w.D.resize(K, r);
    w.D.noalias() = red.C * w.dN;
    w.D.topRows(r).diagonal().array() += 1.0;
    if (jacobian->rows() != red.W.rows() || jacobian->cols() != r) jacobian->resize(red.W.rows(), r);
    jacobian->noalias() = red.W * w.D;
  }
}

void rotation_strain_reduced_curvature(const RsReduced& red, const Eigen::VectorXd& z, const Eigen::VectorXd& g,
                                       Eigen::MatrixXd& curvature) {
  const int r = red.r, S1 = int(red.rot.rows()) / 3;
  if (z.size() != r || g.size() != red.W.rows())
    throw std::invalid_argument("rotation_strain_reduced_curvature: sizes do not match");
  RsReducedWork& w = reduced_work();
  w.lc.resize(red.W.cols());
  w.lc.noalias() = red.W.transpose() * g;
  w.lam.resize(9 * S1);
  w.lam.noalias() = red.C.transpose() * w.lc;  // per sample: the weight of each F entry
  w.v.resize(3 * S1);
  w.sv.resize(9 * S1);
  w.v.noalias() = red.rot * z;
  w.sv.noalias() = red.strain * z;
  if (curvature.rows() != r || curvature.cols() != r) curvature.resize(r, r);
  curvature.setZero();
  for (int t = 0; t < S1; ++t) {
    const Eigen::Map<const Matrix3d> Lam(w.lam.data() + 9 * t);
    const Matrix3d S0 = Matrix3d::Identity() + Eigen::Map<const Matrix3d>(w.sv.data() + 9 * t);
    for (int a = 0; a < r; ++a) {
      const double h = red.hstep[a];
      const Vector3d wa = red.rot.block<3, 1>(3 * t, a);
      const Eigen::Map<const Matrix3d> sa(red.strain.col(a).data() + 9 * t);
      for (int sgn = -1; sgn <= 1; sgn += 2) {
        Matrix3d E, J;
        exp_and_jacobian(w.v.segment<3>(3 * t) + sgn * h * wa, &E, &J);
        const Matrix3d A1 = Lam * (E * (S0 + sgn * h * sa)).transpose(), A2 = E.transpose() * Lam;
        const Vector3d ax = J.transpose() * Vector3d(A1(2, 1) - A1(1, 2), A1(0, 2) - A1(2, 0), A1(1, 0) - A1(0, 1));
        const double f = sgn / (2 * h);
        for (int k = 0; k < r; ++k)
          curvature(k, a) += f * (ax.dot(red.rot.block<3, 1>(3 * t, k)) +
                                  (Eigen::Map<const Matrix3d>(red.strain.col(k).data() + 9 * t).array() * A2.array()).sum());
      }
    }
  }
  for (int a = 0; a < r; ++a)
    for (int k = a + 1; k < r; ++k) curvature(k, a) = curvature(a, k) = 0.5 * (curvature(k, a) + curvature(a, k));
}

}  // namespace pliant::soft
