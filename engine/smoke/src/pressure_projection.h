// Pressure projection: make the MAC velocity divergence-free.
//   solve  A phi = -h^2 div(u)   (A from poisson.h: -h^2 Laplacian, Neumann at closed
//                                 walls, periodic with zero-mean rhs and solution)
//   then   u -= grad(phi)         (phi = p dt / rho, the projection potential, m^2/s)
// so that the discrete divergence of the result is zero up to the solver tolerance.
//
// Two solvers, both matrix-free and OpenMP-parallel:
//  * Jacobi-preconditioned CG (the baseline);
//  * multigrid-preconditioned CG (McAdams, Sifakis & Teran 2010 style): one geometric
//    V-cycle per CG iteration. Levels halve every axis while all are even and >= 4
//    (96x128 -> 48x64 -> ... -> 3x4); sizes with an odd axis just get fewer levels
//    (the coarsest level is then larger and costs more sweeps; no padding). Smoothing
//    is red-black Gauss-Seidel, ordered red-black before and black-red after the
//    coarse correction, restriction is the sum of the children and prolongation
//    piecewise constant (its transpose), and the coarsest level runs a fixed
//    symmetric sweep sequence, so the preconditioner is a symmetric positive
//    (semi-)definite linear operator and CG stays valid. Odd periodic levels use
//    damped Jacobi instead of red-black ordering.
#pragma once
#include <vector>

#include "mac_grid.h"
#include "poisson.h"

namespace pliant::smoke {

enum class PoissonMethod { MultigridPCG, JacobiPCG };

struct PoissonStats {
  int iterations = 0;
  double relative_residual = 0;  // ||b - A x|| / ||b|| (2-norm, zero-mean b)
};

// Owns every buffer the solve needs (allocated once in the constructor).
class PoissonSolver {
 public:
  explicit PoissonSolver(const MacGrid& g);
  // Solves A x = b; x is the warm start on entry. b is made zero-mean in place.
  PoissonStats solve(PoissonMethod method, double* b, double* x, double tolerance, int max_iterations);
  // z = M^-1 r for the chosen preconditioner (exposed for tests of symmetry).
  void precondition(PoissonMethod method, const double* r, double* z);

  int levels() const { return int(levels_.size()); }
  const PoissonLevel& level(int l) const { return levels_[l].shape; }
  size_t cells() const { return levels_[0].shape.cells(); }

  int pre_sweeps = 2, post_sweeps = 2;

 private:
  struct Level {
    PoissonLevel shape;
    std::vector<double> x, b, r;  // r doubles as Jacobi scratch
    int coarse_sweeps = 0;
  };
  void vcycle(int l);
  void smooth(Level& L, int sweeps, bool forward);

  std::vector<Level> levels_;
  std::vector<double> inv_diag_, r_, z_, d_, q_;
};

struct ProjectionStats {
  int iterations = 0;
  double relative_residual = 0;
  double max_divergence_before = 0, max_divergence_after = 0;  // 1/s
};

// Projects `vel` in place. `phi` (cells) is the warm start and receives the potential;
// `rhs` is scratch of cells() values.
ProjectionStats project(const MacGrid& g, PoissonSolver& solver, PoissonMethod method, double tolerance,
                        int max_iterations, FaceVelocityMut vel, double* phi, double* rhs);

}  // namespace pliant::smoke
