// Hexahedral FEM on the lattice: trilinear elements, 2x2x2 Gauss quadrature, stable
// neo-Hookean energy (Smith, de Goes, Kim 2018):
//   psi(F) = mu/2 (tr(F^T F) - 3) + lam/2 (J - alpha)^2,  alpha = 1 + mu/lam,
// with lam = lambda_Lame + mu so the linearization at rest is linear elasticity with
// the user's Young's modulus and Poisson ratio. Chosen over corotational for an exact
// Hessian without polar-decomposition derivatives, and over classic neo-Hookean
// because it stays finite for inverted elements (J <= 0) that large steps can produce.
#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <cstddef>
#include <vector>

#include "pliant/soft/body.h"

namespace pliant::soft {

// [v]x, the cross-product matrix: [v]x u = v x u.
inline Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v[2], v[1], v[2], 0, -v[0], -v[1], v[0], 0;
  return m;
}

struct Material {
  double density_kg_per_m3 = 1000;
  double young_pa = 1e5;
  double poisson = 0.3;
};

struct Lame {
  double mu = 0, lam = 0;  // lam of the stable neo-Hookean form (Lame lambda + mu)
};
Lame lame_from(const Material& m);

// Energy density, first Piola-Kirchhoff stress and dP/dF (9x9, column-major vec(F)).
double snh_energy(const Lame& l, const Eigen::Matrix3d& F);
Eigen::Matrix3d snh_stress(const Lame& l, const Eigen::Matrix3d& F);
Eigen::Matrix<double, 9, 9> snh_stress_derivative(const Lame& l, const Eigen::Matrix3d& F);

// Per-cell weights: cubature keeps a subset of cells with non-negative weights.
// Empty elements = every cell with weight 1.
struct CellWeights {
  std::vector<int> cells;
  std::vector<double> weights;
  bool all() const { return cells.empty(); }
};

// Elastic energy of the lattice at node positions x (3 * nodes). When grad is not
// null it receives dE/dx (resized, overwritten); when hess is not null it receives
// d2E/dx2 (sparse, 3N x 3N).
double elastic_energy(const Lattice& lat, const Lame& l, const Eigen::VectorXd& x, const CellWeights& cw,
                      Eigen::VectorXd* grad, Eigen::SparseMatrix<double>* hess);

// Reduced elastic gradient U^T dE/dx and Hessian U^T K U at x, accumulated cell by
// cell (no 3N x 3N matrix): per Gauss point D = dvec(F)/dq (9 x r), H += w D^T A D
// (one triangle, mirrored). Each thread keeps every cell's D with the 24 rows of U it
// came from and rebuilds a cell only when those rows change, so a constant basis
// (linear modes, POD) pays for D once; memory per thread: cells x (72 + 24) x r
// doubles (spider, 33 cubature cells, r = 10: 253 KB), not kept above 32 MB.
double elastic_reduced(const Lattice& lat, const Lame& l, const Eigen::VectorXd& x, const CellWeights& cw,
                       const Eigen::MatrixXd& U, Eigen::VectorXd* grad, Eigen::MatrixXd* hess);

// Largest cache elastic_reduced keeps per thread, in doubles (default 4 Mi = 32 MB);
// returns the previous limit. For tests of the uncached path.
size_t set_reduced_cache_limit(size_t doubles);

// dN_a/dX of the 8 trilinear shape functions (rows a) at the 8 Gauss points, cell size h
// (cached per thread).
const std::array<Eigen::Matrix<double, 8, 3>, 8>& gauss_shape_gradients(double h);

// Internal force of one cell (24 values: -dE/dx of its 8 nodes).
void cell_force(const Lattice& lat, const Lame& l, const Eigen::VectorXd& x, int cell, double* f24);

// Volume of the lattice at node positions x (3N): sum over Gauss points of vol det F.
double lattice_volume(const Lattice& lat, const Eigen::VectorXd& x);

}  // namespace pliant::soft
