// Rotation-strain coordinates (see rotation_strain.h): the lattice split and Laplacian
// factor (build), the map x(z) and its Jacobian. The adjoint products are in
// rotation_strain_adjoint.cpp, the reduced reconstruction in rotation_strain_reduced.cpp.
#include "pliant/soft/rotation_strain.h"

#include <cholmod.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cmath>
#include <stdexcept>

#include "pliant/soft/fem.h"
#include "rotation_strain_workspace.h"

namespace pliant::soft {

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

std::uint64_t next_rs_id() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

}  // namespace

RsWork& rs_work() {
  thread_local RsWork w;
  return w;
}

void rs_solve(RsWork& w, const RsFactor& f, cholmod_dense* B, cholmod_dense** X, cholmod_dense** Y,
              cholmod_dense** E) {
  // A simplicial solve asks for its workspace Y as max(4, nrhs) x n and then reshapes
  // it per block of 4 columns, so the next call would find the "wrong" shape and
  // reallocate: restore the shape it asks for (same storage) first.
  if (!f.L->is_super && *Y) {
    const size_t nr = std::max<size_t>(4, B->ncol), n = B->nrow;
    if ((*Y)->nzmax >= nr * n) (*Y)->nrow = nr, (*Y)->ncol = n, (*Y)->d = nr;
  }
  if (!cholmod_solve2(CHOLMOD_A, f.L, B, nullptr, X, nullptr, Y, E, &w.cc))
    throw std::runtime_error("rotation_strain: CHOLMOD solve failed");
}

// Fills Js of an evaluation from its rotation vectors and stored coefficients.
void rs_fill_jacobians(RsEval& ev) {
  const size_t S = ev.Es.size();
  ev.Js.resize(S);
  for (size_t i = 0; i < S; ++i)
    so3_left_jacobian(ev.v.segment<3>(3 * i), ev.cb[2 * i], ev.cb[2 * i + 1], &ev.Js[i]);
  ev.has_j = true;
}

const RsEval& rs_evaluate(RsWork& w, const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                          bool need_j) {
  for (int k = 0; k < 2; ++k) {
    RsEval& c = w.slot[k];
    if (c.key == rs.id && rs.id != 0 && c.key_z.size() == z.size() && c.key_z == z) {
      w.next = 1 - k;
      if (need_j && !c.has_j) rs_fill_jacobians(c);
      return c;
    }
  }
  RsEval& ev = w.slot[w.next];
  w.next = 1 - w.next;
  ev.key = 0;
  const int n = rs.nodes, ncell = int(lat.cells.size());
  const auto& G = gauss_shape_gradients(lat.cell_size_m);
  const double vol = rs.sample_volume;
  ev.v.resize(3 * rs.samples);
  ev.sv.resize(9 * rs.samples);
  w.d.resize(3 * n);
  w.d.noalias() = rs.U * z;
  ev.Es.resize(size_t(rs.samples));
  ev.Fs.resize(size_t(rs.samples));
  ev.cb.resize(2 * rs.samples);
  ev.has_j = false;
  w.ensure(w.B, n, 3);
  double* b = static_cast<double*>(w.B->x);
  std::fill(b, b + 3 * size_t(n), 0.0);
  // Right-hand side vol sum_i G_i^T F_i: b(node a, s) += vol sum_c F(s, c) G(a, c),
  // summed per cell before the scatter.
  for (int e = 0; e < ncell; ++e) {
    const auto& ids = lat.cells[e];
    Eigen::Matrix<double, 8, 3> P = Eigen::Matrix<double, 8, 3>::Zero();
    Eigen::Matrix<double, 3, 8> Dc;  // the cell's nodal displacements U z
    for (int a = 0; a < 8; ++a) Dc.col(a) = w.d.segment<3>(3 * ids[a]);
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * e + q;
      // grad(U z) at the sample: its rotation vector (= rot z) and symmetric part (= strain z).
      const Matrix3d Hq = Dc * G[q];
      ev.v.segment<3>(3 * i) = 0.5 * Vector3d(Hq(2, 1) - Hq(1, 2), Hq(0, 2) - Hq(2, 0), Hq(1, 0) - Hq(0, 1));
      Eigen::Map<Matrix3d>(ev.sv.data() + 9 * i) = 0.5 * (Hq + Hq.transpose());
      {
        const Vector3d v = ev.v.segment<3>(3 * i);
        double sc, cc, bc;
        exp_coefficients(v, &sc, &cc, &bc);
        const Matrix3d V = cross_matrix(v), vv = v * v.transpose();
        ev.Es[i] = sc * V + cc * vv;
        ev.Es[i].diagonal().array() += 1 - cc * v.squaredNorm();
        ev.cb[2 * i] = cc, ev.cb[2 * i + 1] = bc;
      }
      ev.Fs[i].noalias() = ev.Es[i] * (Matrix3d::Identity() + Eigen::Map<const Matrix3d>(ev.sv.data() + 9 * i));
      P.noalias() += G[q] * ev.Fs[i].transpose();
    }
    for (int s = 0; s < 3; ++s) {
      double* c = b + size_t(s) * size_t(n);
      for (int a = 0; a < 8; ++a) c[ids[a]] += vol * P(a, s);
    }
  }
  rs_solve(w, *rs.factor, w.B, &w.X, &w.Y, &w.E);
  if (ev.xc.size() != 3 * n) ev.xc.resize(3 * n);
  Eigen::Map<Eigen::MatrixXd> xm(ev.xc.data(), 3 * n, 1);
  rs_gather_centred(w, w.X, rs.mass_fraction, xm);
  ev.key_z = z;
  ev.key = rs.id;
  if (need_j) rs_fill_jacobians(ev);
  return ev;
}

RotationStrain rotation_strain_build(const Lattice& lat, const Eigen::MatrixXd& U) {
  RotationStrain rs;
  rs.id = next_rs_id();
  const int n = lat.nodes(), r = int(U.cols()), ncell = int(lat.cells.size());
  const double h = lat.cell_size_m, vol = h * h * h / 8;
  rs.nodes = n, rs.r = r, rs.samples = 8 * ncell, rs.sample_volume = vol;
  rs.U = U;
  rs.rot.resize(3 * rs.samples, r);
  rs.strain.resize(9 * rs.samples, r);
  const auto& G = gauss_shape_gradients(h);
  for (int e = 0; e < ncell; ++e) {
    const auto& ids = lat.cells[e];
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * e + q;
      for (int k = 0; k < r; ++k) {
        Matrix3d H = Matrix3d::Zero();  // grad U_k: H(s, c) = d u_s / d X_c
        for (int a = 0; a < 8; ++a) H.noalias() += U.block<3, 1>(3 * ids[a], k) * G[q].row(a);
        const Matrix3d W = 0.5 * (H - H.transpose()), S = 0.5 * (H + H.transpose());
        rs.rot.block<3, 1>(3 * i, k) = Vector3d(W(2, 1), W(0, 2), W(1, 0));
        rs.strain.block<9, 1>(9 * i, k) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(S.data());
      }
    }
  }
  double mass = 0;
  rs.mass_fraction.resize(n);
  for (int j = 0; j < n; ++j) mass += lat.node_mass_kg[j];
  for (int j = 0; j < n; ++j) rs.mass_fraction[j] = lat.node_mass_kg[j] / mass;

  // L = sum_i vol G_i G_i^T (upper triangle), node 0 pinned (L_00 doubled: any
  // positive value selects the same solution up to translation).
  auto f = std::make_shared<RsFactor>();
  cholmod_common* cc = &f->cc;
  cholmod_triplet* T = cholmod_allocate_triplet(size_t(n), size_t(n), size_t(ncell) * 8 * 36 + 1, 1, CHOLMOD_REAL, cc);
  if (!T) throw std::runtime_error("rotation_strain: CHOLMOD could not allocate the Laplacian");
  auto* ti = static_cast<int*>(T->i);
  auto* tj = static_cast<int*>(T->j);
  auto* tx = static_cast<double*>(T->x);
  size_t nz = 0;
  double l00 = 0;
  for (int e = 0; e < ncell; ++e) {
    const auto& ids = lat.cells[e];
    Eigen::Matrix<double, 8, 8> Le = Eigen::Matrix<double, 8, 8>::Zero();
    for (int q = 0; q < 8; ++q) Le.noalias() += vol * G[q] * G[q].transpose();
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        if (ids[a] > ids[b]) continue;
        ti[nz] = ids[a], tj[nz] = ids[b], tx[nz] = Le(a, b);
        ++nz;
        if (ids[a] == 0 && ids[b] == 0) l00 += Le(a, b);
      }
  }
  ti[nz] = 0, tj[nz] = 0, tx[nz] = l00;
  T->nnz = nz + 1;
  cholmod_sparse* A = cholmod_triplet_to_sparse(T, T->nnz, cc);
  cholmod_free_triplet(&T, cc);
  if (!A) throw std::runtime_error("rotation_strain: CHOLMOD could not assemble the Laplacian");
  f->L = cholmod_analyze(A, cc);
  const bool ok = f->L && cholmod_factorize(A, f->L, cc) && cc->status == CHOLMOD_OK && f->L->minor == size_t(n);
  cholmod_free_sparse(&A, cc);
  if (!ok) throw std::runtime_error("rotation_strain: the lattice Laplacian is not positive definite");
  rs.factor = f;
  return rs;
}

void rotation_strain_positions(const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                               Eigen::VectorXd& x, Eigen::MatrixXd* jacobian) {
  if (!rs.factor || z.size() != rs.r || lat.nodes() != rs.nodes)
    throw std::invalid_argument("rotation_strain_positions: basis and lattice do not match");
  RsWork& w = rs_work();
  const RsEval& ev = rs_evaluate(w, lat, rs, z, jacobian != nullptr);
  const int n = rs.nodes, r = rs.r, ncell = int(lat.cells.size());
  if (x.size() != 3 * n) x.resize(3 * n);
  x = ev.xc;
  if (!jacobian) return;
  // dF_ik = [J_i w_ik]x F_i + E_i s_ik; right-hand side column 3k + s gets
  // vol sum_i G_i^T dF_ik, summed per cell (w.Pk) before the scatter.
  const auto& G = gauss_shape_gradients(lat.cell_size_m);
  const double vol = rs.sample_volume;
  w.ensure(w.BJ, n, 3 * r);
  double* bj = static_cast<double*>(w.BJ->x);
  std::fill(bj, bj + 3 * size_t(n) * size_t(r), 0.0);
  w.Pk.resize(size_t(r));
  const size_t ld_rot = size_t(rs.rot.rows()), ld_strain = size_t(rs.strain.rows());
  for (int e = 0; e < ncell; ++e) {
    const auto& ids = lat.cells[e];
    for (int k = 0; k < r; ++k) w.Pk[k].setZero();
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * e + q;
      const Matrix3d &E = ev.Es[i], &J = ev.Js[i], &F = ev.Fs[i];
      for (int k = 0; k < r; ++k) {
        const Vector3d dv = J * Eigen::Map<const Vector3d>(rs.rot.data() + size_t(k) * ld_rot + 3 * size_t(i));
        // [dv]x F column by column as dv x F.col: the same two products per entry as the
        // 3x3 product (its third term is 0 * F), without the zero multiplies.
        Matrix3d dF;
        for (int col = 0; col < 3; ++col) dF.col(col) = dv.cross(F.col(col));
        dF.noalias() += E * Eigen::Map<const Matrix3d>(rs.strain.data() + size_t(k) * ld_strain + 9 * size_t(i));
        w.Pk[k].noalias() += G[q] * dF.transpose();
      }
    }
    for (int k = 0; k < r; ++k)
      for (int s = 0; s < 3; ++s) {
        double* c = bj + size_t(3 * k + s) * size_t(n);
        for (int a = 0; a < 8; ++a) c[ids[a]] += vol * w.Pk[k](a, s);
      }
  }
  rs_solve(w, *rs.factor, w.BJ, &w.XJ, &w.YJ, &w.EJ);
  if (jacobian->rows() != 3 * n || jacobian->cols() != r) jacobian->resize(3 * n, r);
  rs_gather_centred(w, w.XJ, rs.mass_fraction, *jacobian);
}

}  // namespace pliant::soft
