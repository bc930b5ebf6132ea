// Feedback planner, offline part 1: features of a pour state and the samples
// (features -> what the full simulator did) cut from full simulations.
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "pliant/liquid/feedback.h"

namespace pliant::liquid {
namespace {

double gravity_norm(const LiquidModel& m) {
  const auto& g = m.gravity_m_per_s2;
  return std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
}

// Velocity of a world point rigidly attached to the source (rotation about z).
Vec3 attached_velocity(const Pose& pose, const Vec3& lin, double tilt_rate, const Vec3& x) {
  const double wz = -tilt_rate;  // positive tilt turns clockwise (toward +x)
  return {lin[0] - wz * (x[1] - pose.position_m[1]), lin[1] + wz * (x[0] - pose.position_m[0]), lin[2]};
}

}  // namespace

FeedbackContext::FeedbackContext(const LiquidModel& m)
    : model(&m),
      tables(build_outflow_tables(m.source.shape, m.dim, gravity_norm(m), std::max(m.planner.max_tilt_rad, 2.6),
                                  41, 31)) {
  vol0 = m.fill_fraction * tables.capacity;
  if (m.source.shape.type == ContainerShape::Bottle) vol0 = std::min(vol0, tables.capacity);
  vol0 = std::max(vol0, 1e-12);
  const LiquidState s = liquid_init(m);
  const Pose pose = source_pose_at(m, 0);
  for (size_t p = 0; p < s.count(); ++p)
    particles0 += m.source.shape.in_cavity(pose.to_local({s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]}), m.dim);
  particles0 = std::max<size_t>(particles0, 1);
}

Vec3 FeedbackContext::lip(const Pose& p) const {
  const ContainerShape& c = model->source.shape;
  return p.to_world({c.opening_radius() + 0.5 * c.wall_m, c.height_m, 0});
}

std::array<double, kFeedbackFeatures> FeedbackContext::features(double tilt, double tilt_rate, double vx, double vy,
                                                                double fraction) const {
  const LiquidModel& m = *model;
  const ContainerShape& c = m.source.shape;
  const double vol = std::clamp(fraction, 0.0, 1.0) * vol0;
  std::array<double, kFeedbackFeatures> f{};
  f[0] = tilt;
  f[1] = tilt_rate;
  f[2] = vx;
  f[3] = vy;
  f[4] = fraction;
  f[5] = tables.lookup(tables.dh, tilt, vol) / c.height_m;
  f[6] = fraction > 0 ? tables.lookup(tables.weir, tilt, vol) / vol0 : 0.0;  // Bernoulli, Cd = 1
  f[7] = m.fill_fraction;
  f[8] = c.radius_m / 0.05;
  f[9] = c.height_m / 0.12;
  f[10] = c.opening_radius() / 0.05;
  f[11] = std::log10(std::max(m.viscosity_pa_s, 1e-4));
  if (c.type < ContainerShape::Mesh) f[12 + int(c.type)] = 1;  // compile rejects mesh sources here
  return f;
}

double source_volume_fraction(const FeedbackContext& c, const LiquidState& s) {
  const LiquidModel& m = *c.model;
  const Pose pose = source_pose_at(m, s.time_s);
  size_t in = 0;
  for (size_t p = 0; p < s.count(); ++p)
    in += m.source.shape.in_cavity(pose.to_local({s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]}), m.dim);
  return double(in) / double(c.particles0);
}

SampleRecorder::SampleRecorder(const FeedbackContext& c, const LiquidState& s, double interval_s) : c_(c) {
  frames_per_interval_ = std::max(1, int(std::lround(interval_s / c.model->dt_s)));
  const LiquidModel& m = *c.model;
  const Pose pose = source_pose_at(m, s.time_s);
  in_source_.resize(s.count());
  for (size_t p = 0; p < s.count(); ++p)
    in_source_[p] = m.source.shape.in_cavity(pose.to_local({s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]}), m.dim);
  begin(s);
}

void SampleRecorder::begin(const LiquidState& s) {
  const LiquidModel& m = *c_.model;
  const double dt = frames_per_interval_ * m.dt_s;
  const Pose a = source_pose_at(m, s.time_s), b = source_pose_at(m, s.time_s + dt);
  start_fraction_ = source_volume_fraction(c_, s);
  cur_ = FeedbackSample{};
  cur_.x = c_.features(a.tilt_rad, (b.tilt_rad - a.tilt_rad) / dt, (b.position_m[0] - a.position_m[0]) / dt,
                       (b.position_m[1] - a.position_m[1]) / dt, start_fraction_);
  sum_ = {};
  frames_in_ = 0;
}

void SampleRecorder::record(const LiquidState& s) {
  const LiquidModel& m = *c_.model;
  const Pose pose = source_pose_at(m, s.time_s);
  Vec3 lin;
  double rate;
  m.source_path.velocity(s.time_s, &lin, &rate);
  const Vec3 lip = c_.lip(pose);
  const Vec3 lip_v = attached_velocity(pose, lin, rate, lip);
  const size_t old = in_source_.size();
  in_source_.resize(s.count(), 0);
  for (size_t p = 0; p < s.count(); ++p) {
    const Vec3 x{s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]};
    const bool in = m.source.shape.in_cavity(pose.to_local(x), m.dim);
    if (p < old && in_source_[p] && !in) {
      ++cur_.leaving;
      sum_[0] += 10 * (x[0] - lip[0]);
      sum_[1] += 10 * (x[1] - lip[1]);
      sum_[2] += s.v[3 * p] - lip_v[0];
      sum_[3] += s.v[3 * p + 1] - lip_v[1];
    }
    in_source_[p] = in;
  }
  if (++frames_in_ < frames_per_interval_) return;
  const double dt = frames_per_interval_ * m.dt_s;
  cur_.outflow_rate = double(cur_.leaving) / double(c_.particles0) / dt;
  for (int i = 0; i < kFeedbackExitOutputs; ++i) cur_.exit[i] = cur_.leaving > 0 ? sum_[i] / cur_.leaving : 0.0;
  samples_.push_back(cur_);
  begin(s);
}

nlohmann::json SampleRecorder::to_json(const std::vector<FeedbackSample>& samples) {
  nlohmann::json rows = nlohmann::json::array();
  for (const FeedbackSample& s : samples) {
    nlohmann::json r = nlohmann::json::array();
    for (double v : s.x) r.push_back(v);
    r.push_back(s.outflow_rate);
    r.push_back(s.leaving);
    for (double v : s.exit) r.push_back(v);
    rows.push_back(r);
  }
  return {{"layout", "features[17], outflow_rate, leaving, exit[4]"}, {"rows", rows}};
}

std::vector<FeedbackSample> SampleRecorder::from_json(const nlohmann::json& j) {
  std::vector<FeedbackSample> out;
  const size_t width = kFeedbackFeatures + 2 + kFeedbackExitOutputs;
  if (!j.is_object() || !j.contains("rows") || !j["rows"].is_array())
    throw std::runtime_error("samples: expected {\"rows\": [...]}");
  for (const auto& r : j["rows"]) {
    if (!r.is_array() || r.size() != width)
      throw std::runtime_error("samples: every row needs " + std::to_string(width) + " numbers");
    FeedbackSample s;
    for (int i = 0; i < kFeedbackFeatures; ++i) s.x[i] = r[i].get<double>();
    s.outflow_rate = r[kFeedbackFeatures].get<double>();
    s.leaving = r[kFeedbackFeatures + 1].get<int>();
    for (int i = 0; i < kFeedbackExitOutputs; ++i) s.exit[i] = r[kFeedbackFeatures + 2 + i].get<double>();
    out.push_back(s);
  }
  return out;
}

std::vector<FeedbackSample> random_rollout_samples(const LiquidModel& base, int rollouts, uint64_t seed,
                                                  double interval_s, Progress* progress) {
  std::vector<FeedbackSample> out;
  std::mt19937_64 rng(seed * 7919 + 3);
  std::uniform_real_distribution<double> U(0, 1);
  const ContainerShape& c = base.source.shape;
  const double reach = std::hypot(c.radius_m + c.wall_m, c.height_m) + 0.01;
  const double x0 = base.source.pose.position_m[0], y0 = base.source.pose.position_m[1];
  const double D = base.target.pose.position_m[0] - x0;
  const double x_lo = std::max(x0 - 0.05, base.domain_min_m[0] + reach);
  const double x_hi = std::min(x0 + std::max(0.05, D + 0.02), base.domain_max_m[0] - reach);
  const double y_hi = std::max(y0, std::min(y0 + 0.08, base.domain_max_m[1] - reach));
  for (int r = 0; r < rollouts; ++r) {
    LiquidModel m = base;
    // Random monotone tilt (keys every 0.2 s to a random final tilt), random
    // horizontal drift: what the MPC's candidates do, with the same speeds.
    const double span = base.planner.pour_time_s * (0.7 + 0.5 * U(rng));
    const int keys = std::max(2, int(std::lround(span / 0.2)));
    const double final_tilt = base.planner.max_tilt_rad * (0.6 + 0.4 * U(rng));
    m.source_path.keys = {{0.0, base.source.pose}};
    std::vector<double> inc(keys);
    double total = 0;
    for (double& v : inc) total += (v = 0.05 + U(rng));
    Pose p = base.source.pose;
    for (int k = 0; k < keys; ++k) {
      p.tilt_rad += final_tilt * inc[k] / total;
      p.position_m[0] = std::clamp(p.position_m[0] + (U(rng) - 0.35) * 0.04, x_lo, x_hi);
      p.position_m[1] = std::clamp(p.position_m[1] + (U(rng) - 0.4) * 0.02, y0, y_hi);
      m.source_path.keys.push_back({span * (k + 1) / keys, p});
    }
    FeedbackContext ctx(m);
    LiquidState s = liquid_init(m);
    SampleRecorder rec(ctx, s, interval_s);
    for (int f = 0; f < m.frames; ++f) {
      if (progress) progress->check_cancelled();
      liquid_step(m, s);
      rec.record(s);
    }
    out.insert(out.end(), rec.samples().begin(), rec.samples().end());
  }
  return out;
}

}  // namespace pliant::liquid
