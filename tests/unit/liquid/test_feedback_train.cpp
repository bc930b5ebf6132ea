// Feedback networks: training lowers the loss; the predictor file round-trips.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "pliant/liquid/feedback.h"

namespace pliant::liquid {
namespace {

// Synthetic samples: outflow grows with tilt and volume, exit speed with outflow.
std::vector<FeedbackSample> tiny_dataset(int n) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<FeedbackSample> out;
  for (int i = 0; i < n; ++i) {
    FeedbackSample s;
    for (double& v : s.x) v = U(rng);
    s.outflow_rate = std::max(0.0, s.x[0] * s.x[4] - 0.2);
    s.leaving = s.outflow_rate > 0 ? 10 : 0;
    s.exit = {0.3 * s.x[0], -0.2, 0.5 * s.outflow_rate, -0.4 * s.x[1]};
    out.push_back(s);
  }
  return out;
}

TEST(FeedbackTrain, TrainingLowersTheLoss) {
  FeedbackTraining o;
  o.epochs = 60;
  o.hidden = 8;
  const FeedbackPredictor p = train_feedback(tiny_dataset(80), &o);
  EXPECT_LT(o.flow_loss, 0.3 * o.flow_loss_initial);
  EXPECT_LT(o.exit_loss, 0.3 * o.exit_loss_initial);
  EXPECT_EQ(p.samples, 80);
}

TEST(FeedbackTrain, PredictorFileRoundTrip) {
  FeedbackTraining o;
  o.epochs = 2;
  o.hidden = 4;
  const FeedbackPredictor p = train_feedback(tiny_dataset(20), &o);
  const auto file = std::filesystem::temp_directory_path() / "pliant_feedback_net_test.json";
  p.save(file);
  const FeedbackPredictor q = FeedbackPredictor::load(file);
  const auto x = tiny_dataset(1)[0].x;
  EXPECT_DOUBLE_EQ(p.predict_flow(p.input(x)), q.predict_flow(q.input(x)));
  EXPECT_EQ(p.predict_exit(p.input(x)), q.predict_exit(q.input(x)));
  std::ofstream(file) << "{\"interval_s\": 0.1}";
  EXPECT_THROW(FeedbackPredictor::load(file), std::runtime_error);
  std::filesystem::remove(file);
  EXPECT_THROW(FeedbackPredictor::load(file), std::runtime_error);
}

}  // namespace
}  // namespace pliant::liquid
