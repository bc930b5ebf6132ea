// Internals shared by the rotation-strain translation units (rotation_strain.cpp: the
// map and its Jacobian; rotation_strain_adjoint.cpp: vjp and curvature;
// rotation_strain_reduced.cpp: the reduced reconstruction): the CHOLMOD factor of the
// lattice Laplacian, the per-thread workspace with its cache of the last two map
// evaluations, and the SO(3) exponential with its left Jacobian.
#pragma once
#include <cholmod.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "pliant/soft/fem.h"
#include "pliant/soft/rotation_strain.h"

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

// exp([v]x) (Rodrigues) and the left Jacobian of SO(3):
// d/dt exp([v + t d]x) = [J(v) d]x exp([v]x), J = I + a [v]x + b [v]x^2.
// exp_coefficients: s = sin t / t, c = (1 - cos t) / t^2 (= a), b = (t - sin t) / t^3.
inline void exp_coefficients(const Eigen::Vector3d& v, double* s, double* c, double* b) {
  const double t2 = v.squaredNorm(), t = std::sqrt(t2);
  if (t < 1e-4) {
    *s = 1 - t2 / 6, *c = 0.5 - t2 / 24, *b = 1.0 / 6 - t2 / 120;
  } else {
    const double it = 1 / t, sn = std::sin(t);  // one division: they are most of the latency
    *s = sn * it, *c = (1 - std::cos(t)) * (it * it), *b = (t - sn) * (it * it * it);
  }
}

// J from v and its coefficients a (= c) and b: the map builds it only where a
// Jacobian, adjoint or curvature reads it (line-search trials do not).
inline void so3_left_jacobian(const Eigen::Vector3d& v, double a, double b, Eigen::Matrix3d* J) {
  const double t2 = v.squaredNorm();
  const Eigen::Matrix3d V = cross_matrix(v), vv = v * v.transpose();
  *J = a * V + b * vv;
  J->diagonal().array() += 1 - b * t2;
}

inline void exp_and_jacobian(const Eigen::Vector3d& v, Eigen::Matrix3d* E, Eigen::Matrix3d* J) {
  double s, c, b;
  exp_coefficients(v, &s, &c, &b);
  const double t2 = v.squaredNorm();
  // [v]x^2 = v v^T - t^2 I.
  const Eigen::Matrix3d V = cross_matrix(v), vv = v * v.transpose();
  *E = s * V + c * vv;
  E->diagonal().array() += 1 - c * t2;
  if (J) so3_left_jacobian(v, c, b, J);
}

// One evaluation of the map: per-sample rotation vector, strain, rotation E, left
// Jacobian J and F = E S, and the centred positions, for coordinates key_z.
struct RsEval {
  std::uint64_t key = 0;  // RotationStrain::id (0: empty)
  Eigen::VectorXd key_z, xc, v, sv;  // z; positions (3N); rotation vectors (3 S), strains (9 S)
  std::vector<Eigen::Matrix3d> Es, Js, Fs;
  Eigen::VectorXd cb;      // per sample the Jacobian's coefficients a, b (2 S)
  bool has_j = false;      // Js filled (rs_evaluate with need_j)
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

// The calling thread's workspace (rotation_strain.cpp).
RsWork& rs_work();

// X = L^-1 B with w's CHOLMOD buffers (X, Y, E reused when their shapes fit).
void rs_solve(RsWork& w, const RsFactor& f, cholmod_dense* B, cholmod_dense** X, cholmod_dense** Y,
              cholmod_dense** E);

// Copies the N x ncol solution into out (3N x cols/3; x[3j+s] of column k is
// X(j, 3k+s)) with each coordinate's mass-weighted mean removed.
template <typename Out>
void rs_gather_centred(const RsWork& w, const cholmod_dense* X, const Eigen::VectorXd& mf, Out& out) {
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

// Evaluates the map at z (per-sample E, F and the centred positions; J too with
// need_j), unless a slot already holds z for this basis (then J is added if missing).
const RsEval& rs_evaluate(RsWork& w, const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                          bool need_j = true);

}  // namespace pliant::soft
