// Locomotion objective residuals (see objective.h).
#include "pliant/soft/objective.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace pliant::soft {

void control_force(const Character& ch, const Eigen::VectorXd& y, double a_max, Eigen::VectorXd& u) {
  u.setZero(ch.basis.r());
  // Saturated activation (muscles have bounded strength): |y| <= a_max.
  for (int k = 0; k < std::min<int>(int(y.size()), ch.basis.r()); ++k)
    u[k] = ch.basis.omega2[k] * a_max * std::tanh(y[k] / a_max) / ch.mode_scale[k];
}

Eigen::VectorXd control_force(const Character& ch, const Eigen::VectorXd& y, double a_max) {
  Eigen::VectorXd u;
  control_force(ch, y, a_max, u);
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

int steady_window_frames(const Objectives& o, double period_s, double dt_s) {
  return std::max(1, int(std::lround(o.steady_periods * period_s / dt_s)));
}

double heading_yaw(const SoftState& s, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d h = s.R * axis;
  return std::atan2(h[2], h[0]);
}

double tilt_from_up_deg(const SoftState& s, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d a = s.R * axis.normalized();
  return std::atan2(std::hypot(a[0], a[2]), a[1]) * 180.0 / M_PI;
}

namespace {

// The objective's per-frame sums over a trajectory (one pass, buffers reused), then
// the residual vector written in place: residuals() feeds it from the rollout and
// trajectory_residuals() from given frames, so both give the same numbers.
class ResidualAccumulator {
 public:
  ResidualAccumulator(const Problem& p, Eigen::Index theta_size)
      : p_(p), ch_(*p.character), o_(p.obj), dt_(p.sim.dt_s),
        s0_(initial_state(ch_, p.start_offset_m, Eigen::Vector3d::Zero(), dt_)),
        com0_(centre_of_mass(ch_, s0_)), yaw_prev_(heading_yaw(s0_, o_.turn_axis)) {
    Eigen::Index n = 0;
    if (o_.w_velocity > 0) n += 3;
    if (o_.w_position > 0) n += 3;
    if (o_.w_heading > 0) n += 3;
    if (o_.w_jump > 0) n += 1;
    if (o_.w_distance > 0) n += 1;
    if (o_.w_turn > 0) n += 2;
    if (o_.w_steady > 0) n += 2;
    if (o_.w_steady_periodic > 0) n += 3;
    if (o_.w_steady > 0 || o_.w_steady_periodic > 0) {
      // Window ends: frames F - P and F - 2P (clamped to the start state, frame 0).
      const int P = steady_window_frames(o_, p.dmp.period_s, dt_);
      steady_frame_[0] = std::max(0, p.frames - P);
      steady_frame_[1] = std::max(0, steady_frame_[0] - P);
      for (int k = 0; k < 2; ++k) steady_com_[k] = com0_, steady_yaw_at_[k] = 0;
      steady_yaw_prev_ = heading_yaw(s0_, o_.steady_axis);
      steady_normal_ = Eigen::Vector3d(o_.steady_direction[2], 0, -o_.steady_direction[0]);
      if (steady_normal_.norm() > 1e-12) steady_normal_.normalize();
    }
    shuffle_at_ = n;
    if (o_.w_shuffle > 0) n += p.frames;
    course_at_ = n;
    if (o_.w_course > 0) n += p.frames;
    upright_at_ = n;
    if (o_.w_upright > 0) n += 3 * Eigen::Index(p.frames);
    // Unit normal of the course in the ground plane (y up): y x d.
    course_normal_ = Eigen::Vector3d(o_.course_direction[2], 0, -o_.course_direction[0]);
    if (course_normal_.norm() > 1e-12) course_normal_.normalize();
    // Keyframe blocks in the order the rollout meets them (by frame, then listed order).
    key_at_.assign(o_.keyframes.size(), -1);
    if (o_.w_keyframes > 0)
      for (int f = 1; f <= p.frames; ++f)
        for (size_t k = 0; k < o_.keyframes.size(); ++k)
          if (o_.keyframes[k].frame == f) {
            key_at_[k] = n;
            n += 3 * Eigen::Index(o_.keyframes[k].vertices.size());
          }
    effort_at_ = n;
    res_.resize(n + theta_size);
  }

  void add(const SoftState& s) {
    ++frame_;
    const Eigen::Vector3d com = centre_of_mass(ch_, s);
    if (o_.w_turn > 0) {
      const double yaw = heading_yaw(s, o_.turn_axis);
      yaw_total_ += std::remainder(yaw - yaw_prev_, 2 * M_PI);  // unwrapped
      yaw_prev_ = yaw;
    }
    if (o_.w_steady > 0 || o_.w_steady_periodic > 0) {
      const double yaw = heading_yaw(s, o_.steady_axis);
      steady_yaw_ += std::remainder(yaw - steady_yaw_prev_, 2 * M_PI);  // unwrapped
      steady_yaw_prev_ = yaw;
      for (int k = 0; k < 2; ++k)
        if (frame_ == steady_frame_[k]) steady_com_[k] = com, steady_yaw_at_[k] = steady_yaw_;
    }
    if (o_.w_heading > 0) heading_sum_ += s.R * o_.heading_axis - o_.heading_direction.normalized();
    if (o_.w_jump > 0) {
      // Smooth max of the height gain: log-sum-exp with a 2 mm temperature.
      const double v = kKappa * (com[1] - com0_[1]);
      if (v > lse_max_) {
        lse_sum_ = lse_sum_ * std::exp(lse_max_ - v) + 1;
        lse_max_ = v;
      } else {
        lse_sum_ += std::exp(v - lse_max_);
      }
    }
    if (o_.w_shuffle > 0 && frame_ <= p_.frames) {
      prev_.q = s.q_prev, prev_.R = s.R_prev, prev_.c = s.c_prev;
      node_positions(ch_, s, x_);
      node_positions(ch_, prev_, xp_);
      double acc = 0;
      for (int j = 0; j < ch_.lattice.nodes(); ++j) {
        Eigen::Vector3d nrm;
        if (contact_normal_force(p_.env, 1.0, x_.segment<3>(3 * j), &nrm) <= 0) continue;
        const Eigen::Vector3d v = (x_.segment<3>(3 * j) - xp_.segment<3>(3 * j)) / dt_;
        acc += ch_.lattice.node_mass_kg[j] * (v - v.dot(nrm) * nrm).squaredNorm();
      }
      const double e = 1e-3;
      res_[shuffle_at_ + frame_ - 1] = std::sqrt(o_.w_shuffle * dt_) * (std::sqrt(acc / ch_.mass_kg + e * e) - e);
    }
    if (o_.w_course > 0 && frame_ <= p_.frames)
      res_[course_at_ + frame_ - 1] =
          std::sqrt(o_.w_course * dt_ / std::max(dt_, p_.frames * dt_)) * (com - com0_).dot(course_normal_);
    if (o_.w_upright > 0 && frame_ <= p_.frames)
      res_.segment<3>(upright_at_ + 3 * Eigen::Index(frame_ - 1)) =
          std::sqrt(o_.w_upright / p_.frames) * (s.R * o_.upright_axis - Eigen::Vector3d::UnitY());
    if (o_.w_keyframes > 0) {
      bool have_x = false;
      for (size_t k = 0; k < o_.keyframes.size(); ++k) {
        const Keyframe& key = o_.keyframes[k];
        if (key.frame != frame_ || key_at_[k] < 0) continue;
        if (!have_x) node_positions(ch_, s, x_), have_x = true;
        for (size_t i = 0; i < key.vertices.size(); ++i) {
          const int v = key.vertices[i];
          Eigen::Vector3d pos = Eigen::Vector3d::Zero();
          const auto& cell = ch_.lattice.cells[ch_.lattice.vertex_cell[v]];
          for (int a = 0; a < 8; ++a) pos += ch_.lattice.vertex_weight[v][a] * x_.segment<3>(3 * cell[a]);
          res_.segment<3>(key_at_[k] + 3 * Eigen::Index(i)) =
              std::sqrt(o_.w_keyframes) * (pos - (ch_.surface.vertices[v] + p_.start_offset_m + key.offset_m));
        }
      }
    }
  }

  // `last` is the final state (s0 when there are no frames).
  Eigen::VectorXd finish(const SoftState& last, const Eigen::VectorXd& theta) {
    const double T = p_.frames * dt_;
    const Eigen::Vector3d com = centre_of_mass(ch_, last);
    Eigen::Index at = 0;
    auto push3 = [&](double w, const Eigen::Vector3d& v) {
      res_.segment<3>(at) = std::sqrt(w) * v;
      at += 3;
    };
    if (o_.w_velocity > 0) push3(o_.w_velocity, (com - com0_) / T - o_.velocity_m_per_s);
    if (o_.w_position > 0) push3(o_.w_position, com - o_.position_m);
    if (o_.w_heading > 0) push3(o_.w_heading, heading_sum_ / std::max(1, p_.frames));
    // log-sum-exp minus log(frames): never above the true maximum, so meeting the
    // target in the objective means meeting it in the rollout.
    if (o_.w_jump > 0)
      res_[at++] = std::sqrt(o_.w_jump) *
                   ((lse_max_ + std::log(lse_sum_) - std::log(double(std::max(1, frame_)))) / kKappa - o_.jump_height_m);
    if (o_.w_distance > 0)
      res_[at++] = std::sqrt(o_.w_distance) * ((com - com0_).dot(o_.distance_direction.normalized()) - o_.distance_m);
    if (o_.w_turn > 0) {
      res_[at++] = std::sqrt(o_.w_turn) * (yaw_total_ / T - o_.turn_rate_rad_per_s);
      // Signed progress along the initial heading (smooth, unlike the horizontal speed).
      Eigen::Vector3d h0 = s0_.R * o_.turn_axis;
      h0[1] = 0;
      if (h0.norm() > 1e-12) h0.normalize();
      res_[at++] = std::sqrt(o_.w_turn) * ((com - com0_).dot(h0) / T - o_.turn_speed_m_per_s);
    }
    if (o_.w_steady > 0 || o_.w_steady_periodic > 0) {
      // Mean rates over the last window [F - P, F] and the one before [F - 2P, F - P].
      const double t1 = (p_.frames - steady_frame_[0]) * dt_, t2 = (steady_frame_[0] - steady_frame_[1]) * dt_;
      const Eigen::Vector3d v1 = t1 > 0 ? Eigen::Vector3d((com - steady_com_[0]) / t1) : Eigen::Vector3d::Zero();
      const Eigen::Vector3d v2 = t2 > 0 ? Eigen::Vector3d((steady_com_[0] - steady_com_[1]) / t2) : v1;
      const double w1 = t1 > 0 ? (steady_yaw_ - steady_yaw_at_[0]) / t1 : 0;
      const double w2 = t2 > 0 ? (steady_yaw_at_[0] - steady_yaw_at_[1]) / t2 : w1;
      if (o_.w_steady > 0) {
        res_[at++] = std::sqrt(o_.w_steady) * w1;
        res_[at++] = std::sqrt(o_.w_steady) * v1.dot(steady_normal_);
      }
      if (o_.w_steady_periodic > 0) {
        const double sw = std::sqrt(o_.w_steady_periodic);
        res_[at++] = sw * (v1[0] - v2[0]);
        res_[at++] = sw * (v1[2] - v2[2]);
        res_[at++] = sw * (w1 - w2);
      }
    }
    res_.segment(effort_at_, theta.size()) = std::sqrt(o_.w_effort) * theta;
    return std::move(res_);
  }

  const SoftState& initial() const { return s0_; }

 private:
  static constexpr double kKappa = 500;
  const Problem& p_;
  const Character& ch_;
  const Objectives& o_;
  const double dt_;
  const SoftState s0_;
  const Eigen::Vector3d com0_;
  Eigen::Index shuffle_at_ = 0, course_at_ = 0, upright_at_ = 0, effort_at_ = 0;
  Eigen::Vector3d course_normal_ = Eigen::Vector3d::Zero();
  std::vector<Eigen::Index> key_at_;
  Eigen::VectorXd res_, x_, xp_;
  SoftState prev_;
  Eigen::Vector3d heading_sum_ = Eigen::Vector3d::Zero();
  double lse_max_ = -1e300, lse_sum_ = 0;
  double yaw_prev_, yaw_total_ = 0;
  // steady: window-end frames, COM and unwrapped yaw there; lateral unit normal.
  int steady_frame_[2] = {0, 0};
  Eigen::Vector3d steady_com_[2], steady_normal_ = Eigen::Vector3d::Zero();
  double steady_yaw_at_[2] = {0, 0}, steady_yaw_prev_ = 0, steady_yaw_ = 0;
  int frame_ = 0;
};

}  // namespace

Eigen::VectorXd trajectory_residuals(const Problem& p, const std::vector<SoftState>& frames,
                                     const Eigen::VectorXd& theta) {
  if (int(frames.size()) != p.frames)
    throw std::invalid_argument("trajectory_residuals: " + std::to_string(frames.size()) + " frames given, the problem has " +
                                std::to_string(p.frames));
  ResidualAccumulator acc(p, theta.size());
  for (const SoftState& s : frames) acc.add(s);
  return acc.finish(frames.empty() ? acc.initial() : frames.back(), theta);
}

Eigen::VectorXd residuals(const Problem& p, const Eigen::VectorXd& theta) {
  ResidualAccumulator acc(p, theta.size());
  int unconverged = 0;
  const SoftState last = simulate(p, theta, p.frames, [&](const SoftState& s) { acc.add(s); }, &unconverged);
  Eigen::VectorXd res = acc.finish(last, theta);
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
