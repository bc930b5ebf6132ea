#include "pliant/optim/mlp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace pliant::optim {
namespace {

TEST(Mlp, BackpropagationMatchesFiniteDifferences) {
  const Mlp net({3, 8, 8, 8, 2}, 7);  // 4 weight layers
  Eigen::VectorXd x(3), y(2);
  x << 0.3, -0.7, 1.1;
  y << 0.2, -0.4;
  Eigen::VectorXd g;
  net.loss_gradient(x, y, &g);
  Mlp probe = net;
  const Eigen::VectorXd p = net.params();
  double worst = 0;
  for (int i = 0; i < p.size(); ++i) {
    const double e = 1e-6;
    Eigen::VectorXd q = p;
    q[i] += e;
    probe.set_params(q);
    const double fp = probe.loss_gradient(x, y, nullptr);
    q[i] -= 2 * e;
    probe.set_params(q);
    const double fm = probe.loss_gradient(x, y, nullptr);
    worst = std::max(worst, std::abs((fp - fm) / (2 * e) - g[i]));
  }
  EXPECT_LT(worst, 1e-7);
}

TEST(Mlp, LearnsASmoothFunction) {
  const int n = 200;
  Eigen::MatrixXd X(1, n), Y(1, n);
  for (int i = 0; i < n; ++i) X(0, i) = -2 + 4.0 * i / (n - 1), Y(0, i) = std::sin(1.5 * X(0, i));
  Mlp net({1, 16, 16, 1}, 3);
  const double loss = net.train(X, Y, 400, 0.01, 20, 5);
  EXPECT_LT(loss, 1e-3);  // 0.5 r^2 averaged: RMS error under about 0.045
}

TEST(Mlp, SaveLoadRoundTrip) {
  const Mlp net({2, 5, 1}, 11);
  const auto file = std::filesystem::temp_directory_path() / "pliant_mlp_test.json";
  net.save(file);
  const Mlp back = Mlp::load(file);
  Eigen::VectorXd x(2);
  x << 0.5, -1;
  EXPECT_EQ(net.forward(x)[0], back.forward(x)[0]);
  std::filesystem::remove(file);
  EXPECT_THROW(Mlp::load(file), std::runtime_error);
}

}  // namespace
}  // namespace pliant::optim
