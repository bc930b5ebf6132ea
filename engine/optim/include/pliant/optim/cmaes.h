// CMA-ES (Hansen, "The CMA Evolution Strategy: A Tutorial", 2016): (mu/mu_w,
// lambda) selection, rank-one + rank-mu covariance update, cumulative step-size
// adaptation. Written here rather than taken from a library because Debian ships
// none and the planners need a small, deterministic (fixed seed) one whose
// population can be evaluated in parallel.
//
// Bounds, when given, are handled by evaluating the clamped point and adding a
// quadratic penalty on the distance to the box (Hansen's "repair + penalty").
#pragma once
#include <Eigen/Dense>
#include <cstdint>
#include <functional>
#include <vector>

namespace pliant::optim {

struct CmaesOptions {
  double sigma0 = 0.3;          // initial step size (coordinates should be scaled alike)
  int population = 0;           // lambda; 0 = 4 + floor(3 ln n)
  int max_iterations = 200;
  int max_evaluations = 0;      // 0 = no limit
  double f_target = -1e300;     // stop when the best value is below
  double tol_sigma = 1e-11;     // stop when sigma * max sqrt(C_ii) is below
  uint64_t seed = 1;
  bool parallel = false;        // evaluate each generation with OpenMP
  Eigen::VectorXd lower, upper; // optional box (both empty or both of size n)
};

struct CmaesResult {
  Eigen::VectorXd x;            // best point seen (inside the box)
  double f = 0;                 // its value
  int iterations = 0;
  int evaluations = 0;
  enum Stop { FTarget, TolSigma, MaxIterations, MaxEvaluations } stop = MaxIterations;
};

using Objective = std::function<double(const Eigen::VectorXd&)>;
// Called after every generation with (iteration, best f so far); return false to stop.
using CmaesMonitor = std::function<bool(int, double)>;

CmaesResult cmaes_minimize(const Objective& f, const Eigen::VectorXd& x0, const CmaesOptions& opt,
                           const CmaesMonitor& monitor = {});

}  // namespace pliant::optim
