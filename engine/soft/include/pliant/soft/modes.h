// Linear vibration modes of the lattice: K phi = omega^2 M phi with K the stable
// neo-Hookean Hessian at rest and M the lumped mass. The six rigid modes (null space
// of K) are removed explicitly (M-orthogonal deflation) because the reduced model
// carries rigid motion in its floating frame (translation c, rotation R).
// Small lattices (3N <= 900) use a dense symmetric eigensolver; larger ones use
// shift-invert subspace iteration with a CHOLMOD factorization of K + sigma M.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "pliant/soft/body.h"
#include "pliant/soft/fem.h"

namespace pliant::soft {

struct ModalBasis {
  Eigen::MatrixXd U;        // 3N x r, U^T M U = I, M-orthogonal to rigid motion
  Eigen::VectorXd omega2;   // eigenvalues (1/s^2), ascending
  int r() const { return int(U.cols()); }
};

// The 6 rigid modes (3 translations, 3 infinitesimal rotations about the centre of
// mass), M-orthonormal.
Eigen::MatrixXd rigid_modes(const Lattice& lat);

// r lowest non-rigid modes; r is clamped to 3N - 6.
ModalBasis linear_modes(const Lattice& lat, const Lame& lame, int r);

// Adds the modal derivatives of the first k modes (Barbic & James 2005): for i <= j < k
// solve K Psi_ij = -(dK/dphi_i) phi_j (dK/dphi_i by central differences of the
// assembled Hessian, K regularized by sigma M and factored once with CHOLMOD), then
// M-orthonormalizes [U, Psi], removes rigid motion and rotates the basis so that
// U^T K U is diagonal again (omega2 ascending). Captures the quadratic coupling of
// large bending that linear modes miss.
ModalBasis with_modal_derivatives(const Lattice& lat, const Lame& lame, const ModalBasis& b, int k);

// Nonlinear POD (proper orthogonal decomposition) of simulated poses: the r dominant
// M-weighted principal directions of the displacement snapshots (rigid motion removed
// from each), M-orthonormalized and rotated so that U^T K U is diagonal (omega2 are
// then Rayleigh quotients, ascending). Snapshots are 3N local displacements.
// M-orthonormalizes the columns of B (rigid motion removed) and rotates them so that
// U^T K U is diagonal (omega2 ascending).
ModalBasis rayleigh_ritz(const Lattice& lat, const Lame& lame, Eigen::MatrixXd B);

ModalBasis pod_basis(const Lattice& lat, const Lame& lame, const std::vector<Eigen::VectorXd>& snapshots, int r);

}  // namespace pliant::soft
