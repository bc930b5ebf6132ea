// Rotation-strain coordinates (see rotation_strain.h).
#include "pliant/soft/rotation_strain.h"

#include <cholmod.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "pliant/soft/fem.h"

namespace pliant::soft {

struct RsFactor {
  cholmod_common cc;
  cholmod_factor* L = nullptr;
  RsFactor() { cholmod_start(&cc); }
  ~RsFactor() {
    if (L) cholmod_free_factor(&L, &cc);
    cholmod_finish(&cc);
  }
  RsFactor(const RsFactor&) = delete;
  RsFactor& operator=(const RsFactor&) = delete;
};

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// exp([v]x) (Rodrigues) and the left Jacobian of SO(3):
// d/dt exp([v + t d]x) = [J(v) d]x exp([v]x), J = I + a [v]x + b [v]x^2.
void exp_and_jacobian(const Vector3d& v, Matrix3d* E, Matrix3d* J) {
  const double t2 = v.squaredNorm(), t = std::sqrt(t2);
  double s, c, a, b;  // sin t / t, (1 - cos t) / t^2, and the Jacobian's (t - sin t) / t^3
  if (t < 1e-4) {
    s = 1 - t2 / 6, c = 0.5 - t2 / 24, b = 1.0 / 6 - t2 / 120;
  } else {
    s = std::sin(t) / t, c = (1 - std::cos(t)) / t2, b = (t - std::sin(t)) / (t2 * t);
  }
  a = c;
  const Matrix3d V = cross_matrix(v), V2 = V * V;
  *E = Matrix3d::Identity() + s * V + c * V2;
  if (J) *J = Matrix3d::Identity() + a * V + b * V2;
}

// Per-thread reconstruction buffers (sized on first use).
struct RsWork {
  cholmod_common cc;
  cholmod_dense *B = nullptr, *X = nullptr, *Y = nullptr, *E = nullptr;      // positions: N x 3
  cholmod_dense *BJ = nullptr, *XJ = nullptr, *YJ = nullptr, *EJ = nullptr;  // Jacobian: N x 3r
  Eigen::VectorXd hstep;  // curvature: difference step per coordinate
  Eigen::VectorXd v, sv;  // per-sample rotation vectors (3 S) and strains (9 S)
  RsWork() { cholmod_start(&cc); }
  ~RsWork() {
    for (cholmod_dense** d : {&B, &X, &Y, &E, &BJ, &XJ, &YJ, &EJ})
      if (*d) cholmod_free_dense(d, &cc);
    cholmod_finish(&cc);
  }
  void ensure(cholmod_dense*& d, int nrow, int ncol) {
    if (d && int(d->nrow) == nrow && int(d->ncol) == ncol) return;
    if (d) cholmod_free_dense(&d, &cc);
    d = cholmod_allocate_dense(size_t(nrow), size_t(ncol), size_t(nrow), CHOLMOD_REAL, &cc);
    if (!d) throw std::runtime_error("rotation_strain: CHOLMOD could not allocate a dense buffer");
  }
};

RsWork& work() {
  thread_local RsWork w;
  return w;
}

void solve(RsWork& w, const RsFactor& f, cholmod_dense* B, cholmod_dense** X, cholmod_dense** Y,
           cholmod_dense** E) {
  if (!cholmod_solve2(CHOLMOD_A, f.L, B, nullptr, X, nullptr, Y, E, &w.cc))
    throw std::runtime_error("rotation_strain: CHOLMOD solve failed");
}

// Copies the N x ncol solution into out (3N x cols/3; x[3j+s] of column k is
// X(j, 3k+s)) with each coordinate's mass-weighted mean removed.
template <typename Out>
void gather_centred(const RsWork& w, const cholmod_dense* X, const Eigen::VectorXd& mf, Out& out) {
  const int n = int(X->nrow), cols = int(X->ncol);
  const double* p = static_cast<const double*>(X->x);
  for (int col = 0; col < cols; ++col) {
    const double* c = p + size_t(col) * size_t(n);
    double mean = 0;
    for (int j = 0; j < n; ++j) mean += mf[j] * c[j];
    const int k = col / 3, s = col % 3;
    for (int j = 0; j < n; ++j) out(3 * j + s, k) = c[j] - mean;
  }
  (void)w;
}

}  // namespace

RotationStrain rotation_strain_build(const Lattice& lat, const Eigen::MatrixXd& U) {
  RotationStrain rs;
  const int n = lat.nodes(), r = int(U.cols()), ncell = int(lat.cells.size());
  const double h = lat.cell_size_m, vol = h * h * h / 8;
  rs.nodes = n, rs.r = r, rs.samples = 8 * ncell, rs.sample_volume = vol;
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
  RsWork& w = work();
  const int n = rs.nodes, r = rs.r, ncell = int(lat.cells.size());
  const auto& G = gauss_shape_gradients(lat.cell_size_m);
  const double vol = rs.sample_volume;
  w.v.resize(3 * rs.samples);
  w.sv.resize(9 * rs.samples);
  w.v.noalias() = rs.rot * z;
  w.sv.noalias() = rs.strain * z;
  w.ensure(w.B, n, 3);
  if (jacobian) w.ensure(w.BJ, n, 3 * r);
  double* b = static_cast<double*>(w.B->x);
  double* bj = jacobian ? static_cast<double*>(w.BJ->x) : nullptr;
  std::fill(b, b + 3 * size_t(n), 0.0);
  if (bj) std::fill(bj, bj + 3 * size_t(n) * size_t(r), 0.0);
  // Scatter vol * G_i^T F into the right-hand side: b(node a, s) += vol sum_c F(s, c) G(a, c).
  auto scatter = [&](double* dst, int col0, const std::array<int, 8>& ids, const Eigen::Matrix<double, 8, 3>& Gq,
                     const Matrix3d& F) {
    const Eigen::Matrix<double, 8, 3> P = vol * Gq * F.transpose();  // P(a, s)
    for (int s = 0; s < 3; ++s) {
      double* c = dst + size_t(col0 + s) * size_t(n);
      for (int a = 0; a < 8; ++a) c[ids[a]] += P(a, s);
    }
  };
  for (int e = 0; e < ncell; ++e) {
    const auto& ids = lat.cells[e];
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * e + q;
      Matrix3d E, J;
      exp_and_jacobian(w.v.segment<3>(3 * i), &E, bj ? &J : nullptr);
      const Matrix3d S = Matrix3d::Identity() + Eigen::Map<const Matrix3d>(w.sv.data() + 9 * i);
      scatter(b, 0, ids, G[q], E * S);
      if (!bj) continue;
      const Matrix3d ES = E * S;
      for (int k = 0; k < r; ++k) {
        const Vector3d dv = J * rs.rot.block<3, 1>(3 * i, k);
        const Matrix3d dF =
            cross_matrix(dv) * ES + E * Eigen::Map<const Matrix3d>(rs.strain.col(k).data() + 9 * i);
        scatter(bj, 3 * k, ids, G[q], dF);
      }
    }
  }
  solve(w, *rs.factor, w.B, &w.X, &w.Y, &w.E);
  if (x.size() != 3 * n) x.resize(3 * n);
  Eigen::Map<Eigen::MatrixXd> xm(x.data(), 3 * n, 1);
  gather_centred(w, w.X, rs.mass_fraction, xm);
  if (jacobian) {
    solve(w, *rs.factor, w.BJ, &w.XJ, &w.YJ, &w.EJ);
    if (jacobian->rows() != 3 * n || jacobian->cols() != r) jacobian->resize(3 * n, r);
    gather_centred(w, w.XJ, rs.mass_fraction, *jacobian);
  }
}

void rotation_strain_curvature(const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                               const Eigen::VectorXd& g, Eigen::MatrixXd& curvature) {
  if (!rs.factor || z.size() != rs.r || lat.nodes() != rs.nodes || g.size() != 3 * rs.nodes)
    throw std::invalid_argument("rotation_strain_curvature: sizes do not match");
  RsWork& w = work();
  const int n = rs.nodes, r = rs.r, ncell = int(lat.cells.size());
  const auto& G = gauss_shape_gradients(lat.cell_size_m);
  const double vol = rs.sample_volume;
  // lambda = L^-1 P^T g: P^T g = g - mass_fraction (sum_j g_j) per coordinate.
  w.ensure(w.B, n, 3);
  double* b = static_cast<double*>(w.B->x);
  for (int s = 0; s < 3; ++s) {
    double sum = 0;
    for (int j = 0; j < n; ++j) sum += g[3 * j + s];
    for (int j = 0; j < n; ++j) b[size_t(s) * size_t(n) + size_t(j)] = g[3 * j + s] - rs.mass_fraction[j] * sum;
  }
  solve(w, *rs.factor, w.B, &w.X, &w.Y, &w.E);
  const double* lam = static_cast<const double*>(w.X->x);
  w.v.resize(3 * rs.samples);
  w.sv.resize(9 * rs.samples);
  w.v.noalias() = rs.rot * z;
  w.sv.noalias() = rs.strain * z;
  if (curvature.rows() != r || curvature.cols() != r) curvature.resize(r, r);
  curvature.setZero();
  // Step per coordinate: at most 1e-4 rad of rotation or strain anywhere.
  w.hstep.resize(r);
  for (int a = 0; a < r; ++a) {
    const double big = std::max(rs.rot.col(a).cwiseAbs().maxCoeff(), rs.strain.col(a).cwiseAbs().maxCoeff());
    w.hstep[a] = 1e-4 / std::max(big, 1e-300);
  }
  for (int e = 0; e < ncell; ++e) {
    const auto& ids = lat.cells[e];
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * e + q;
      Matrix3d Lam = Matrix3d::Zero();  // grad lambda at the sample: Lam(s, c) = sum_k lambda(k, s) G(k, c)
      for (int k = 0; k < 8; ++k)
        for (int s = 0; s < 3; ++s) Lam.row(s) += lam[size_t(s) * size_t(n) + size_t(ids[k])] * G[q].row(k);
      const Matrix3d S0 = Matrix3d::Identity() + Eigen::Map<const Matrix3d>(w.sv.data() + 9 * i);
      for (int a = 0; a < r; ++a) {
        const double h = w.hstep[a];
        const Vector3d wa = rs.rot.block<3, 1>(3 * i, a);
        const Eigen::Map<const Matrix3d> sa(rs.strain.col(a).data() + 9 * i);
        for (int sgn = -1; sgn <= 1; sgn += 2) {
          Matrix3d E, J;
          exp_and_jacobian(w.v.segment<3>(3 * i) + sgn * h * wa, &E, &J);
          const Matrix3d S = S0 + sgn * h * sa;
          const Matrix3d ES = E * S;
          for (int k = 0; k < r; ++k) {
            const Matrix3d dF = cross_matrix(J * rs.rot.block<3, 1>(3 * i, k)) * ES +
                                E * Eigen::Map<const Matrix3d>(rs.strain.col(k).data() + 9 * i);
            curvature(k, a) += sgn * vol / (2 * h) * (dF.array() * Lam.array()).sum();
          }
        }
      }
    }
  }
  for (int a = 0; a < r; ++a)
    for (int k = a + 1; k < r; ++k) curvature(k, a) = curvature(a, k) = 0.5 * (curvature(k, a) + curvature(a, k));
}

}  // namespace pliant::soft
