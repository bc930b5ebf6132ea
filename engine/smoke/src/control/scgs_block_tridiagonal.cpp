#include "scgs_block_tridiagonal.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace pliant::smoke {

namespace {

template <int M>
bool lu_factor_t(int m_rt, double* a, int* piv) {
  const int m = M > 0 ? M : m_rt;
  for (int k = 0; k < m; ++k) {
    int p = k;
    double best = std::abs(a[k * m + k]);
    for (int i = k + 1; i < m; ++i)
      if (std::abs(a[i * m + k]) > best) best = std::abs(a[i * m + k]), p = i;
    piv[k] = p;
    if (best == 0.0) return false;
    if (p != k)
      for (int j = 0; j < m; ++j) std::swap(a[k * m + j], a[p * m + j]);
    const double inv = 1.0 / a[k * m + k];
    for (int i = k + 1; i < m; ++i) {
      const double l = a[i * m + k] * inv;
      a[i * m + k] = l;
      for (int j = k + 1; j < m; ++j) a[i * m + j] -= l * a[k * m + j];
    }
  }
  return true;
}

template <int M, int R>
void lu_solve_t(int m_rt, const double* lu, const int* piv, double* b, int nrhs_rt) {
  const int m = M > 0 ? M : m_rt;
  const int nrhs = R > 0 ? R : nrhs_rt;
  for (int k = 0; k < m; ++k)
    if (piv[k] != k)
      for (int c = 0; c < nrhs; ++c) std::swap(b[k * nrhs + c], b[piv[k] * nrhs + c]);
  for (int i = 1; i < m; ++i)
    for (int k = 0; k < i; ++k) {
      const double l = lu[i * m + k];
      if (l != 0.0)
        for (int c = 0; c < nrhs; ++c) b[i * nrhs + c] -= l * b[k * nrhs + c];
    }
  for (int i = m - 1; i >= 0; --i) {
    const double inv = 1.0 / lu[i * m + i];
    for (int c = 0; c < nrhs; ++c) {
      double s = b[i * nrhs + c];
      for (int k = i + 1; k < m; ++k) s -= lu[i * m + k] * b[k * nrhs + c];
      b[i * nrhs + c] = s * inv;
    }
  }
}

// The same for the first nc columns of a row-major m x m right-hand side (columns
// nc..m-1 are zero and stay zero: SCGS's U blocks have no dual column).
template <int M>
void lu_solve_cols_t(int m_rt, const double* lu, const int* piv, double* b, int nc) {
  const int m = M > 0 ? M : m_rt;
  for (int k = 0; k < m; ++k)
    if (piv[k] != k)
      for (int c = 0; c < nc; ++c) std::swap(b[k * m + c], b[piv[k] * m + c]);
  for (int i = 1; i < m; ++i)
    for (int k = 0; k < i; ++k) {
      const double l = lu[i * m + k];
      if (l != 0.0)
        for (int c = 0; c < nc; ++c) b[i * m + c] -= l * b[k * m + c];
    }
  for (int i = m - 1; i >= 0; --i) {
    const double inv = 1.0 / lu[i * m + i];
    for (int c = 0; c < nc; ++c) {
      double s = b[i * m + c];
      for (int k = i + 1; k < m; ++k) s -= lu[i * m + k] * b[k * m + c];
      b[i * m + c] = s * inv;
    }
  }
}

template <int M>
bool block_solve_t(int T, int m_rt, const double* B, const double* L, const double* U, double* rhs,
                   const BlockTridiagonalScratch& s) {
  const int m = M > 0 ? M : m_rt;
  const int mm = m * m;
  // Columns of the U blocks after the last non-zero one are zero, and so are those of
  // S^-1 U: solve and eliminate only the leading nc columns.
  int nc = 0;
  for (int t = 0; t + 1 < T; ++t)
    for (int e = 0; e < mm; ++e)
      if (U[size_t(t) * mm + e] != 0.0) nc = std::max(nc, e % m + 1);
  // Forward elimination: S_0 = B_0; S_t = B_t - L_t S_{t-1}^-1 U_{t-1};
  // y_t = r_t - L_t S_{t-1}^-1 y_{t-1} (y overwrites rhs, already multiplied by S^-1).
  for (int t = 0; t < T; ++t) {
    double* S = s.schur + size_t(t) * mm;
    for (int e = 0; e < mm; ++e) S[e] = B[size_t(t) * mm + e];
    double* y = rhs + size_t(t) * m;
    if (t > 0) {
      const double* Lt = L + size_t(t) * mm;
      const double* X = s.sinv_u + size_t(t - 1) * mm;  // S_{t-1}^-1 U_{t-1}
      const double* yp = rhs + size_t(t - 1) * m;       // S_{t-1}^-1 y_{t-1}
      for (int i = 0; i < m; ++i)
        for (int k = 0; k < m; ++k) {
          const double l = Lt[i * m + k];
          if (l == 0.0) continue;
          for (int j = 0; j < nc; ++j) S[i * m + j] -= l * X[k * m + j];
          y[i] -= l * yp[k];
        }
    }
    int* piv = s.piv + size_t(t) * m;
    if (!lu_factor_t<M>(m, S, piv)) return false;
    lu_solve_t<M, 1>(m, S, piv, y, 1);
    if (t + 1 < T) {
      double* X = s.sinv_u + size_t(t) * mm;
      for (int e = 0; e < mm; ++e) X[e] = U[size_t(t) * mm + e];
      lu_solve_cols_t<M>(m, S, piv, X, nc);
    }
  }
  // Back substitution: x_t = y_t - S_t^-1 U_t x_{t+1}.
  for (int t = T - 2; t >= 0; --t) {
    const double* X = s.sinv_u + size_t(t) * mm;
    double* x = rhs + size_t(t) * m;
    const double* xn = rhs + size_t(t + 1) * m;
    for (int i = 0; i < m; ++i) {
      double acc = 0;
      for (int k = 0; k < nc; ++k) acc += X[i * m + k] * xn[k];
      x[i] -= acc;
    }
  }
  return true;
}

}  // namespace

// Fixed sizes for the SCGS blocks (2D: 5, 3D: 7) so the compiler unrolls the loops.
bool dense_lu_factor(int m, double* a, int* piv) { return lu_factor_t<0>(m, a, piv); }
void dense_lu_solve(int m, const double* lu, const int* piv, double* b, int nrhs) {
  lu_solve_t<0, 0>(m, lu, piv, b, nrhs);
}
bool block_tridiagonal_solve(int T, int m, const double* B, const double* L, const double* U, double* rhs,
                             const BlockTridiagonalScratch& s) {
  if (m == 5) return block_solve_t<5>(T, m, B, L, U, rhs, s);
  if (m == 7) return block_solve_t<7>(T, m, B, L, U, rhs, s);
  return block_solve_t<0>(T, m, B, L, U, rhs, s);
}

}  // namespace pliant::smoke
