// Feedback planner, offline part 2: gather the dataset sweep's samples, train
// the two networks (flow: all samples; exit: samples where liquid left), and
// the predictor file (networks + input normalisation) the MPC loads.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "pliant/core/take.h"
#include "pliant/liquid/feedback.h"

#ifndef PLIANT_LIQUID_DEFAULT_NET
#define PLIANT_LIQUID_DEFAULT_NET "assets/sweeps/liquid_dataset_net.json"
#endif

namespace pliant::liquid {
namespace {

// Exit statistics of a handful of particles are noise.
constexpr int kMinLeavingForExit = 3;

Eigen::VectorXd to_vector(const std::array<double, kFeedbackFeatures>& x) {
  Eigen::VectorXd v(kFeedbackFeatures);
  for (int i = 0; i < kFeedbackFeatures; ++i) v[i] = x[i];
  return v;
}

double mean_loss(const optim::Mlp& net, const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y) {
  if (X.cols() == 0) return 0;
  return 0.5 * (net.forward_batch(X) - Y).squaredNorm() / double(X.cols());
}

}  // namespace

Eigen::VectorXd FeedbackPredictor::input(const std::array<double, kFeedbackFeatures>& x) const {
  return (to_vector(x) - x_mean).cwiseQuotient(x_scale);
}

double FeedbackPredictor::predict_flow(const Eigen::VectorXd& in) const {
  return std::max(0.0, flow.forward(in)[0] * flow_scale);
}

std::array<double, kFeedbackExitOutputs> FeedbackPredictor::predict_exit(const Eigen::VectorXd& in) const {
  const Eigen::VectorXd y = exit.forward(in);
  std::array<double, kFeedbackExitOutputs> out{};
  for (int i = 0; i < kFeedbackExitOutputs; ++i) out[i] = y[i];
  return out;
}

void FeedbackPredictor::save(const std::filesystem::path& file) const {
  nlohmann::json j = {{"pliant_liquid_feedback", 1},
                      {"interval_s", interval_s},
                      {"samples", samples},
                      {"flow_scale", flow_scale},
                      {"x_mean", std::vector<double>(x_mean.data(), x_mean.data() + x_mean.size())},
                      {"x_scale", std::vector<double>(x_scale.data(), x_scale.data() + x_scale.size())},
                      {"flow", flow.to_json()},
                      {"exit", exit.to_json()}};
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file.string() + ": cannot write");
  out << j.dump() << "\n";
}

FeedbackPredictor FeedbackPredictor::load(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the feedback network");
  try {
    nlohmann::json j;
    in >> j;
    FeedbackPredictor p;
    p.interval_s = j.at("interval_s").get<double>();
    p.samples = j.value("samples", 0);
    p.flow_scale = j.at("flow_scale").get<double>();
    const auto mean = j.at("x_mean").get<std::vector<double>>(), scale = j.at("x_scale").get<std::vector<double>>();
    if (mean.size() != kFeedbackFeatures || scale.size() != kFeedbackFeatures)
      throw std::runtime_error("x_mean/x_scale need " + std::to_string(kFeedbackFeatures) + " values");
    p.x_mean = Eigen::Map<const Eigen::VectorXd>(mean.data(), kFeedbackFeatures);
    p.x_scale = Eigen::Map<const Eigen::VectorXd>(scale.data(), kFeedbackFeatures);
    p.flow = optim::Mlp::from_json(j.at("flow"));
    p.exit = optim::Mlp::from_json(j.at("exit"));
    if (p.flow.sizes().front() != kFeedbackFeatures || p.flow.sizes().back() != 1 ||
        p.exit.sizes().front() != kFeedbackFeatures || p.exit.sizes().back() != kFeedbackExitOutputs)
      throw std::runtime_error("network sizes do not match the feature layout");
    if (!(p.interval_s > 0)) throw std::runtime_error("interval_s must be positive");
    return p;
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": not a feedback network: " + e.what());
  }
}

FeedbackPredictor train_feedback(const std::vector<FeedbackSample>& samples, FeedbackTraining* o) {
  if (samples.empty()) throw std::runtime_error("train_feedback: no samples");
  const int n = int(samples.size());
  FeedbackPredictor p;
  p.samples = n;
  Eigen::MatrixXd X(kFeedbackFeatures, n);
  for (int i = 0; i < n; ++i) X.col(i) = to_vector(samples[i].x);
  p.x_mean = X.rowwise().mean();
  p.x_scale = ((X.colwise() - p.x_mean).array().square().rowwise().mean().sqrt() + 1e-3).matrix();
  const Eigen::MatrixXd Xn = (X.colwise() - p.x_mean).array().colwise() / p.x_scale.array();
  Eigen::MatrixXd Yf(1, n);
  double sq = 0;
  for (int i = 0; i < n; ++i) sq += samples[i].outflow_rate * samples[i].outflow_rate;
  p.flow_scale = std::sqrt(sq / n) + 1e-6;
  for (int i = 0; i < n; ++i) Yf(0, i) = samples[i].outflow_rate / p.flow_scale;
  std::vector<int> with_exit;
  for (int i = 0; i < n; ++i)
    if (samples[i].leaving >= kMinLeavingForExit) with_exit.push_back(i);
  Eigen::MatrixXd Xe(kFeedbackFeatures, Eigen::Index(with_exit.size())), Ye(kFeedbackExitOutputs, Xe.cols());
  for (size_t k = 0; k < with_exit.size(); ++k) {
    Xe.col(Eigen::Index(k)) = Xn.col(with_exit[k]);
    for (int i = 0; i < kFeedbackExitOutputs; ++i) Ye(i, Eigen::Index(k)) = samples[with_exit[k]].exit[i];
  }
  const int h = o->hidden;
  p.flow = optim::Mlp({kFeedbackFeatures, h, h, h, 1}, o->seed);
  p.exit = optim::Mlp({kFeedbackFeatures, h, h, h, kFeedbackExitOutputs}, o->seed + 1);
  o->flow_loss_initial = mean_loss(p.flow, Xn, Yf);
  o->exit_loss_initial = mean_loss(p.exit, Xe, Ye);
  o->flow_loss = p.flow.train(Xn, Yf, o->epochs, o->learning_rate, o->batch, o->seed);
  o->exit_loss = Xe.cols() > 0 ? p.exit.train(Xe, Ye, o->epochs, o->learning_rate, o->batch, o->seed + 1) : 0.0;
  o->flow_loss = mean_loss(p.flow, Xn, Yf);
  o->exit_loss = mean_loss(p.exit, Xe, Ye);
  return p;
}

std::vector<FeedbackSample> gather_samples(const std::filesystem::path& dir, int* takes) {
  std::vector<std::filesystem::path> dirs;
  if (std::filesystem::exists(dir / "take.json")) {
    dirs.push_back(dir);
  } else if (std::filesystem::is_directory(dir)) {
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.is_directory() && std::filesystem::exists(e.path() / "take.json")) dirs.push_back(e.path());
  }
  std::sort(dirs.begin(), dirs.end());  // deterministic order -> deterministic training
  std::vector<FeedbackSample> out;
  int used = 0;
  for (const auto& d : dirs) {
    const TakeReader reader(d);
    const Manifest& man = reader.manifest();
    if (man.status != "done" || !man.metrics.contains("samples")) continue;
    const auto s = SampleRecorder::from_json(man.metrics["samples"]);
    out.insert(out.end(), s.begin(), s.end());
    ++used;
  }
  if (takes) *takes = used;
  return out;
}

std::filesystem::path default_feedback_network() { return PLIANT_LIQUID_DEFAULT_NET; }

}  // namespace pliant::liquid
