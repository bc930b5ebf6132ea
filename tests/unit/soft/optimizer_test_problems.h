// Small least-squares problems for the optimizer tests: the extended Rosenbrock
// residuals plus a damping residual 0.1 * sum(x), and their exact Jacobian.
#pragma once

#include <Eigen/Dense>

namespace pliant::soft::test {

inline Eigen::VectorXd rosenbrock_residuals(const Eigen::VectorXd& x) {
  Eigen::VectorXd r(x.size() + 1);
  for (int i = 0; i + 1 < x.size(); i += 2) {
    r[i] = 10 * (x[i + 1] - x[i] * x[i]);
    r[i + 1] = 1 - x[i];
  }
  r[x.size()] = 0.1 * x.sum();
  return r;
}

inline Eigen::MatrixXd rosenbrock_jacobian(const Eigen::VectorXd& x) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(x.size() + 1, x.size());
  for (int i = 0; i + 1 < x.size(); i += 2) {
    J(i, i) = -20 * x[i];
    J(i, i + 1) = 10;
    J(i + 1, i) = -1;
  }
  J.row(x.size()).setConstant(0.1);
  return J;
}

}  // namespace pliant::soft::test
