// Periodic Dynamic Movement Primitives (Ijspeert et al. 2013, rhythmic form), one
// per controlled mode, as in Pan & Manocha TOG 2018 section 6: the activation y_k
// of mode k follows
//   tau dz = alpha (beta (g_k - y_k) - z) + f_k(phi),   tau dy = z,   dphi = 1 / tau,
//   f_k(phi) = sum_i psi_i(phi) w_ki / sum_i psi_i(phi),  psi_i = exp(h (cos(phi - c_i) - 1)),
// with tau = period / (2 pi), alpha = 25, beta = alpha / 4 (critically damped) and
// kernels c_i evenly spaced on the circle. Activations are in metres of the mode's
// largest node displacement; the modal control force is u_k = omega_k^2 y_k / s_k
// (the force that would hold mode k at that amplitude).
// Parameters theta = [w_k1..w_kK, g_k] for each controlled mode k.
#pragma once
#include <Eigen/Core>

namespace pliant::soft {

struct DmpSpec {
  int modes = 0;          // controlled modes (the lowest ones)
  int kernels = 6;
  double period_s = 1.0;
  double alpha = 25;
  double kernel_width = 2.5;  // h
  double max_activation_rel = 0.3;  // activation bound, times the body's radius
  int parameters() const { return modes * (kernels + 1); }
};

struct DmpState {
  double phase = 0;
  Eigen::VectorXd y, z;  // per controlled mode
};

DmpState dmp_init(const DmpSpec& spec);
// Advances by dt (semi-implicit Euler) and returns the activations y (modes values).
const Eigen::VectorXd& dmp_step(const DmpSpec& spec, const Eigen::VectorXd& theta, double dt, DmpState& s);
// The forcing term f(phi) for all controlled modes.
Eigen::VectorXd dmp_forcing(const DmpSpec& spec, const Eigen::VectorXd& theta, double phase);

}  // namespace pliant::soft
