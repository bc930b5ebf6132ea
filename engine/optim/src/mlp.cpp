// MLP forward/backward (standard backpropagation) and Adam (Kingma & Ba 2015).
#include "pliant/optim/mlp.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>
#include <stdexcept>

namespace pliant::optim {

Mlp::Mlp(std::vector<int> sizes, uint64_t seed) : sizes_(std::move(sizes)) {
  if (sizes_.size() < 2) throw std::invalid_argument("Mlp: need at least input and output sizes");
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0, 1);
  for (size_t l = 0; l + 1 < sizes_.size(); ++l) {
    Eigen::MatrixXd W(sizes_[l + 1], sizes_[l]);
    const double s = 1 / std::sqrt(double(sizes_[l]));
    for (int i = 0; i < W.rows(); ++i)
      for (int j = 0; j < W.cols(); ++j) W(i, j) = s * N(rng);
    W_.push_back(W);
    b_.push_back(Eigen::VectorXd::Zero(sizes_[l + 1]));
  }
}

Eigen::VectorXd Mlp::forward(const Eigen::VectorXd& x) const {
  Eigen::VectorXd a = x;
  for (size_t l = 0; l < W_.size(); ++l) {
    a = W_[l] * a + b_[l];
    if (l + 1 < W_.size()) a = a.array().tanh().matrix();
  }
  return a;
}

Eigen::MatrixXd Mlp::forward_batch(const Eigen::MatrixXd& X) const {
  Eigen::MatrixXd a = X;
  for (size_t l = 0; l < W_.size(); ++l) {
    a = (W_[l] * a).colwise() + b_[l];
    if (l + 1 < W_.size()) a = a.array().tanh().matrix();
  }
  return a;
}

double Mlp::loss_gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& y, Eigen::VectorXd* grad) const {
  const size_t L = W_.size();
  std::vector<Eigen::VectorXd> act(L + 1);  // act[0] = x, act[l+1] = layer l output
  act[0] = x;
  for (size_t l = 0; l < L; ++l) {
    act[l + 1] = W_[l] * act[l] + b_[l];
    if (l + 1 < L) act[l + 1] = act[l + 1].array().tanh().matrix();
  }
  const Eigen::VectorXd r = act[L] - y;
  if (grad) {
    if (grad->size() != param_count()) *grad = Eigen::VectorXd::Zero(param_count());
    // Offsets of each layer's block in params().
    std::vector<int> off(L + 1, 0);
    for (size_t l = 0; l < L; ++l) off[l + 1] = off[l] + int(W_[l].size() + b_[l].size());
    Eigen::VectorXd delta = r;  // dLoss / d(pre-activation) of the output layer
    for (size_t l = L; l-- > 0;) {
      const Eigen::MatrixXd gW = delta * act[l].transpose();
      for (int i = 0; i < gW.rows(); ++i)
        for (int j = 0; j < gW.cols(); ++j) (*grad)[off[l] + i * gW.cols() + j] += gW(i, j);
      grad->segment(off[l] + int(W_[l].size()), delta.size()) += delta;
      if (l > 0) delta = (W_[l].transpose() * delta).array() * (1 - act[l].array().square());
    }
  }
  return 0.5 * r.squaredNorm();
}

int Mlp::param_count() const {
  int n = 0;
  for (size_t l = 0; l < W_.size(); ++l) n += int(W_[l].size() + b_[l].size());
  return n;
}

Eigen::VectorXd Mlp::params() const {
  Eigen::VectorXd p(param_count());
  int k = 0;
  for (size_t l = 0; l < W_.size(); ++l) {
    for (int i = 0; i < W_[l].rows(); ++i)
      for (int j = 0; j < W_[l].cols(); ++j) p[k++] = W_[l](i, j);
    for (int i = 0; i < b_[l].size(); ++i) p[k++] = b_[l][i];
  }
  return p;
}

void Mlp::set_params(const Eigen::VectorXd& p) {
  if (p.size() != param_count()) throw std::invalid_argument("Mlp::set_params: wrong size");
  int k = 0;
  for (size_t l = 0; l < W_.size(); ++l) {
    for (int i = 0; i < W_[l].rows(); ++i)
      for (int j = 0; j < W_[l].cols(); ++j) W_[l](i, j) = p[k++];
    for (int i = 0; i < b_[l].size(); ++i) b_[l][i] = p[k++];
  }
}

double Mlp::train(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, int epochs, double lr, int batch,
                  uint64_t seed) {
  const int n = int(X.cols());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::mt19937_64 rng(seed);
  Eigen::VectorXd p = params(), m = Eigen::VectorXd::Zero(p.size()), v = m, g;
  const double b1 = 0.9, b2 = 0.999, eps = 1e-8;
  long long t = 0;
  double loss = 0;
  for (int e = 0; e < epochs; ++e) {
    std::shuffle(order.begin(), order.end(), rng);
    loss = 0;
    for (int s = 0; s < n; s += batch) {
      g = Eigen::VectorXd::Zero(p.size());
      const int end = std::min(n, s + batch);
      for (int i = s; i < end; ++i) loss += loss_gradient(X.col(order[i]), Y.col(order[i]), &g);
      g /= double(end - s);
      ++t;
      m = b1 * m + (1 - b1) * g;
      v = b2 * v + (1 - b2) * g.cwiseProduct(g);
      const Eigen::VectorXd mh = m / (1 - std::pow(b1, double(t)));
      const Eigen::VectorXd vh = v / (1 - std::pow(b2, double(t)));
      p -= lr * mh.cwiseQuotient((vh.array().sqrt() + eps).matrix());
      set_params(p);
    }
    loss /= n;
  }
  return loss;
}

nlohmann::json Mlp::to_json() const {
  const Eigen::VectorXd p = params();
  return {{"sizes", sizes_}, {"params", std::vector<double>(p.data(), p.data() + p.size())}};
}

Mlp Mlp::from_json(const nlohmann::json& j) {
  try {
    Mlp m(j.at("sizes").get<std::vector<int>>(), 0);
    const auto p = j.at("params").get<std::vector<double>>();
    if (int(p.size()) != m.param_count())
      throw std::runtime_error("params has " + std::to_string(p.size()) + " values, sizes need " +
                               std::to_string(m.param_count()));
    m.set_params(Eigen::Map<const Eigen::VectorXd>(p.data(), Eigen::Index(p.size())));
    return m;
  } catch (const std::runtime_error&) {
    throw;
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("not an MLP: ") + e.what());
  }
}

void Mlp::save(const std::filesystem::path& file) const {
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file.string() + ": cannot write");
  out << to_json().dump() << "\n";
}

Mlp Mlp::load(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read");
  try {
    nlohmann::json j;
    in >> j;
    return from_json(j);
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": not an MLP file: " + e.what());
  }
}

}  // namespace pliant::optim
