// Cubature for the reduced elastic force (An, Kim, James 2008 "Optimizing cubature
// for efficient integration of subspace deformations"; used by Pan & Manocha 2018
// for the elastic/kinetic terms): the reduced force U^T f(X + U q) = sum over all
// cells is replaced by sum_{e in S} w_e U^T f_e with a small cell set S and weights
// w >= 0, fitted on training poses q_p by greedy selection + non-negative least
// squares (Lawson-Hanson), until the relative fit error is below `tolerance`.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "pliant/soft/fem.h"

namespace pliant::soft {

struct Character;

struct CubatureReport {
  int cells = 0;              // kept cells (0 = cubature off)
  double kept_fraction = 0;   // cells / all cells
  double training_error = 0;  // relative force error on the training poses
};

// Lawson-Hanson NNLS: min |A w - b| subject to w >= 0.
Eigen::VectorXd nnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, int max_iterations = 500);

// Largest node displacement (relative to the lattice size) of the extra training
// poses for rotation-strain coordinates (cubature and reduced reconstruction).
constexpr double rotation_strain_training_amplitude = 0.3;

// Random training poses: modal amplitudes with the largest node displacement up to
// `amplitude_rel` times the lattice's size, fixed seed.
std::vector<Eigen::VectorXd> training_poses(const Character& ch, int count, double amplitude_rel, unsigned seed);

// Reduced elastic force U^T (-dE/dx) at pose q with the given weights (rotation-strain
// coordinates: J(q)^T (-dE/dx) at the reconstructed shape).
Eigen::VectorXd reduced_force(const Character& ch, const Eigen::VectorXd& q, const CellWeights& w);

// Greedy selection + NNLS on a column per cell (A: rows x cells) against the target
// b: the cell whose column best matches the residual (normalized correlation) joins
// until |A_S w - b| <= tolerance |b| or max_cells; *fit_error = final relative residual.
CellWeights greedy_cubature(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double tolerance, int max_cells,
                            double* fit_error);

// Fits the cubature on the poses; max_cells caps the set. With rotation-strain
// coordinates the poses are reconstructed by the character's map (local_shape) and the
// force is J^T f; poses of rotation_strain_training_amplitude (large rotations) are
// added to the given ones, so the weights are trained where the coordinates rotate.
CellWeights fit_cubature(const Character& ch, const std::vector<Eigen::VectorXd>& poses, double tolerance,
                         int max_cells, CubatureReport* report);

}  // namespace pliant::soft
