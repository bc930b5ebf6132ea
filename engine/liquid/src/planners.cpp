// Pouring planners. "simplified" (section 2.5): CMA-ES over key poses against
// the simplified model; "correction" (Algorithm 2): alternate the full
// simulation with a closed-form correction of the trajectory under the
// rigid-follow model (a particle leaving the source during key interval k
// moves with the container's displacement d_k, Eq. 2.7), minimising the
// distance of the landing points to the opening centre (Eq. 2.6).
#include <algorithm>
#include <cmath>

#include "planners.h"
#include "pliant/core/error.h"
#include "pliant/liquid/pour_tracks.h"
#include "pliant/liquid/simplified_model.h"
#include "pliant/optim/cmaes.h"

namespace pliant::liquid {
namespace {

double gravity_magnitude(const LiquidModel& m) {
  const auto& g = m.gravity_m_per_s2;
  return std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
}

// Where the planners aim: the target's x when the pour is well under way (a
// FOLLOW target moves; a static one is where it is).
double target_x_while_pouring(const LiquidModel& m) {
  return target_pose_at(m, 0.6 * m.planner.pour_time_s).position_m[0];
}

// Search box of the key poses, relative to the start pose.
struct KeyBox {
  double x_lo, x_hi, y_lo, y_hi, tilt_hi;
};

KeyBox key_box(const LiquidModel& m) {
  const double D = target_x_while_pouring(m) - m.source.pose.position_m[0];
  // Keep the whole container (any tilt) inside the domain.
  const auto& c = m.source.shape;
  const double reach = std::hypot(c.radius_m + c.wall_m, c.height_m) + 0.01;
  const double y0 = m.source.pose.position_m[1], x0 = m.source.pose.position_m[0];
  const double y_hi = std::max(0.0, std::min(0.2, m.domain_max_m[1] - reach - y0));
  const double x_lo = std::max(std::min(-0.05, D - 0.1), m.domain_min_m[0] + reach - x0);
  const double x_hi = std::min(std::max(0.05, D + 0.05), m.domain_max_m[0] - reach - x0);
  return {x_lo, std::max(x_lo + 1e-3, x_hi), -0.05, std::max(y_hi, 1e-3), m.planner.max_tilt_rad};
}

// u in [0,1]^(3K) -> trajectory: start pose at t = 0, K keys up to pour_time_s.
Trajectory decode(const LiquidModel& m, const Eigen::VectorXd& u) {
  const KeyBox b = key_box(m);
  const int K = int(u.size()) / 3;
  Trajectory t;
  t.keys.push_back({0.0, m.source.pose});
  for (int k = 0; k < K; ++k) {
    KeyPose kp;
    kp.time_s = m.planner.pour_time_s * (k + 1) / K;
    kp.pose = m.source.pose;
    kp.pose.position_m[0] += b.x_lo + (b.x_hi - b.x_lo) * u[3 * k];
    kp.pose.position_m[1] += b.y_lo + (b.y_hi - b.y_lo) * u[3 * k + 1];
    // Tilt only grows (a pour never tips back): increments of up to 2 max / K.
    kp.pose.tilt_rad = std::min(b.tilt_hi, t.keys.back().pose.tilt_rad + 2 * b.tilt_hi / K * u[3 * k + 2]);
    t.keys.push_back(kp);
  }
  return t;
}

// Starting guess: drift toward the target, rise a little, tilt steadily.
Eigen::VectorXd initial_guess(const LiquidModel& m) {
  const KeyBox b = key_box(m);
  const int K = m.planner.keys;
  const double D = target_x_while_pouring(m) - m.source.pose.position_m[0];
  Eigen::VectorXd u(3 * K);
  for (int k = 0; k < K; ++k) {
    const double s = double(k + 1) / K;
    u[3 * k] = std::clamp((0.4 * D * s - b.x_lo) / (b.x_hi - b.x_lo), 0.0, 1.0);
    u[3 * k + 1] = (0.05 - b.y_lo) / (b.y_hi - b.y_lo);
    u[3 * k + 2] = 0.425;  // reaches 0.85 max_tilt at the last key
    (void)s;
  }
  return u;
}

// Spill and leftover, robot limits, and smoothness: the model knows nothing of
// sloshing, so fast or jerky motions (which it would happily exploit) are
// penalised by the squared key-to-key speeds (m/s, rad/s).
double plan_cost(const SimplifiedResult& r, const Trajectory& t) {
  double smooth = 0;
  for (size_t k = 1; k < t.keys.size(); ++k) {
    const double dt = t.keys[k].time_s - t.keys[k - 1].time_s;
    const auto& a = t.keys[k - 1].pose;
    const auto& b = t.keys[k].pose;
    const double dx = b.position_m[0] - a.position_m[0], dy = b.position_m[1] - a.position_m[1];
    smooth += (dx * dx + dy * dy) / (dt * dt) + 0.01 * std::pow((b.tilt_rad - a.tilt_rad) / dt, 2);
  }
  return 3 * r.spilled + 2 * r.remaining + 1e4 * r.collision + 0.3 * smooth / double(t.keys.size());
}

// Cd by golden-section search so the model's volume curve matches one full
// simulation of a steady tilt ramp (the fitted correction of section 2.5).
double fit_discharge(const LiquidModel& m, const OutflowTables& t, Progress& progress, double* rms) {
  LiquidModel ramp = m;
  ramp.source_path.keys = {{0.0, m.source.pose}, {m.planner.pour_time_s, m.source.pose}};
  ramp.source_path.keys[1].pose.tilt_rad = 0.75 * m.planner.max_tilt_rad;
  LiquidState s = liquid_init(ramp);
  std::vector<double> times, fractions;
  const int frames = int(std::ceil(m.planner.pour_time_s / m.dt_s));
  for (int f = 0; f < frames; ++f) {
    progress.check_cancelled();
    liquid_step(ramp, s);
    times.push_back(s.time_s);
    fractions.push_back(liquid_fractions(ramp, s)[2]);
  }
  auto err = [&](double cd) {
    double e = 0;
    for (size_t i = 0; i < times.size(); ++i) {
      const SimplifiedResult r = simulate_simplified(ramp, t, ramp.source_path, times[i], cd);
      e += std::pow(r.remaining - fractions[i], 2);
    }
    return e / times.size();
  };
  double a = 0.05, b = 3.0;
  const double phi = 0.5 * (std::sqrt(5.0) - 1);
  double c = b - phi * (b - a), d = a + phi * (b - a), fc = err(c), fd = err(d);
  for (int i = 0; i < 30; ++i) {
    if (fc < fd) b = d, d = c, fd = fc, c = b - phi * (b - a), fc = err(c);
    else a = c, c = d, fc = fd, d = a + phi * (b - a), fd = err(d);
  }
  const double cd = 0.5 * (a + b);
  *rms = std::sqrt(err(cd));
  return cd;
}

}  // namespace

Trajectory plan_simplified(const LiquidModel& m, Progress& progress, nlohmann::json* info) {
  const double g = gravity_magnitude(m);
  progress.stage("lookup_tables", 1);
  const OutflowTables tables = build_outflow_tables(m.source.shape, m.dim, g, m.planner.max_tilt_rad);
  double cd = m.planner.discharge_coefficient, fit_rms = -1;
  if (m.planner.fit_discharge) {
    progress.stage("fit_discharge", 1);
    cd = fit_discharge(m, tables, progress, &fit_rms);
  }
  const double duration = m.frames * m.dt_s;
  optim::CmaesOptions o;
  o.sigma0 = 0.2;
  o.population = m.planner.population;
  o.max_iterations = m.planner.generations;
  o.seed = m.planner.seed;
  o.parallel = true;
  const int n = 3 * m.planner.keys;
  o.lower = Eigen::VectorXd::Zero(n);
  o.upper = Eigen::VectorXd::Ones(n);
  auto cost = [&](const Eigen::VectorXd& u) {
    const Trajectory t = decode(m, u);
    return plan_cost(simulate_simplified(m, tables, t, duration, cd), t);
  };
  progress.stage("cmaes", m.planner.generations);
  const optim::CmaesResult r = optim::cmaes_minimize(cost, initial_guess(m), o, [&](int it, double f) {
    progress.report(it, f);
    return !progress.cancelled();
  });
  progress.check_cancelled();
  const Trajectory best = decode(m, r.x);
  const SimplifiedResult pred = simulate_simplified(m, tables, best, duration, cd);
  if (info) {
    (*info)["mode"] = "simplified";
    (*info)["discharge_coefficient"] = cd;
    if (fit_rms >= 0) (*info)["discharge_fit_rms"] = fit_rms;
    (*info)["cmaes_generations"] = r.iterations;
    (*info)["cmaes_evaluations"] = r.evaluations;
    (*info)["cost"] = r.f;
    (*info)["predicted_transfer"] = pred.transferred;
    (*info)["predicted_spilled"] = pred.spilled;
    (*info)["predicted_remaining"] = pred.remaining;
  }
  if (m.planner.refine_iterations <= 0) return best;
  // The model ignores splashing and the stream's width; a few rounds of
  // Algorithm 2 on the full simulation correct where the stream really lands
  // (the first round validates the CMA-ES plan itself; the best round wins).
  LiquidModel refine = m;
  refine.source_path = best;
  refine.planner.iterations = m.planner.refine_iterations;
  nlohmann::json rinfo;
  const Trajectory refined = plan_correction(refine, progress, &rinfo);
  if (info) (*info)["refine"] = rinfo["iterations"];
  return refined;
}

Trajectory plan_correction(const LiquidModel& m, Progress& progress, nlohmann::json* info) {
  LiquidModel cur = m;
  if (cur.source_path.keys.size() < 2) cur.source_path = decode(m, initial_guess(m));
  const int iters = m.planner.iterations;
  const double inner = m.target.shape.opening_radius() - 0.3 * m.target.shape.wall_m;
  Trajectory best = cur.source_path;
  double best_transfer = -1;
  std::vector<double> direction;  // correction of the best plan, per key (m)
  double tilt_direction = 0, step = 0.7;
  nlohmann::json history = nlohmann::json::array();
  progress.stage("correction", iters);
  for (int it = 1; it <= iters; ++it) {
    // P_k from Q_k: the full simulation (Algorithm 1).
    LiquidState s = liquid_init(cur);
    PourTracks tracks(cur, s);
    for (int f = 0; f < cur.frames; ++f) {
      progress.check_cancelled();
      liquid_step(cur, s);
      tracks.record(s);
    }
    const auto fr = liquid_fractions(cur, s);
    int useful = 0;
    const double cobj = tracks.objective(0.25 * m.cell_size_m, &useful);
    history.push_back({{"iteration", it}, {"in_target", fr[0]}, {"spilled", fr[1]}, {"in_source", fr[2]},
                       {"c_obj", cobj}});
    progress.report(it, fr[1]);
    const bool improved = fr[0] > best_transfer;
    if (improved) {
      best_transfer = fr[0], best = cur.source_path;
      // Q_{k+1} direction from the best P_k: per key interval, the rigid
      // displacement d_k that moves the landing points of the particles
      // leaving then onto the opening (least squares: minus the mean miss of
      // those that miss), and more tilt at the end if liquid stays behind.
      const auto& keys = best.keys;
      const int K = int(keys.size());
      std::vector<double> miss(K, 0.0);
      std::vector<int> count(K, 0), total(K, 0);
      // A particle counts as a miss when it lands outside the opening, or lands
      // inside but ends up spilled (splashed over the far wall): either way its
      // landing offset says which way to move.
      const Pose end_pose = source_pose_at(cur, s.time_s), target_end = target_pose_at(cur, s.time_s);
      for (size_t p = 0; p < tracks.tracks().size(); ++p) {
        const auto& t = tracks.tracks()[p];
        if (t.leave_time < 0 || !t.landed) continue;
        int k = 1;
        while (k < K - 1 && t.leave_time > keys[k].time_s) ++k;
        ++total[k];
        const Vec3 x{s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]};
        const bool spilled = !m.target.shape.in_cavity(target_end.to_local(x), m.dim) &&
                             !m.source.shape.in_cavity(end_pose.to_local(x), m.dim);
        // Miss relative to where the (possibly moving) opening was at landing.
        const double dx = t.landing_offset[0];
        if (std::abs(dx) > inner || spilled) miss[k] += dx, ++count[k];
      }
      direction.assign(K, 0.0);
      for (int k = 1; k < K; ++k)
        if (count[k] > 0 && count[k] >= 0.01 * std::max(1, total[k])) direction[k] = -miss[k] / count[k];
      tilt_direction = fr[2] > 0.02 ? 0.2 : 0.0;
      step = 0.7;
    } else {
      step *= 0.5;  // the trial was worse: back to the best plan, shorter step
    }
    if (it == iters) break;
    Trajectory next = best;
    double change = 0;
    for (size_t k = 1; k < next.keys.size() && k < direction.size(); ++k) {
      const double d = std::clamp(step * direction[k], -0.05, 0.05);
      next.keys[k].pose.position_m[0] += d;
      change = std::max(change, std::abs(d));
    }
    auto& last = next.keys.back().pose.tilt_rad;
    const double nt = std::min(m.planner.max_tilt_rad, last + step * tilt_direction);
    change = std::max(change, nt - last);
    last = nt;
    cur.source_path = next;
    if (change < 1e-3) break;  // ||Q_{k+1} - Q_k||_inf small
  }
  if (info) {
    (*info)["mode"] = "correction";
    (*info)["iterations"] = history;
  }
  return best;
}

}  // namespace pliant::liquid
