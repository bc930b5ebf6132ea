// Locomotion objective residuals (see objective.h).
#include "pliant/soft/objective.h"

#include <cmath>
#include <limits>

namespace pliant::soft {

Eigen::VectorXd control_force(const Character& ch, const Eigen::VectorXd& y, double a_max) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(ch.basis.r());
  // Saturated activation (muscles have bounded strength): |y| <= a_max.
  for (int k = 0; k < std::min<int>(int(y.size()), ch.basis.r()); ++k)
    u[k] = ch.basis.omega2[k] * a_max * std::tanh(y[k] / a_max) / ch.mode_scale[k];
  return u;
}

double max_activation_m(const Character& ch, const DmpSpec& spec) {
  const auto& X = ch.rest_local;
  double size = 0;
  for (int j = 0; j < ch.lattice.nodes(); ++j) size = std::max(size, X.segment<3>(3 * j).norm());
  return spec.max_activation_rel * size;
}

SoftState simulate(const Problem& p, const Eigen::VectorXd& theta, int n,
                   const std::function<void(const SoftState&)>& on_frame, int* unconverged) {
  const Character& ch = *p.character;
  SoftState s = initial_state(ch, p.start_offset_m, Eigen::Vector3d::Zero(), p.sim.dt_s);
  DmpState d = dmp_init(p.dmp);
  const double a_max = max_activation_m(ch, p.dmp);
  StepStats st;
  for (int f = 0; f < n; ++f) {
    const Eigen::VectorXd& y = dmp_step(p.dmp, theta, p.sim.dt_s, d);
    reduced_step(ch, p.env, p.sim, control_force(ch, y, a_max), s, &st);
    if (!st.converged && unconverged) ++*unconverged;
    if (on_frame) on_frame(s);
  }
  return s;
}

double heading_yaw(const SoftState& s, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d h = s.R * axis;
  return std::atan2(h[2], h[0]);
}

Eigen::VectorXd residuals(const Problem& p, const Eigen::VectorXd& theta) {
  const Character& ch = *p.character;
  const Objectives& o = p.obj;
  const double dt = p.sim.dt_s, T = p.frames * dt;
  const SoftState s0 = initial_state(ch, p.start_offset_m, Eigen::Vector3d::Zero(), dt);
  const Eigen::Vector3d com0 = centre_of_mass(ch, s0);
  Eigen::Vector3d heading_sum = Eigen::Vector3d::Zero();
  // Smooth max of the height gain: log-sum-exp with a 2 mm temperature.
  const double kappa = 500;
  double lse_max = -1e300, lse_sum = 0;
  std::vector<double> shuffle;
  std::vector<Eigen::VectorXd> key_res;
  Eigen::VectorXd x;
  int frame = 0, unconverged = 0;
  double yaw_prev = heading_yaw(s0, o.turn_axis), yaw_total = 0;
  SoftState last = simulate(p, theta, p.frames, [&](const SoftState& s) {
    ++frame;
    const Eigen::Vector3d com = centre_of_mass(ch, s);
    if (o.w_turn > 0) {
      const double yaw = heading_yaw(s, o.turn_axis);
      yaw_total += std::remainder(yaw - yaw_prev, 2 * M_PI);  // unwrapped
      yaw_prev = yaw;
    }
    if (o.w_heading > 0) heading_sum += s.R * o.heading_axis - o.heading_direction.normalized();
    if (o.w_jump > 0) {
      const double v = kappa * (com[1] - com0[1]);
      if (v > lse_max) {
        lse_sum = lse_sum * std::exp(lse_max - v) + 1;
        lse_max = v;
      } else {
        lse_sum += std::exp(v - lse_max);
      }
    }
    if (o.w_shuffle > 0) {
      SoftState prev = s;
      prev.q = s.q_prev, prev.R = s.R_prev, prev.c = s.c_prev;
      Eigen::VectorXd xp;
      node_positions(ch, s, x);
      node_positions(ch, prev, xp);
      double acc = 0;
      for (int j = 0; j < ch.lattice.nodes(); ++j) {
        Eigen::Vector3d nrm;
        if (contact_normal_force(p.env, 1.0, x.segment<3>(3 * j), &nrm) <= 0) continue;
        const Eigen::Vector3d v = (x.segment<3>(3 * j) - xp.segment<3>(3 * j)) / dt;
        acc += ch.lattice.node_mass_kg[j] * (v - v.dot(nrm) * nrm).squaredNorm();
      }
      const double e = 1e-3;
      shuffle.push_back(std::sqrt(acc / ch.mass_kg + e * e) - e);
    }
    if (o.w_keyframes > 0)
      for (const auto& k : o.keyframes) {
        if (k.frame != frame) continue;
        node_positions(ch, s, x);
        Eigen::VectorXd r(3 * k.vertices.size());
        for (size_t i = 0; i < k.vertices.size(); ++i) {
          const int v = k.vertices[i];
          Eigen::Vector3d pos = Eigen::Vector3d::Zero();
          const auto& cell = ch.lattice.cells[ch.lattice.vertex_cell[v]];
          for (int a = 0; a < 8; ++a) pos += ch.lattice.vertex_weight[v][a] * x.segment<3>(3 * cell[a]);
          r.segment<3>(3 * i) = pos - (ch.surface.vertices[v] + p.start_offset_m + k.offset_m);
        }
        key_res.push_back(r);
      }
  }, &unconverged);
  std::vector<double> out;
  const Eigen::Vector3d com = centre_of_mass(ch, last);
  auto push3 = [&](double w, const Eigen::Vector3d& v) {
    for (int a = 0; a < 3; ++a) out.push_back(std::sqrt(w) * v[a]);
  };
  if (o.w_velocity > 0) push3(o.w_velocity, (com - com0) / T - o.velocity_m_per_s);
  if (o.w_position > 0) push3(o.w_position, com - o.position_m);
  if (o.w_heading > 0) push3(o.w_heading, heading_sum / std::max(1, p.frames));
  // log-sum-exp minus log(frames): never above the true maximum, so meeting the
  // target in the objective means meeting it in the rollout.
  if (o.w_jump > 0)
    out.push_back(std::sqrt(o.w_jump) *
                  ((lse_max + std::log(lse_sum) - std::log(double(std::max(1, frame)))) / kappa - o.jump_height_m));
  if (o.w_distance > 0)
    out.push_back(std::sqrt(o.w_distance) * ((com - com0).dot(o.distance_direction.normalized()) - o.distance_m));
  if (o.w_turn > 0) {
    out.push_back(std::sqrt(o.w_turn) * (yaw_total / T - o.turn_rate_rad_per_s));
    // Signed progress along the initial heading (smooth, unlike the horizontal speed).
    Eigen::Vector3d h0 = s0.R * o.turn_axis;
    h0[1] = 0;
    if (h0.norm() > 1e-12) h0.normalize();
    out.push_back(std::sqrt(o.w_turn) * ((com - com0).dot(h0) / T - o.turn_speed_m_per_s));
  }
  for (double v : shuffle) out.push_back(std::sqrt(o.w_shuffle * dt) * v);
  for (const auto& r : key_res)
    for (int i = 0; i < r.size(); ++i) out.push_back(std::sqrt(o.w_keyframes) * r[i]);
  for (int i = 0; i < theta.size(); ++i) out.push_back(std::sqrt(o.w_effort) * theta[i]);
  Eigen::VectorXd res = Eigen::Map<Eigen::VectorXd>(out.data(), Eigen::Index(out.size()));
  // A rollout whose implicit steps did not converge is not physics: reject it.
  if (unconverged > 0) res.setConstant(std::numeric_limits<double>::quiet_NaN());
  return res;
}

Eigen::VectorXd initial_theta(const Problem& p) {
  // Small fixed pseudo-random weights: theta = 0 is a symmetric rest state where the
  // objective has a kink (static friction), so optimizers start next to it.
  Eigen::VectorXd th(p.dmp.parameters());
  const double a = 0.02 * max_activation_m(*p.character, p.dmp);
  unsigned v = 12345;
  for (int i = 0; i < th.size(); ++i) {
    v = v * 1103515245u + 12345u;
    th[i] = a * (double((v >> 8) & 0xffff) / 65535.0 - 0.5);
  }
  return th;
}

double max_height_gain(const Problem& p, const Eigen::VectorXd& theta, int n) {
  const Character& ch = *p.character;
  const double y0 = centre_of_mass(ch, initial_state(ch, p.start_offset_m, Eigen::Vector3d::Zero(), p.sim.dt_s))[1];
  double best = 0;
  simulate(p, theta, n, [&](const SoftState& s) { best = std::max(best, centre_of_mass(ch, s)[1] - y0); });
  return best;
}

}  // namespace pliant::soft
