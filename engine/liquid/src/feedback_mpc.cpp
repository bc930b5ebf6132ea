// Feedback planner, online part: receding-horizon MPC over the networks'
// predictions, interleaved with the full simulator (feedback.h).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>

#include "pliant/liquid/feedback.h"

namespace pliant::liquid {
namespace {

struct Rollout {
  double tilt, x, y, fraction;
};

// CPU time of this thread: on a shared machine wall-clock time per decision
// mostly measures the other processes.
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

double gravity_norm(const LiquidModel& m) {
  const auto& g = m.gravity_m_per_s2;
  return std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
}

// Robot-side limits: the source stays above the target's rim where it is over
// the target, above the floor, and inside the domain (squared violation, m^2).
double pose_violation(const LiquidModel& m, const Pose& pose, double t) {
  const ContainerShape& c = m.source.shape;
  const Pose tp = target_pose_at(m, t);
  const double rim = tp.position_m[1] + m.target.shape.height_m + 0.01;
  const double reach = m.target.shape.radius_m + m.target.shape.wall_m + 0.01;
  double v = 0;
  for (double sx : {-1.0, 1.0})
    for (double ly : {-c.wall_m, c.height_m}) {
      const Vec3 q = pose.to_world({sx * (c.radius_m + c.wall_m), ly, 0});
      if (std::abs(q[0] - tp.position_m[0]) < reach && q[1] < rim) v += std::pow(rim - q[1], 2);
      for (int a = 0; a < 2; ++a) {
        const double lo = m.domain_min_m[a] + m.cell_size_m, hi = m.domain_max_m[a] - m.cell_size_m;
        if (q[a] < lo) v += std::pow(lo - q[a], 2);
        if (q[a] > hi) v += std::pow(q[a] - hi, 2);
      }
    }
  return v;
}

}  // namespace

double stream_spill(const MpcSettings& ms, double land, double near, double centre, double inner) {
  auto ramp = [&](double x) {
    return std::clamp((std::abs(x - centre) / inner - ms.spill_inner) / (ms.spill_outer - ms.spill_inner), 0.0, 1.0);
  };
  if (ms.stream_near <= 0 && ms.stream_far <= 0) return ramp(land);
  double sum = ramp(land);
  for (double f : {-ms.stream_near, -0.5 * ms.stream_near, 0.5 * ms.stream_far, ms.stream_far})
    sum += ramp(land + f * (land - near));
  return sum / 5;
}

bool set_mpc_setting(MpcSettings& ms, const std::string& name, double value) {
  double* fields[] = {&ms.approach_weight,    &ms.approach_goal,      &ms.spill_inner,
                      &ms.spill_outer,        &ms.spill_weight,       &ms.stream_near,
                      &ms.stream_far,         &ms.centre_weight,      &ms.moving_spill_outer,
                      &ms.moving_stream_near, &ms.moving_stream_far,  &ms.moving_centre_weight};
  const char* names[] = {"approach_weight",    "approach_goal",      "spill_inner",
                         "spill_outer",        "spill_weight",       "stream_near",
                         "stream_far",         "centre_weight",      "moving_spill_outer",
                         "moving_stream_near", "moving_stream_far",  "moving_centre_weight"};
  for (int k = 0; k < 12; ++k)
    if (name == names[k]) return *fields[k] = value, true;
  if (name == "stop_at") return ms.stop_at = value, true;
  if (name == "stop_tilt_rate") return ms.stop_tilt_rate = value, true;
  if (name == "horizon") return ms.horizon = int(value), true;
  if (name == "bottle_stream_width") return ms.bottle_stream_width = value != 0, true;
  return false;
}

MpcAction mpc_decide(const FeedbackContext& c, const FeedbackPredictor& net, const MpcSettings& settings,
                     double time_s, const Pose& pose, double fraction, const MpcAction& committed) {
  const LiquidModel& m = *c.model;
  MpcSettings ms = settings;
  if (target_moves(m))
    ms.spill_outer = ms.moving_spill_outer, ms.stream_near = ms.moving_stream_near, ms.stream_far = ms.moving_stream_far,
    ms.centre_weight = ms.moving_centre_weight;
  if (m.source.shape.type == ContainerShape::Bottle && !ms.bottle_stream_width) ms.stream_near = ms.stream_far = 0;
  // Stop rule (MpcSettings::stop_at): upright before the end, no rollout.
  if (!target_moves(m) && ms.stop_at > 0 && time_s >= ms.stop_at * m.planner.pour_time_s - 1e-9)
    return MpcAction{-ms.stop_tilt_rate, 0, 0};
  const double dt = net.interval_s, g = gravity_norm(m);
  const double max_tilt = m.planner.max_tilt_rad;
  const double rim = m.target.pose.position_m[1] + m.target.shape.height_m;
  const double inner = m.target.shape.opening_radius() - 0.3 * m.target.shape.wall_m;
  // Candidates: every (tilt rate, vx, vy) of the settings' grid.
  std::vector<MpcAction> cand;
  for (double w : ms.tilt_rates)
    for (double vx : ms.speeds)
      for (double vy : {0.0, 0.04}) cand.push_back({w, vx, vy});
  const int n = int(cand.size());
  std::vector<Rollout> st(n, Rollout{pose.tilt_rad, pose.position_m[0], pose.position_m[1], fraction});
  std::vector<double> cost(n, 0.0);
  Eigen::MatrixXd X(kFeedbackFeatures, n);
  // Step 0 is the committed interval (the same for every candidate), then the
  // candidate is held for `horizon` intervals.
  for (int step = 0; step <= ms.horizon; ++step) {
    for (int i = 0; i < n; ++i) {
      const MpcAction& a = step == 0 ? committed : cand[i];
      const double w = st[i].tilt >= max_tilt ? 0.0 : a.tilt_rate;
      X.col(i) = net.input(c.features(st[i].tilt, w, a.vx, a.vy, st[i].fraction));
    }
    const Eigen::MatrixXd F = net.flow.forward_batch(X), E = net.exit.forward_batch(X);
    const double t_end = time_s + (step + 1) * dt;
    for (int i = 0; i < n; ++i) {
      const MpcAction& a = step == 0 ? committed : cand[i];
      Rollout& r = st[i];
      const double w = r.tilt >= max_tilt ? 0.0 : a.tilt_rate;
      const double dv = std::min(r.fraction, std::max(0.0, F(0, i) * net.flow_scale) * dt);
      // The stream's parabola from the predicted exit point and velocity.
      Pose p;
      p.position_m = {r.x, r.y, 0};
      p.tilt_rad = r.tilt;
      const Vec3 lip = c.lip(p);
      const double ex = lip[0] + 0.1 * E(0, i), ey = lip[1] + 0.1 * E(1, i);
      const double wz = -w;
      const double vx = a.vx - wz * (lip[1] - r.y) + E(2, i), vy = a.vy + wz * (lip[0] - r.x) + E(3, i);
      const double disc = vy * vy + 2 * g * (ey - rim);
      const double flight = disc >= 0 ? (vy + std::sqrt(disc)) / g : 0.0;
      const double land = ex + vx * flight;
      // Measured against where the (FOLLOW: moving) target is when the stream arrives.
      const double centre = target_pose_at(m, t_end - 0.5 * dt + flight).position_m[0];
      const double d = std::abs(land - centre) / inner;
      // Stream width (MpcSettings): the near edge is the lip's own fall with
      // the container's velocity.
      const double lvx = a.vx - wz * (lip[1] - r.y), lvy = a.vy + wz * (lip[0] - r.x);
      const double ld = lvy * lvy + 2 * g * (lip[1] - rim);
      const double near = lip[0] + lvx * (ld >= 0 ? (lvy + std::sqrt(ld)) / g : 0.0);
      const double spill = stream_spill(ms, land, near, centre, inner);
      cost[i] += ms.spill_weight * dv * spill - dv * (1 - spill) + ms.centre_weight * std::max(dv, 0.01) * d * d;
      r.fraction -= dv;
      r.tilt = std::min(max_tilt, r.tilt + w * dt);
      r.x += a.vx * dt, r.y += a.vy * dt;
      p.position_m = {r.x, r.y, 0};
      p.tilt_rad = r.tilt;
      cost[i] += 1e3 * pose_violation(m, p, t_end);
      // Approach: before the flow has started, bring the lip over the near part
      // of the opening (approach_goal inner radii short of the centre). The
      // first trickle falls almost straight down from the lip, earlier and
      // shorter than the networks' mean stream, so a source still far from the
      // target at the onset spilled it (the main failure of the first MPC on
      // validation problems). The term fades out by 60% of the pour time: where
      // the networks predict the stream would miss from the approach position,
      // it otherwise held the tilt below the onset for the whole pour.
      const double pre = std::clamp((r.fraction - 0.9) / 0.07, 0.0, 1.0) *
                         std::clamp(1 - t_end / (0.6 * m.planner.pour_time_s), 0.0, 1.0);
      if (ms.approach_weight > 0 && pre > 0) {
        const double goal = target_pose_at(m, t_end + 0.2).position_m[0] - ms.approach_goal * inner;
        const double e = (c.lip(p)[0] - goal) / inner;
        cost[i] += ms.approach_weight * pre * e * e;
      }
      if (step == ms.horizon) {
        // Liquid still in the source weighs more as the pour's time runs out;
        // a little tilt progress gets the flow started at all.
        const double late = std::clamp(t_end / m.planner.pour_time_s, 0.0, 1.0);
        cost[i] += (0.5 + 3 * late) * r.fraction + 0.4 * r.fraction * (max_tilt - r.tilt) / max_tilt;
      }
    }
  }
  int best = 0;
  for (int i = 0; i < n; ++i) {
    const MpcAction& a = cand[i];
    cost[i] += 0.01 * (std::pow(a.tilt_rate - committed.tilt_rate, 2) +
                       100 * (std::pow(a.vx - committed.vx, 2) + std::pow(a.vy - committed.vy, 2)));
    if (cost[i] < cost[best]) best = i;  // first minimum: deterministic
  }
  return cand[best];
}

FeedbackRun run_feedback(const LiquidModel& model, const FeedbackPredictor& net, const MpcSettings& ms,
                         LiquidState s, Trajectory path,
                         const std::function<void(const LiquidModel&, const LiquidState&)>& on_frame) {
  LiquidModel m = model;
  const double dt = net.interval_s;
  const int K = std::max(1, int(std::lround(dt / m.dt_s)));
  if (path.keys.size() < 2) path.keys = {{0.0, m.source.pose}, {dt, m.source.pose}};
  m.source_path = path;
  FeedbackContext c(m);
  FeedbackRun run;
  double total_ms = 0, total_cpu_ms = 0;
  for (int f = s.frame; f < m.frames; ++f) {
    auto& keys = m.source_path.keys;
    // At the start of each interval the key two intervals ahead is chosen.
    if (f % K == 0 && keys.back().time_s < f * m.dt_s + 2 * dt - 1e-9) {
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = thread_cpu_ms();
      const KeyPose& a = keys[keys.size() - 2];
      const KeyPose& b = keys.back();
      const double span = b.time_s - a.time_s;
      const MpcAction committed{(b.pose.tilt_rad - a.pose.tilt_rad) / span,
                                (b.pose.position_m[0] - a.pose.position_m[0]) / span,
                                (b.pose.position_m[1] - a.pose.position_m[1]) / span};
      const double fraction = source_volume_fraction(c, s);
      const MpcAction act =
          mpc_decide(c, net, ms, s.time_s, source_pose_at(m, s.time_s), fraction, committed);
      KeyPose next = b;
      next.time_s = b.time_s + dt;
      // The stop rule's negative rate ends upright, not past it.
      next.pose.tilt_rad = std::clamp(b.pose.tilt_rad + act.tilt_rate * dt, std::min(0.0, b.pose.tilt_rad), m.planner.max_tilt_rad);
      next.pose.position_m[0] += act.vx * dt;
      next.pose.position_m[1] += act.vy * dt;
      keys.push_back(next);
      const double ms_step = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      total_ms += ms_step;
      total_cpu_ms += thread_cpu_ms() - c0;
      run.mpc_step_ms_max = std::max(run.mpc_step_ms_max, ms_step);
      ++run.mpc_steps;
    }
    liquid_step(m, s);
    if (on_frame) on_frame(m, s);
  }
  run.mpc_step_ms_mean = run.mpc_steps ? total_ms / run.mpc_steps : 0;
  run.mpc_step_cpu_ms_mean = run.mpc_steps ? total_cpu_ms / run.mpc_steps : 0;
  run.path = m.source_path;
  run.final_state = std::move(s);
  return run;
}

}  // namespace pliant::liquid
