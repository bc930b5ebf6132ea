// The "liquid" job kind: plan (planner != none), then simulate the trajectory
// with the full FLIP simulator, writing one take frame per frame; metrics are
// those of this validation run.
#include <omp.h>

#include <chrono>
#include <stdexcept>

#include "planners.h"
#include "pliant/core/error.h"
#include "pliant/liquid/pour_tracks.h"
#include "pliant/liquid/liquid.h"

namespace pliant::liquid {

std::array<double, 3> simulate_fractions(const LiquidModel& m, Progress* progress) {
  LiquidState s = liquid_init(m);
  for (int f = 0; f < m.frames; ++f) {
    if (progress) progress->check_cancelled();
    liquid_step(m, s);
  }
  return liquid_fractions(m, s);
}

nlohmann::json liquid_run_job(JobContext& ctx) {
  LiquidModel m = liquid_compile(ctx.scene);
  if (ctx.threads > 0) omp_set_num_threads(ctx.threads);
  nlohmann::json metrics = nlohmann::json::object();
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds_since = [](auto t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  nlohmann::json info = nlohmann::json::object();
  switch (m.planner.planner) {
    case Planner::None: break;
    case Planner::Simplified: m.source_path = plan_simplified(m, ctx.progress, &info); break;
    case Planner::Correction: m.source_path = plan_correction(m, ctx.progress, &info); break;
    case Planner::Feedback:
      throw InputError(ctx.scene.file, "/planner/mode", "planner \"feedback\" is not implemented yet (use simplified or correction)");
  }
  const double plan_s = seconds_since(t0);
  if (m.planner.planner != Planner::None) {
    metrics["plan_s"] = plan_s;
    metrics["planner"] = info;
    nlohmann::json keys = nlohmann::json::array();
    for (const KeyPose& k : m.source_path.keys)
      keys.push_back({{"time_s", k.time_s},
                      {"position_m", {k.pose.position_m[0], k.pose.position_m[1], k.pose.position_m[2]}},
                      {"tilt_deg", k.pose.tilt_rad * 180 / 3.14159265358979323846}});
    metrics["trajectory"] = keys;
  }

  const auto t1 = std::chrono::steady_clock::now();
  LiquidState s = liquid_init(m);
  ctx.progress.stage("simulate", m.frames);
  ctx.take.append(liquid_frame_record(m, s));
  ctx.events.frame(0);
  long long pressure_iterations = 0;
  double max_speed = 0;
  long long particle_steps = 0;
  PourTracks tracks(m, s);
  for (int f = 0; f < m.frames; ++f) {
    ctx.progress.check_cancelled();
    StepStats st;
    liquid_step(m, s, &st);
    pressure_iterations += st.pressure_iterations;
    max_speed = std::max(max_speed, st.max_speed);
    particle_steps += (long long)st.substeps * (long long)s.count();
    if (m.has_source && m.has_target) tracks.record(s);
    ctx.take.append(liquid_frame_record(m, s));
    ctx.events.frame(s.frame);
    const auto fr = liquid_fractions(m, s);
    ctx.progress.report(f + 1, fr[1]);
  }
  const double sim_s = seconds_since(t1);
  const auto fr = liquid_fractions(m, s);
  metrics["fraction_in_target"] = fr[0];
  metrics["fraction_spilled"] = fr[1];
  metrics["fraction_in_source"] = fr[2];
  if (m.has_source && m.has_target) {
    int useful = 0;
    metrics["c_obj"] = tracks.objective(0.25 * m.cell_size_m, &useful);  // Eq. 2.6, metres summed
    metrics["c_obj_particles"] = useful;
  }
  metrics["particles"] = s.count();
  metrics["substeps"] = s.substeps;
  metrics["pressure_iterations"] = pressure_iterations;
  metrics["max_speed_m_per_s"] = max_speed;
  metrics["validate_s"] = sim_s;
  metrics["wall_per_sim_s"] = sim_s / std::max(1e-9, m.frames * m.dt_s);
  metrics["particle_steps_per_s"] = particle_steps / std::max(1e-9, sim_s);
  return metrics;
}

}  // namespace pliant::liquid
