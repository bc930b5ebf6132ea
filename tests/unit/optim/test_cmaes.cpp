#include "pliant/optim/cmaes.h"

#include <gtest/gtest.h>

namespace pliant::optim {
namespace {

double sphere(const Eigen::VectorXd& x) { return x.squaredNorm(); }
double rosenbrock(const Eigen::VectorXd& x) {
  double s = 0;
  for (int i = 0; i + 1 < x.size(); ++i)
    s += 100 * std::pow(x[i + 1] - x[i] * x[i], 2) + std::pow(1 - x[i], 2);
  return s;
}

TEST(Cmaes, SphereReachesTheOrigin) {
  CmaesOptions o;
  o.sigma0 = 1;
  o.max_iterations = 1000;
  o.f_target = 1e-12;
  const CmaesResult r = cmaes_minimize(sphere, Eigen::VectorXd::Constant(10, 3.0), o);
  EXPECT_EQ(r.stop, CmaesResult::FTarget);
  EXPECT_LT(r.x.norm(), 1e-5);
}

TEST(Cmaes, RosenbrockReachesOnes) {
  CmaesOptions o;
  o.sigma0 = 0.5;
  o.max_iterations = 5000;
  o.f_target = 1e-14;
  const CmaesResult r = cmaes_minimize(rosenbrock, Eigen::VectorXd::Zero(6), o);
  EXPECT_LT(r.f, 1e-10);
  EXPECT_LT((r.x - Eigen::VectorXd::Ones(6)).norm(), 1e-4) << r.x.transpose();
}

TEST(Cmaes, BoxConstrainedMinimumOnTheBound) {
  CmaesOptions o;
  o.sigma0 = 0.5;
  o.lower = Eigen::VectorXd::Constant(3, 1.0);
  o.upper = Eigen::VectorXd::Constant(3, 2.0);
  o.max_iterations = 300;
  const CmaesResult r = cmaes_minimize(sphere, Eigen::VectorXd::Constant(3, 1.5), o);
  EXPECT_NEAR(r.f, 3.0, 1e-6);
  EXPECT_TRUE((r.x.array() >= 1.0).all());
}

TEST(Cmaes, ParallelEvaluationGivesTheSameRun) {
  CmaesOptions o;
  o.max_iterations = 50;
  const CmaesResult a = cmaes_minimize(rosenbrock, Eigen::VectorXd::Zero(4), o);
  o.parallel = true;
  const CmaesResult b = cmaes_minimize(rosenbrock, Eigen::VectorXd::Zero(4), o);
  EXPECT_EQ(a.f, b.f);
  EXPECT_EQ(a.evaluations, b.evaluations);
}

}  // namespace
}  // namespace pliant::optim
