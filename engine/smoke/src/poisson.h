// Matrix-free cell-centred Poisson operator and the smoothers / grid transfers the
// multigrid preconditioner is built from.
//
// Scaled operator (A x)_c = sum over existing neighbours n of (x_c - x_n), i.e.
// A = -h^2 * Laplacian with homogeneous Neumann conditions at closed walls (a wall
// face contributes no term) and wrapping at periodic ones. A is symmetric positive
// semi-definite with the constants as null space in both cases; solvers keep
// right-hand sides and iterates zero-mean.
//
// Vectors are double: CG to relative residuals of 1e-6..1e-10 needs more than
// float's 7 digits (the velocity fields themselves are stored as float).
#pragma once
#include <array>
#include <cstddef>

namespace pliant::smoke {

// Below this many cells a loop runs serially: an OpenMP fork/join costs more than
// the work on coarse multigrid levels (and much more on a loaded machine).
inline constexpr size_t kOmpMinCells = 4096;

// Sums over [0, n) in a fixed partition into kSumBlocks blocks: block(i0, i1) sums its
// range in index order, then the block sums are added in block order. The same bits
// for any thread count (an OpenMP reduction's order depends on it), so the control
// solvers give identical results on 1 and 2 threads.
inline constexpr int kSumBlocks = 64;
template <class Block>
double fixed_order_block_sum(size_t n, bool parallel, const Block& block) {
  double part[kSumBlocks];
#pragma omp parallel for schedule(static) if (parallel)
  for (int b = 0; b < kSumBlocks; ++b) part[b] = block(n * size_t(b) / kSumBlocks, n * size_t(b + 1) / kSumBlocks);
  double s = 0;
  for (int b = 0; b < kSumBlocks; ++b) s += part[b];
  return s;
}
// sum of term(i), i in [0, n), in the same fixed order.
template <class Term>
double fixed_order_sum(size_t n, const Term& term) {
  return fixed_order_block_sum(n, n >= 16 * kOmpMinCells, [&](size_t i0, size_t i1) {
    double s = 0;
    for (size_t i = i0; i < i1; ++i) s += term(i);
    return s;
  });
}

struct PoissonLevel {
  int dim = 2;
  std::array<int, 3> n{1, 1, 1};
  bool periodic = false;
  size_t cells() const { return size_t(n[0]) * n[1] * n[2]; }
  // Red-black Gauss-Seidel needs no two neighbours of one colour: false when a
  // periodic axis has an odd number of cells (then damped Jacobi is used).
  bool red_black_ok() const {
    if (!periodic) return true;
    for (int a = 0; a < dim; ++a)
      if (n[a] % 2) return false;
    return true;
  }
  // True when this level can be coarsened by 2 along every axis (even and >= 4).
  bool coarsenable() const {
    for (int a = 0; a < dim; ++a)
      if (n[a] % 2 || n[a] < 4) return false;
    return true;
  }
};

// y = A x.
void poisson_apply(const PoissonLevel& L, const double* x, double* y);
// r = b - A x; returns sum(r^2).
double poisson_residual(const PoissonLevel& L, const double* b, const double* x, double* r);
// Diagonal of A (number of neighbour terms) for cell c.
void poisson_diagonal(const PoissonLevel& L, double* diag);
// One red-black Gauss-Seidel half sweep over the cells of `colour` (0 or 1).
void poisson_gauss_seidel_colour(const PoissonLevel& L, const double* b, double* x, int colour);
// One damped-Jacobi sweep x += omega D^-1 (b - A x); `tmp` holds cells() values.
void poisson_jacobi_sweep(const PoissonLevel& L, const double* b, double* x, double* tmp,
                          double omega);
// Coarse right-hand side from a fine residual (sum of the 2^dim children, scaled by
// 4 / 2^dim so the coarse equation is the rediscretised operator at 2h).
void poisson_restrict(const PoissonLevel& fine, const PoissonLevel& coarse, const double* r_fine,
                      double* b_coarse);
// x_fine += piecewise-constant prolongation of x_coarse (the transpose of the
// restriction up to its constant factor, which keeps the V-cycle symmetric).
void poisson_prolong_add(const PoissonLevel& fine, const PoissonLevel& coarse, const double* x_coarse,
                         double* x_fine);
// Subtracts the mean (projection onto the complement of the null space).
void remove_mean(double* x, size_t n);

}  // namespace pliant::smoke
