// Linear vibration modes of the lattice: K phi = omega^2 M phi with K the stable
// neo-Hookean Hessian at rest and M the lumped mass. The six rigid modes (null space
// of K) are removed explicitly (M-orthogonal deflation) because the reduced model
// carries rigid motion in its floating frame (translation c, rotation R).
// Small lattices (3N <= 900) use a dense symmetric eigensolver; larger ones use
// shift-invert subspace iteration with a CHOLMOD factorization of K + sigma M.
#pragma once
#include <Eigen/Core>

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

}  // namespace pliant::soft
