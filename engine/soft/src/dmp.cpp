// Periodic DMP (see dmp.h).
#include "pliant/soft/dmp.h"

#include <cmath>

namespace pliant::soft {

DmpState dmp_init(const DmpSpec& spec) {
  DmpState s;
  s.y = Eigen::VectorXd::Zero(spec.modes);
  s.z = Eigen::VectorXd::Zero(spec.modes);
  return s;
}

namespace {
// Normalized kernel activations psi_i(phase) / sum psi (psi has spec.kernels values).
void kernel_weights(const DmpSpec& spec, double phase, Eigen::VectorXd& psi) {
  for (int i = 0; i < spec.kernels; ++i) {
    const double c = 2 * M_PI * i / spec.kernels;
    psi[i] = std::exp(spec.kernel_width * (std::cos(phase - c) - 1));
  }
  psi /= psi.sum();
}
}  // namespace

Eigen::VectorXd dmp_forcing(const DmpSpec& spec, const Eigen::VectorXd& theta, double phase) {
  Eigen::VectorXd psi(spec.kernels);
  kernel_weights(spec, phase, psi);
  Eigen::VectorXd f(spec.modes);
  for (int k = 0; k < spec.modes; ++k) f[k] = theta.segment(k * (spec.kernels + 1), spec.kernels).dot(psi);
  return f;
}

const Eigen::VectorXd& dmp_step(const DmpSpec& spec, const Eigen::VectorXd& theta, double dt, DmpState& s) {
  const double tau = spec.period_s / (2 * M_PI), beta = spec.alpha / 4;
  // Substeps keep the explicit transformation system stable (alpha h / tau <= 0.25);
  // a simulation frame is often longer than the DMP's time constant.
  const int sub = std::max(1, int(std::ceil(spec.alpha * dt / tau / 0.25)));
  const double h = dt / sub;
  // Kernel activations in a per-thread buffer (same values as dmp_forcing, no
  // allocation per step: the playback loop is allocation-free).
  thread_local Eigen::VectorXd psi;
  if (psi.size() != spec.kernels) psi.resize(spec.kernels);
  for (int i = 0; i < sub; ++i) {
    kernel_weights(spec, s.phase, psi);
    for (int k = 0; k < spec.modes; ++k) {
      const double fk = theta.segment(k * (spec.kernels + 1), spec.kernels).dot(psi);
      const double g = theta[k * (spec.kernels + 1) + spec.kernels];
      // The forcing is scaled by alpha beta so w reads as an amplitude (metres).
      s.z[k] += h / tau * (spec.alpha * (beta * (g - s.y[k]) - s.z[k]) + spec.alpha * beta * fk);
      s.y[k] += h / tau * s.z[k];
    }
    s.phase = std::fmod(s.phase + h / tau, 2 * M_PI);
  }
  return s.y;
}

}  // namespace pliant::soft
