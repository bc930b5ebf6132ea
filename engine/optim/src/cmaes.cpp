// CMA-ES following Hansen's tutorial (2016), equations numbered as there.
#include "pliant/optim/cmaes.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>

namespace pliant::optim {

CmaesResult cmaes_minimize(const Objective& f, const Eigen::VectorXd& x0, const CmaesOptions& opt,
                           const CmaesMonitor& monitor) {
  const int n = int(x0.size());
  if (n == 0) throw std::invalid_argument("cmaes_minimize: empty start point");
  const bool boxed = opt.lower.size() == n && opt.upper.size() == n;
  const int lambda = opt.population > 0 ? opt.population : 4 + int(std::floor(3 * std::log(double(n))));
  const int mu = lambda / 2;
  Eigen::VectorXd w(mu);
  for (int i = 0; i < mu; ++i) w[i] = std::log((lambda + 1) / 2.0) - std::log(i + 1.0);
  w /= w.sum();
  const double mueff = 1.0 / w.squaredNorm();
  // Default strategy parameters (tutorial, Table 1).
  const double cc = (4 + mueff / n) / (n + 4 + 2 * mueff / n);
  const double cs = (mueff + 2) / (n + mueff + 5);
  const double c1 = 2 / ((n + 1.3) * (n + 1.3) + mueff);
  const double cmu = std::min(1 - c1, 2 * (mueff - 2 + 1 / mueff) / ((n + 2) * (n + 2) + mueff));
  const double damps = 1 + 2 * std::max(0.0, std::sqrt((mueff - 1) / (n + 1)) - 1) + cs;
  const double chin = std::sqrt(double(n)) * (1 - 1.0 / (4 * n) + 1.0 / (21.0 * n * n));

  Eigen::VectorXd mean = x0, pc = Eigen::VectorXd::Zero(n), ps = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd C = Eigen::MatrixXd::Identity(n, n), B = C;
  Eigen::VectorXd D = Eigen::VectorXd::Ones(n);
  double sigma = opt.sigma0;
  std::mt19937_64 rng(opt.seed);
  std::normal_distribution<double> normal(0, 1);

  auto clamp = [&](const Eigen::VectorXd& x) {
    return boxed ? Eigen::VectorXd(x.cwiseMax(opt.lower).cwiseMin(opt.upper)) : x;
  };
  CmaesResult res;
  res.x = clamp(x0);
  res.f = f(res.x);
  res.evaluations = 1;
  int eigen_age = 0;

  Eigen::MatrixXd Z(n, lambda), Y(n, lambda), X(n, lambda);
  std::vector<double> fit(lambda);
  std::vector<int> order(lambda);
  for (int it = 1; it <= opt.max_iterations; ++it) {
    for (int k = 0; k < lambda; ++k)
      for (int i = 0; i < n; ++i) Z(i, k) = normal(rng);  // drawn serially: deterministic
    Y = B * D.asDiagonal() * Z;
    X = (sigma * Y).colwise() + mean;
    auto evaluate = [&](int k) {
      const Eigen::VectorXd x = X.col(k);
      const Eigen::VectorXd xc = clamp(x);
      fit[k] = f(xc) + (boxed ? 1e3 * (x - xc).squaredNorm() : 0.0);
    };
    if (opt.parallel) {
#pragma omp parallel for schedule(dynamic, 1)
      for (int k = 0; k < lambda; ++k) evaluate(k);
    } else {
      for (int k = 0; k < lambda; ++k) evaluate(k);
    }
    res.evaluations += lambda;
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return fit[a] < fit[b]; });
    const Eigen::VectorXd best = clamp(X.col(order[0]));
    if (fit[order[0]] < res.f) {
      const double fb = f(best);  // the unpenalised value of the repaired point
      ++res.evaluations;
      if (fb < res.f) res.f = fb, res.x = best;
    }
    // Recombination (Eq. 41) and evolution paths (Eqs. 43-45).
    Eigen::VectorXd yw = Eigen::VectorXd::Zero(n), zw = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < mu; ++i) yw += w[i] * Y.col(order[i]), zw += w[i] * Z.col(order[i]);
    mean += sigma * yw;
    ps = (1 - cs) * ps + std::sqrt(cs * (2 - cs) * mueff) * (B * zw);
    const bool hsig = ps.norm() / std::sqrt(1 - std::pow(1 - cs, 2.0 * it)) / chin < 1.4 + 2.0 / (n + 1);
    pc = (1 - cc) * pc + (hsig ? std::sqrt(cc * (2 - cc) * mueff) : 0.0) * yw;
    // Covariance (Eq. 47) and step size (Eq. 44).
    Eigen::MatrixXd rank_mu = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < mu; ++i) rank_mu += w[i] * Y.col(order[i]) * Y.col(order[i]).transpose();
    const double dh = hsig ? 0.0 : cc * (2 - cc);
    C = (1 - c1 - cmu) * C + c1 * (pc * pc.transpose() + dh * C) + cmu * rank_mu;
    sigma *= std::exp((cs / damps) * (ps.norm() / chin - 1));
    if (++eigen_age > std::max(1, int(lambda / ((c1 + cmu) * n * 10)))) {
      eigen_age = 0;
      C = 0.5 * (C + C.transpose()).eval();
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(C);
      B = es.eigenvectors();
      D = es.eigenvalues().cwiseMax(1e-300).cwiseSqrt();
    }
    res.iterations = it;
    if (monitor && !monitor(it, res.f)) break;
    if (res.f <= opt.f_target) { res.stop = CmaesResult::FTarget; break; }
    if (sigma * std::sqrt(C.diagonal().maxCoeff()) < opt.tol_sigma) { res.stop = CmaesResult::TolSigma; break; }
    if (opt.max_evaluations > 0 && res.evaluations >= opt.max_evaluations) {
      res.stop = CmaesResult::MaxEvaluations;
      break;
    }
  }
  return res;
}

}  // namespace pliant::optim
