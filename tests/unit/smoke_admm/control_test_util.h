// Helpers shared by the keyframe-control unit tests (test_smoke_admm and the NSO
// tests in test_smoke).
#pragma once
#include <random>
#include <vector>

#include "control/control_forward_model.h"

namespace pliant::smoke::test {

// T frames of Gaussian face velocities (standard deviation `scale`), solid faces zeroed.
inline std::vector<control_detail::Vec> random_velocity_series(control_detail::ForwardOps& ops, int T, double scale,
                                                               unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0, scale);
  std::vector<control_detail::Vec> u(T, control_detail::Vec(ops.faces()));
  for (auto& v : u) {
    for (double& x : v) x = N(rng);
    ops.mask(v);
  }
  return u;
}

}  // namespace pliant::smoke::test
