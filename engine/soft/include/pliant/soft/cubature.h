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

// Random training poses: modal amplitudes with the largest node displacement up to
// `amplitude_rel` times the lattice's size, fixed seed.
std::vector<Eigen::VectorXd> training_poses(const Character& ch, int count, double amplitude_rel, unsigned seed);

// Reduced elastic force U^T (-dE/dx) at pose q with the given weights.
Eigen::VectorXd reduced_force(const Character& ch, const Eigen::VectorXd& q, const CellWeights& w);

// Fits the cubature on the poses; max_cells caps the set.
CellWeights fit_cubature(const Character& ch, const std::vector<Eigen::VectorXd>& poses, double tolerance,
                         int max_cells, CubatureReport* report);

}  // namespace pliant::soft
