// Exact solve of one SCGS block: a cell's unknowns (its 2*dim face velocities and
// its pressure-like dual) across all T timesteps form a block-tridiagonal system
//   L_t x_{t-1} + B_t x_t + U_t x_{t+1} = r_t,   t = 0..T-1,  blocks m x m (m <= 7),
// solved by the block Thomas algorithm (block LU without pivoting between blocks,
// partial pivoting inside each m x m Schur complement, which is indefinite here:
// the dual's diagonal entry is 0). Row-major m x m blocks stored contiguously.
#pragma once
#include <cstddef>

namespace pliant::smoke {

inline constexpr int kScgsMaxBlock = 7;

// In-place LU with partial pivoting of an m x m row-major matrix; false if singular.
bool dense_lu_factor(int m, double* a, int* piv);
// Solves (LU) x = b in place for `nrhs` right-hand sides stored as columns of a
// row-major m x nrhs matrix.
void dense_lu_solve(int m, const double* lu, const int* piv, double* b, int nrhs);

// Scratch for block_tridiagonal_solve: T*m*m + T*m*m + T*m doubles and T*m ints.
struct BlockTridiagonalScratch {
  double* schur = nullptr;  // T*m*m: LU of the Schur complements S_t
  double* sinv_u = nullptr; // T*m*m: S_t^-1 U_t
  int* piv = nullptr;       // T*m
};

// B, L, U: T blocks each (L[0] and U[T-1] unused). rhs: T*m, overwritten with x.
// Returns false if a Schur complement is singular.
bool block_tridiagonal_solve(int T, int m, const double* B, const double* L, const double* U,
                             double* rhs, const BlockTridiagonalScratch& s);

}  // namespace pliant::smoke
