// Environment API and CEM model-predictive control (sampling-based MPC).
#include <algorithm>
#include <chrono>
#include <numeric>
#include <random>

#include "pliant/articulated/mpc.h"

namespace pliant::articulated {

Environment::Environment(const Model& m, const SimOptions& o, const State& initial, int substeps,
                         double ctrl_cost)
    : m_(&m), o_(o), init_(initial), s_(initial), substeps_(substeps), ctrl_cost_(ctrl_cost) {}

void Environment::reset() { reset(init_); }
void Environment::reset(const State& s) {
  s_ = s;
  last_reward_ = 0;
}

bool Environment::step(const VecX& action) {
  const double x0 = forward_position();
  s_.ctrl = action;
  for (int i = 0; i < substeps_; ++i)
    if (!sim_step(*m_, o_, s_, ws_)) return false;
  last_reward_ = (forward_position() - x0) / (substeps_ * o_.dt) - ctrl_cost_ * action.squaredNorm();
  return true;
}

VecX Environment::observation() const {
  VecX obs(m_->nq - 1 + m_->nv);
  obs << s_.qpos.tail(m_->nq - 1), s_.qvel;
  return obs;
}

double Environment::reward() const { return last_reward_; }

double Environment::forward_position() const {
  Kinematics k;
  kinematics(*m_, s_.qpos, &k);
  return k.xcom[1].x();
}

MpcResult run_cem_mpc(const Model& m, const SimOptions& o, const State& initial, const MpcOptions& c,
                      const std::function<void(int, const State&)>& on_step) {
  const auto t0 = std::chrono::steady_clock::now();
  const int na = static_cast<int>(m.actuators.size());
  const int h = c.horizon;
  std::mt19937 rng(c.seed);
  std::normal_distribution<double> normal(0, 1);
  VecX lo(na), hi(na);
  for (int a = 0; a < na; ++a) {
    lo[a] = m.actuators[a].ctrl_min;
    hi[a] = m.actuators[a].ctrl_max;
  }
  Eigen::MatrixXd mean = Eigen::MatrixXd::Zero(na, h);
  MpcResult res;
  res.trajectory.push_back(initial);
  State s = initial;
  Environment env(m, o, initial, c.substeps, c.ctrl_cost);
  const double x_start = env.forward_position();
  Kinematics k0;
  kinematics(m, initial.qpos, &k0, true);
  const double z0 = k0.xcom[1].z();
  const Vec3 up0 = k0.xmat[1].col(2);
  const int control_steps = static_cast<int>(std::llround(c.duration_s / (o.dt * c.substeps)));
  int sim_index = 0;
  std::vector<Eigen::MatrixXd> plans(c.samples);
  std::vector<double> score(c.samples);
  for (int cs = 0; cs < control_steps; ++cs) {
    Eigen::MatrixXd sd = (c.noise * (hi - lo) * 0.5).replicate(1, h);
    for (int it = 0; it < c.iterations; ++it) {
      for (int k = 0; k < c.samples; ++k) {
        plans[k] = mean;
        if (k > 0 || it > 0)  // sample 0 keeps the mean (warm start)
          for (int j = 0; j < h; ++j)
            for (int a = 0; a < na; ++a) plans[k](a, j) += sd(a, j) * normal(rng);
        for (int j = 0; j < h; ++j) plans[k].col(j) = plans[k].col(j).cwiseMax(lo).cwiseMin(hi);
      }
      // Parallel rollouts of the candidate plans from the current state.
#pragma omp parallel for schedule(dynamic, 1)
      for (int k = 0; k < c.samples; ++k) {
        Environment e(m, o, s, c.substeps, c.ctrl_cost);
        double total = 0;
        Kinematics kk;
        // Stay upright: penalise a torso (body 1) lower than 80% of its start height
        // and tilted away from its start orientation, at every control step of the
        // horizon (averaged) so that a dive that pays off only later is seen early.
        auto posture = [&]() {
          kinematics(m, e.state().qpos, &kk, true);
          const double tilt = 1 - kk.xmat[1].col(2).dot(up0);
          return c.height_weight * std::max(0.0, 0.8 * z0 - kk.xcom[1].z()) + c.upright_weight * tilt;
        };
        for (int j = 0; j < h; ++j) {
          if (!e.step(plans[k].col(j))) {
            total = -1e9;
            break;
          }
          total += e.reward() - posture() / h;
        }
        score[k] = total - posture();
      }
      std::vector<int> order(c.samples);
      std::iota(order.begin(), order.end(), 0);
      std::partial_sort(order.begin(), order.begin() + c.elites, order.end(),
                        [&](int a, int b) { return score[a] > score[b]; });
      Eigen::MatrixXd nm = Eigen::MatrixXd::Zero(na, h), var = Eigen::MatrixXd::Zero(na, h);
      for (int e = 0; e < c.elites; ++e) nm += plans[order[e]];
      nm /= c.elites;
      for (int e = 0; e < c.elites; ++e) var += (plans[order[e]] - nm).cwiseAbs2();
      sd = (var / c.elites).cwiseSqrt().cwiseMax(0.05 * (hi - lo).maxCoeff());
      mean = nm;
    }
    // Execute the first action.
    s.ctrl = mean.col(0);
    SimWorkspace ws;
    for (int i = 0; i < c.substeps; ++i) {
      if (!sim_step(m, o, s, ws)) {
        res.trajectory.push_back(s);
        on_step(++sim_index, s);
        break;
      }
      res.trajectory.push_back(s);
      on_step(++sim_index, s);
    }
    // Shift the plan.
    Eigen::MatrixXd shifted(na, h);
    shifted.leftCols(h - 1) = mean.rightCols(h - 1);
    shifted.col(h - 1) = mean.col(h - 1);
    mean = shifted;
  }
  env.reset(s);
  res.distance = env.forward_position() - x_start;
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace pliant::articulated
