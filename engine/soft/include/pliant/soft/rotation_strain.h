// Rotation-strain (RS) coordinates (Pan, Bao, Huang et al., "Subspace dynamic
// simulation using rotation-strain coordinates", SIGGRAPH Asia 2015): a nonlinear map
// from modal coordinates z to node positions that rotates parts of the body instead of
// stretching them. At every Gauss point i of the lattice and for every basis vector
// U_k, the displacement gradient grad U_k splits into its skew part (rotation vector
// w_ik) and symmetric part (strain s_ik). For coordinates z the target deformation
// gradient is
//   F_i(z) = exp([sum_k z_k w_ik]x) (I + sum_k z_k s_ik),
// and the positions are its least-squares integration
//   x(z) = argmin sum_i vol_i |G_i x - F_i(z)|^2,
// G_i x the deformation gradient of x at Gauss point i. The normal matrix G^T W G is
// the lattice's scalar Laplacian L (N x N) times I_3; its only null space is
// translation, fixed by pinning node 0 and then moving the mass-weighted centroid to
// 0 (exact: translation does not change the residual). L is factored once with
// CHOLMOD; a reconstruction is one solve with 3 right-hand sides and the Jacobian
// dx/dz = L^-1 G^T W dF/dz is one solve with 3 r right-hand sides
// (dF/dz_k = [J(v) w_k]x exp([v]x) S + exp([v]x) s_k, J the left Jacobian of SO(3)).
// Per-Gauss-point targets make x(z) = X + U z + O(|z|^2) exactly (U z's gradient is
// reproduced with zero residual), and a pure rotation field reconstructs a rigid
// rotation with no volume change where linear modes grow the body.
// Reconstruction buffers (CHOLMOD dense matrices, per-sample vectors) live in a
// thread-local workspace: after the first call with given sizes nothing is allocated,
// and concurrent threads (parallel rollouts) do not share buffers.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "pliant/soft/body.h"

namespace pliant::soft {

struct RsFactor;  // CHOLMOD factor of L (opaque; src/rotation_strain_workspace.h)
struct RsReduced;


struct RotationStrain {
  int nodes = 0, r = 0, samples = 0;   // samples = 8 Gauss points x cells
  double sample_volume = 0;            // h^3 / 8
  Eigen::MatrixXd rot;                 // 3 samples x r: rotation vectors w_ik
  Eigen::MatrixXd strain;              // 9 samples x r: symmetric strains s_ik (column-major 3x3)
  Eigen::VectorXd mass_fraction;       // N: node mass / total mass (centroid)
  Eigen::MatrixXd U;                   // 3N x r: the basis (per-sample rot z and strain z are
                                       // taken from the nodal U z per cell: 12x less data than rot, strain)
  std::shared_ptr<const RsFactor> factor;
  // Unique per rotation_strain_build (copies share it): keys the per-thread cache of
  // the last evaluation (per-sample exp, positions), so the positions, adjoint,
  // Jacobian and curvature at one z share one exp pass.
  std::uint64_t id = 0;
  // Set by rotation_strain_reduce: the step then uses the reduced reconstruction
  // (below) instead of the full solve.
  std::shared_ptr<const RsReduced> reduced;
};

// Reduced reconstruction (playback cost scales with a cubature set, not the lattice).
// The map is linear in the per-sample targets F_i, and x(z) = Xbar + U z exactly to
// first order, so only the nonlinear remainder N_i(z) = F_i(z) - I - grad(U z)_i is
// approximated, in two ways:
//  * projection: x(z) = Xbar + U z + W c(z), W = [U V] (M-orthonormal, centred), V the
//    M-weighted POD of what exact reconstructions of training poses hold beyond U;
//  * cubature over cells: c(z) = W^T M L^-1 sum_i vol G_i^T N_i(z) = sum_i C_i N_i(z)
//    (C_i = vol W_s^T M L^-1 G_i per coordinate s, precomputed: one solve with
//    3 (r + m) columns at build) is replaced by sum over a few cells e with weights
//    w_e >= 0, fitted by greedy NNLS (cubature.h) to c and dc/dz on the poses.
// Per evaluation: the cubature samples' exp and 3x3 products, one gemv/gemm with C,
// and x = Xbar + W (z; 0) + W c over the nodes (dense, no solve).
struct RsReduced {
  int r = 0, m = 0;               // modes, POD vectors beyond U
  Eigen::VectorXd rest;           // 3N, Xbar (centred rest shape)
  Eigen::MatrixXd W;              // 3N x (r + m): [U V]
  std::vector<int> cells;         // cubature cells of the remainder
  std::vector<double> weights;
  Eigen::MatrixXd C;              // (r + m) x 9 S' (S' = 8 cells.size()), weights folded in
  Eigen::MatrixXd rot, strain;    // 3 S' x r, 9 S' x r: w_ik, s_ik at the cubature samples
  Eigen::VectorXd hstep;          // r: curvature difference step per coordinate
  double basis_error = 0;         // training poses: |P_W dx - dx|_M / |dx|_M (worst)
  double cubature_error = 0;      // training: relative fit error of (c, dc/dz)
};

struct RsReductionSettings {
  double basis_tolerance = 0.01;    // POD: relative M-norm energy left out <= tol^2
  int max_basis = 30;               // m at most
  double cubature_tolerance = 0.01; // relative fit error of (c, dc/dz) on the poses
  int max_cells = 400;
};

// Builds the reduced reconstruction of rs for the basis U (the one rs was built
// from), rest_local (Xbar, centred), lumped node masses and training coordinates.
std::shared_ptr<const RsReduced> rotation_strain_reduce(const Lattice& lat, const RotationStrain& rs,
                                                        const Eigen::MatrixXd& U, const Eigen::VectorXd& rest_local,
                                                        const std::vector<Eigen::VectorXd>& poses,
                                                        const RsReductionSettings& settings);

// Reduced map: x = Xbar + U z + W c(z) (3N) and optionally dx/dz = U + W dc/dz.
// Allocates nothing once x/jacobian have their sizes.
void rotation_strain_reduced_positions(const RsReduced& red, const Eigen::VectorXd& z, Eigen::VectorXd& x,
                                       Eigen::MatrixXd* jacobian = nullptr);

// Curvature term (as rotation_strain_curvature) of the reduced map: the adjoint is
// W^T g, then central differences over the cubature samples only.
void rotation_strain_reduced_curvature(const RsReduced& red, const Eigen::VectorXd& z, const Eigen::VectorXd& g,
                                       Eigen::MatrixXd& curvature);

// Splits the gradients of the columns of U (3N x r, local displacements) at every
// Gauss point and factors L. Throws std::runtime_error when CHOLMOD fails.
RotationStrain rotation_strain_build(const Lattice& lat, const Eigen::MatrixXd& U);

// Positions (3N, xyz per node, mass-weighted centroid 0) for coordinates z (r); with
// jacobian, also dx/dz (3N x r, centroid-free columns). x and jacobian are resized
// only when their size differs.
void rotation_strain_positions(const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                               Eigen::VectorXd& x, Eigen::MatrixXd* jacobian = nullptr);

// Vector-Jacobian product (dx/dz)^T g for a nodal vector g (3N) by the adjoint: one
// 3-column solve L lambda = P^T g, then sum_i vol <dF_i/dz_k, grad lambda_i> per
// sample (no 3r-column solve, no per-mode scatter). out: r values.
void rotation_strain_vjp(const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                         const Eigen::VectorXd& g, Eigen::VectorXd& out);

// Second-order term of the map for a fixed nodal vector g (3N, e.g. dE/dx):
//   curvature(a, b) = sum_j g_j . d2x_j / dz_a dz_b   (r x r, symmetric),
// the part of the exact Hessian that Gauss-Newton (J^T K J) drops. Adjoint form:
// J^T g = sum_i vol <dF_i/dz, grad lambda_i> with L lambda = P^T g (one solve, P the
// centroid removal), differentiated in z in closed form (derivative of the left
// Jacobian of SO(3) included; no more solves, no exp).
void rotation_strain_curvature(const Lattice& lat, const RotationStrain& rs, const Eigen::VectorXd& z,
                               const Eigen::VectorXd& g, Eigen::MatrixXd& curvature);

}  // namespace pliant::soft
