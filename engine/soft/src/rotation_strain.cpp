// Rotation-strain coordinates (see rotation_strain.h).
#include "pliant/soft/rotation_strain.h"

#include <cholmod.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "pliant/soft/cubature.h"
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
    const double it = 1 / t, sn = std::sin(t);  // one division: they are most of the latency
    s = sn * it, c = (1 - std::cos(t)) * (it * it), b = (t - sn) * (it * it * it);
  }
  a = c;
  // [v]x^2 = v v^T - t^2 I.
  const Matrix3d V = cross_matrix(v), vv = v * v.transpose();
  *E = s * V + c * vv;
  E->diagonal().array() += 1 - c * t2;
  if (J) {
    *J = a * V + b * vv;
    J->diagonal().array() += 1 - b * t2;
  }
}

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

// One evaluation of the map: per-sample rotation vector, strain, rotation E, left
// Jacobian J and F = E S, and the centred positions, for coordinates key_z.
struct RsEval {
  std::uint64_t key = 0;  // RotationStrain::id (0: empty)
  Eigen::VectorXd key_z, xc, v, sv;  // z; positions (3N); rotation vectors (3 S), strains (9 S)
  std::vector<Matrix3d> Es, Js, Fs;
};

// Per-thread reconstruction buffers (sized on first use) and the last two
// evaluations: the step evaluates the map, its adjoint and its Jacobian at the same
// z (and a step starts with q, q_prev, then q again), so exp runs once per z.
struct RsWork {
  cholmod_common cc;
  cholmod_dense *B = nullptr, *X = nullptr, *Y = nullptr, *E = nullptr;      // positions: N x 3
  cholmod_dense *BJ = nullptr, *XJ = nullptr, *YJ = nullptr, *EJ = nullptr;  // Jacobian: N x 3r
  Eigen::VectorXd d, t;   // nodal U z; vjp: nodal adjoint sum (3N)
  RsEval slot[2];
  int next = 0;           // the slot the next new z overwrites (least recently used)
  Eigen::MatrixXd Yc, Bc;            // curvature: the same per direction (3 S x r, 9 S x r)
  std::vector<Eigen::Matrix<double, 8, 3>> Pk;  // Jacobian: one cell's right-hand side per mode
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

std::uint64_t next_rs_id() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

void solve(RsWork& w, const RsFactor& f, cholmod_dense* B, cholmod_dense** X, cholmod_dense** Y,
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

// Evaluates the map at z (per-sample E, J, F and the centred positions), unless a
// slot already holds z for this basis.
const RsEval& evaluate(RsWork& w, const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z) {
  for (int k = 0; k < 2; ++k) {
    const RsEval& c = w.slot[k];
    if (c.key == rs.id && rs.id != 0 && c.key_z.size() == z.size() && c.key_z == z) {
      w.next = 1 - k;
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
  ev.Js.resize(size_t(rs.samples));
  ev.Fs.resize(size_t(rs.samples));
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
      exp_and_jacobian(ev.v.segment<3>(3 * i), &ev.Es[i], &ev.Js[i]);
      ev.Fs[i].noalias() = ev.Es[i] * (Matrix3d::Identity() + Eigen::Map<const Matrix3d>(ev.sv.data() + 9 * i));
      P.noalias() += G[q] * ev.Fs[i].transpose();
    }
    for (int s = 0; s < 3; ++s) {
      double* c = b + size_t(s) * size_t(n);
      for (int a = 0; a < 8; ++a) c[ids[a]] += vol * P(a, s);
    }
  }
  solve(w, *rs.factor, w.B, &w.X, &w.Y, &w.E);
  if (ev.xc.size() != 3 * n) ev.xc.resize(3 * n);
  Eigen::Map<Eigen::MatrixXd> xm(ev.xc.data(), 3 * n, 1);
  gather_centred(w, w.X, rs.mass_fraction, xm);
  ev.key_z = z;
  ev.key = rs.id;
  return ev;
}

}  // namespace

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
  RsWork& w = work();
  const RsEval& ev = evaluate(w, lat, rs, z);
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
        Matrix3d dF;
        dF.noalias() = cross_matrix(dv) * F;
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
  solve(w, *rs.factor, w.BJ, &w.XJ, &w.YJ, &w.EJ);
  if (jacobian->rows() != 3 * n || jacobian->cols() != r) jacobian->resize(3 * n, r);
  gather_centred(w, w.XJ, rs.mass_fraction, *jacobian);
}

namespace {

// The reconstruction's adjoint: lambda = L^-1 P^T g (3 columns of n, in w.X), with
// P^T g = g - mass_fraction (sum_j g_j) per coordinate; the map is evaluated at z
// first (per-sample E, J, F). Shared by the vjp and the curvature.
const double* adjoint_multipliers(RsWork& w, const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                                  const Eigen::VectorXd& g, const RsEval*& ev) {
  ev = &evaluate(w, lat, rs, z);
  const int n = rs.nodes;
  w.ensure(w.B, n, 3);
  double* b = static_cast<double*>(w.B->x);
  for (int s = 0; s < 3; ++s) {
    double sum = 0;
    for (int j = 0; j < n; ++j) sum += g[3 * j + s];
    for (int j = 0; j < n; ++j) b[size_t(s) * size_t(n) + size_t(j)] = g[3 * j + s] - rs.mass_fraction[j] * sum;
  }
  solve(w, *rs.factor, w.B, &w.X, &w.Y, &w.E);
  return static_cast<const double*>(w.X->x);
}

// grad lambda at sample q of a cell: Lam(s, c) = sum_a lambda(ids[a], s) G_q(a, c).
Matrix3d adjoint_gradient(const double* lam, int n, const std::array<int, 8>& ids, const Eigen::Matrix<double, 8, 3>& Gq) {
  Eigen::Matrix<double, 3, 8> Lc;
  for (int a = 0; a < 8; ++a)
    for (int s = 0; s < 3; ++s) Lc(s, a) = lam[size_t(s) * size_t(n) + size_t(ids[a])];
  return Lc * Gq;
}

Vector3d axial2(const Matrix3d& A) { return Vector3d(A(2, 1) - A(1, 2), A(0, 2) - A(2, 0), A(1, 0) - A(0, 1)); }

}  // namespace

void rotation_strain_vjp(const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                         const Eigen::VectorXd& g, Eigen::VectorXd& out) {
  if (!rs.factor || z.size() != rs.r || lat.nodes() != rs.nodes || g.size() != 3 * rs.nodes)
    throw std::invalid_argument("rotation_strain_vjp: sizes do not match");
  RsWork& w = work();
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
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * e + q;
      const Matrix3d Lam = adjoint_gradient(lam, n, ids, G[q]);
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
  RsWork& w = work();
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
    const auto& ids = lat.cells[e];
    for (int q = 0; q < 8; ++q) {
      const int i = 8 * e + q;
      const Matrix3d Lam = adjoint_gradient(lam, n, ids, G[q]);
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

// ---- Reduced reconstruction -------------------------------------------------------

namespace {

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
  RsWork& w = work();
  w.ensure(w.BJ, n, 3 * K);
  double* bz = static_cast<double*>(w.BJ->x);
  for (int k = 0; k < K; ++k)
    for (int s = 0; s < 3; ++s)
      for (int j = 0; j < n; ++j) bz[size_t(3 * k + s) * size_t(n) + size_t(j)] = lat.node_mass_kg[j] * red->W(3 * j + s, k);
  solve(w, *rs.factor, w.BJ, &w.XJ, &w.YJ, &w.EJ);
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
