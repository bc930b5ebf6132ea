#include "pliant/core/progress.h"

#include <gtest/gtest.h>

#include <cmath>
#include <thread>
#include <vector>

#include "pliant/core/error.h"

namespace pliant {
namespace {

TEST(Progress, ThrottlesButShowsStageFirstAndLastReports) {
  std::vector<ProgressReport> seen;
  Progress p([&](const ProgressReport& r) { seen.push_back(r); });
  p.min_interval_s = 1000;
  p.stage("simulate", 10);
  for (int i = 1; i <= 10; ++i) p.report(i, 0.5 * i);
  ASSERT_EQ(seen.size(), 3u);  // the stage, the first report, the last one
  EXPECT_EQ(seen[0].stage, "simulate");
  EXPECT_EQ(seen[0].iter, 0);
  EXPECT_TRUE(std::isnan(seen[0].objective));
  EXPECT_EQ(seen[1].iter, 1);
  EXPECT_DOUBLE_EQ(seen[1].objective, 0.5);
  EXPECT_EQ(seen[2].iter, 10);
  EXPECT_EQ(seen[2].of, 10);
  EXPECT_DOUBLE_EQ(seen[2].eta_s, 0);
  EXPECT_EQ(p.last().iter, 10);
}

TEST(Progress, NoThrottleReportsEverything) {
  int calls = 0;
  Progress p([&](const ProgressReport&) { ++calls; });
  p.min_interval_s = 0;
  p.stage("a");
  for (int i = 1; i <= 5; ++i) p.report(i);
  EXPECT_EQ(calls, 6);
  EXPECT_DOUBLE_EQ(p.last().eta_s, -1);  // unknown total
}

TEST(Progress, EtaIsElapsedPerIterationTimesRemaining) {
  Progress p;
  const auto t0 = std::chrono::steady_clock::now();
  p.stage("solve", 4);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  const auto t1 = std::chrono::steady_clock::now();
  p.report(1);
  const auto t2 = std::chrono::steady_clock::now();
  const double lo = std::chrono::duration<double>(t1 - t0).count() * 3;
  const double hi = std::chrono::duration<double>(t2 - t0).count() * 3;
  EXPECT_GE(p.last().eta_s, lo * 0.999);
  EXPECT_LE(p.last().eta_s, hi * 1.001);
  EXPECT_GE(p.last().elapsed_s, 0.03);
}

TEST(Progress, Cancellation) {
  Progress p;
  EXPECT_FALSE(p.cancelled());
  EXPECT_NO_THROW(p.check_cancelled());
  std::thread([&] { p.cancel(); }).join();
  EXPECT_TRUE(p.cancelled());
  EXPECT_THROW(p.check_cancelled(), CancelledError);
}

}  // namespace
}  // namespace pliant
