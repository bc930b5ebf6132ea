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

namespace {

constexpr int kCheckpointEveryFrames = 10;

// Doubles travel as (hi, lo) float pairs so a resumed run uses the same path.
void push_double(std::vector<float>& out, double d) {
  const float hi = float(d);
  out.push_back(hi);
  out.push_back(float(d - double(hi)));
}
double pop_double(const std::vector<float>& in, size_t& i) {
  const double d = double(in[i]) + double(in[i + 1]);
  i += 2;
  return d;
}

// Exact particle state and the (planned) source path.
Record checkpoint_record(const LiquidState& s, const Trajectory& path) {
  Record r;
  r.kind = RecordKind::Checkpoint;
  r.index = s.frame;
  r.time_s = s.time_s;
  r.fields.push_back(Field{"x", {uint32_t(s.x.size())}, s.x});
  r.fields.push_back(Field{"v", {uint32_t(s.v.size())}, s.v});
  std::vector<float> keys;
  for (const KeyPose& k : path.keys)
    for (double d : {k.time_s, k.pose.position_m[0], k.pose.position_m[1], k.pose.position_m[2], k.pose.tilt_rad})
      push_double(keys, d);
  if (keys.empty()) push_double(keys, -1);  // no fields of size zero
  r.fields.push_back(Field{"path", {uint32_t(keys.size())}, keys});
  return r;
}

bool restore_checkpoint(const LiquidModel& m, const Record& r, LiquidState& s, Trajectory& path) {
  const Field *x = r.find("x"), *v = r.find("v"), *p = r.find("path");
  if (!x || !v || !p || x->data.size() != v->data.size() || x->data.size() % 3 || r.index < 0 ||
      r.index > m.frames)
    return false;
  s = LiquidState{};
  s.frame = r.index;
  s.time_s = r.index * m.dt_s;
  s.x = x->data, s.v = v->data;
  path.keys.clear();
  if (p->data.size() % 10 == 0) {
    for (size_t i = 0; i + 10 <= p->data.size();) {
      KeyPose k;
      k.time_s = pop_double(p->data, i);
      for (int a = 0; a < 3; ++a) k.pose.position_m[a] = pop_double(p->data, i);
      k.pose.tilt_rad = pop_double(p->data, i);
      path.keys.push_back(k);
    }
  }
  return true;
}

}  // namespace

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
  // --resume: continue from the latest checkpoint (it holds the planned path,
  // so planning is not repeated).
  LiquidState s;
  bool resumed = false;
  if (ctx.resume) {
    Record cp;
    Trajectory path;
    if (TakeReader(ctx.take.dir()).latest(RecordKind::Checkpoint, &cp) && restore_checkpoint(m, cp, s, path)) {
      resumed = true;
      m.source_path = path;
      metrics["resumed_from_frame"] = s.frame;
    }
  }
  if (!resumed) {
    switch (m.planner.planner) {
      case Planner::None: break;
      case Planner::Simplified: m.source_path = plan_simplified(m, ctx.progress, &info); break;
      case Planner::Correction: m.source_path = plan_correction(m, ctx.progress, &info); break;
      case Planner::Feedback:
        throw InputError(ctx.scene.file, "/planner/mode",
                         "planner \"feedback\" is not implemented yet (use simplified or correction)");
    }
  }
  const double plan_s = seconds_since(t0);
  if (m.planner.planner != Planner::None) {
    if (!resumed) metrics["plan_s"] = plan_s, metrics["planner"] = info;
    nlohmann::json keys = nlohmann::json::array();
    for (const KeyPose& k : m.source_path.keys)
      keys.push_back({{"time_s", k.time_s},
                      {"position_m", {k.pose.position_m[0], k.pose.position_m[1], k.pose.position_m[2]}},
                      {"tilt_deg", k.pose.tilt_rad * 180 / 3.14159265358979323846}});
    metrics["trajectory"] = keys;
  }

  const auto t1 = std::chrono::steady_clock::now();
  ctx.progress.stage("simulate", m.frames);
  if (!resumed) {
    s = liquid_init(m);
    ctx.take.append(liquid_frame_record(m, s));
    ctx.take.append(checkpoint_record(s, m.source_path));
    ctx.events.frame(0);
  }
  long long pressure_iterations = 0;
  double max_speed = 0;
  long long particle_steps = 0;
  PourTracks tracks(m, s);  // streamlines (C_OBJ) only for runs from frame 0
  for (int f = s.frame; f < m.frames; ++f) {
    ctx.progress.check_cancelled();
    StepStats st;
    liquid_step(m, s, &st);
    pressure_iterations += st.pressure_iterations;
    max_speed = std::max(max_speed, st.max_speed);
    particle_steps += (long long)st.substeps * (long long)s.count();
    if (m.has_source && m.has_target && !resumed) tracks.record(s);
    ctx.take.append(liquid_frame_record(m, s));
    if (s.frame % kCheckpointEveryFrames == 0) ctx.take.append(checkpoint_record(s, m.source_path));
    ctx.events.frame(s.frame);
    const auto fr = liquid_fractions(m, s);
    ctx.progress.report(f + 1, fr[1]);
  }
  const double sim_s = seconds_since(t1);
  const auto fr = liquid_fractions(m, s);
  metrics["fraction_in_target"] = fr[0];
  metrics["fraction_spilled"] = fr[1];
  metrics["fraction_in_source"] = fr[2];
  if (m.has_source && m.has_target && !resumed) {
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
