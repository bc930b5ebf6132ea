// A small multilayer perceptron (Eigen): tanh hidden layers, linear output,
// squared loss, backpropagation, Adam. For the feedback planner's predictor
// (dissertation section 2.6: a 4-layer network from pour features to the key
// parameters of the objective). Written here because it is ~150 lines and the
// planners need it deterministic and dependency-free.
#pragma once
#include <Eigen/Dense>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <vector>

namespace pliant::optim {

class Mlp {
 public:
  Mlp() = default;
  // sizes = {inputs, hidden..., outputs}; weights ~ N(0, 1/fan_in), biases 0.
  Mlp(std::vector<int> sizes, uint64_t seed);

  Eigen::VectorXd forward(const Eigen::VectorXd& x) const;
  // Columns of X at once (one matrix product per layer: the MPC's candidates).
  Eigen::MatrixXd forward_batch(const Eigen::MatrixXd& X) const;
  // Loss 0.5 ||f(x) - y||^2 and its gradient w.r.t. params() (added to *grad).
  double loss_gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& y, Eigen::VectorXd* grad) const;

  // All weights and biases, layer by layer (W row-major, then b).
  Eigen::VectorXd params() const;
  void set_params(const Eigen::VectorXd& p);
  int param_count() const;
  const std::vector<int>& sizes() const { return sizes_; }

  // Adam over mini-batches of the columns of X, Y; returns the final mean loss.
  double train(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, int epochs, double learning_rate,
               int batch, uint64_t seed);

  // JSON file {"sizes": [...], "params": [...]}; load throws std::runtime_error.
  void save(const std::filesystem::path& file) const;
  static Mlp load(const std::filesystem::path& file);
  nlohmann::json to_json() const;
  static Mlp from_json(const nlohmann::json& j);  // throws std::runtime_error

 private:
  std::vector<int> sizes_;
  std::vector<Eigen::MatrixXd> W_;
  std::vector<Eigen::VectorXd> b_;
};

}  // namespace pliant::optim
