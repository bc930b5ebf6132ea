// Periodic DMP: constant weights give a constant forcing; the output becomes
// periodic with the DMP period after the transient.
#include <gtest/gtest.h>

#include "pliant/soft/dmp.h"

using namespace pliant::soft;

TEST(Dmp, ConstantWeightsGiveConstantForcing) {
  DmpSpec spec;
  spec.modes = 2;
  spec.kernels = 5;
  Eigen::VectorXd th = Eigen::VectorXd::Zero(spec.parameters());
  th.head(5).setConstant(0.3);
  for (double ph : {0.0, 1.0, 4.0}) {
    const Eigen::VectorXd f = dmp_forcing(spec, th, ph);
    EXPECT_NEAR(f[0], 0.3, 1e-12);
    EXPECT_NEAR(f[1], 0.0, 1e-12);
  }
  // Goal plus constant forcing: y converges to g + w.
  th[5] = 0.1;
  DmpState s = dmp_init(spec);
  for (int i = 0; i < 2000; ++i) dmp_step(spec, th, 0.001, s);
  EXPECT_NEAR(s.y[0], 0.4, 1e-6);
}

TEST(Dmp, OutputIsPeriodic) {
  DmpSpec spec;
  spec.modes = 1;
  spec.kernels = 6;
  spec.period_s = 0.5;
  Eigen::VectorXd th(7);
  th << 0.2, -0.1, 0.05, 0.3, -0.2, 0.0, 0.05;
  const double dt = 0.5 / 500;
  DmpState s = dmp_init(spec);
  for (int i = 0; i < 5000; ++i) dmp_step(spec, th, dt, s);  // 10 periods of transient
  std::vector<double> a, b;
  for (int i = 0; i < 500; ++i) a.push_back(dmp_step(spec, th, dt, s)[0]);
  for (int i = 0; i < 500; ++i) b.push_back(dmp_step(spec, th, dt, s)[0]);
  double diff = 0, amp = 0;
  for (int i = 0; i < 500; ++i) diff = std::max(diff, std::abs(a[i] - b[i])), amp = std::max(amp, std::abs(a[i]));
  EXPECT_GT(amp, 0.01);
  EXPECT_LT(diff, 1e-3 * amp);
}

TEST(Dmp, LargeFrameStepsStayBounded) {
  // A 30 fps frame is longer than the DMP time constant (alpha dt / tau ~ 8): the
  // substeps keep y bounded by the forcing amplitude.
  DmpSpec spec;
  spec.modes = 1;
  spec.kernels = 4;
  spec.period_s = 0.5;
  Eigen::VectorXd th(5);
  th << 0.1, -0.1, 0.1, -0.1, 0.0;
  DmpState s = dmp_init(spec);
  double mx = 0;
  for (int i = 0; i < 300; ++i) mx = std::max(mx, std::abs(dmp_step(spec, th, 1.0 / 30, s)[0]));
  EXPECT_LT(mx, 0.2);
  EXPECT_GT(mx, 0.01);
}
