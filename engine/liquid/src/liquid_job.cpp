// The "liquid" job kind: plan (planner != none), then simulate the trajectory
// with the full FLIP simulator, writing one take frame per frame; metrics are
// those of this validation run.
#include <omp.h>

#include <chrono>
#include <memory>
#include <stdexcept>

#include "planners.h"
#include "pliant/liquid/feedback.h"
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
      case Planner::Feedback: break;  // plans while it simulates (below)
    }
  }
  const bool feedback = m.planner.planner == Planner::Feedback;
  FeedbackPredictor net;
  if (feedback) {
    try {
      net = FeedbackPredictor::load(m.planner.network);
    } catch (const std::exception& e) {
      throw InputError(ctx.scene.file, "/planner/network", e.what());
    }
  }
  const double plan_s = seconds_since(t0);
  if (m.planner.planner != Planner::None && !resumed && !feedback) metrics["plan_s"] = plan_s, metrics["planner"] = info;

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
  std::unique_ptr<FeedbackContext> sample_ctx;
  std::unique_ptr<SampleRecorder> samples;
  if (m.planner.record_samples && !resumed) {
    sample_ctx = std::make_unique<FeedbackContext>(m);
    samples = std::make_unique<SampleRecorder>(*sample_ctx, s, m.planner.interval_s);
  }
  // Bookkeeping after every frame; `mm` is the model the frame was simulated
  // with (the feedback planner extends its path as it goes).
  long long last_substeps = s.substeps;
  auto after_frame = [&](const LiquidModel& mm, const LiquidState& st) {
    if (feedback) m.source_path = mm.source_path;  // tracks and samples read m's path
    particle_steps += (st.substeps - last_substeps) * (long long)st.count();
    last_substeps = st.substeps;
    if (m.has_source && m.has_target && !resumed) tracks.record(st);
    if (samples) samples->record(st);
    ctx.take.append(liquid_frame_record(mm, st));
    if (st.frame % kCheckpointEveryFrames == 0) ctx.take.append(checkpoint_record(st, mm.source_path));
    ctx.events.frame(st.frame);
    const auto fr = liquid_fractions(mm, st);
    ctx.progress.report(st.frame, fr[1]);
    ctx.progress.check_cancelled();
  };
  if (feedback) {
    // Receding-horizon MPC: decisions interleaved with the simulated frames,
    // so this run is both the plan and its full-simulation validation.
    MpcSettings ms;
    ms.horizon = m.planner.horizon;
    FeedbackRun run = run_feedback(m, net, ms, s, m.source_path, after_frame);
    m.source_path = run.path;
    s = std::move(run.final_state);
    if (!resumed) {
      metrics["plan_s"] = run.mpc_step_ms_mean * run.mpc_steps / 1000;
      metrics["planner"] = {{"mode", "feedback"}, {"network", m.planner.network}, {"training_samples", net.samples}};
    }
    metrics["mpc_step_ms"] = run.mpc_step_ms_mean;
    metrics["mpc_step_ms_max"] = run.mpc_step_ms_max;
    metrics["mpc_step_cpu_ms"] = run.mpc_step_cpu_ms_mean;
    metrics["mpc_steps"] = run.mpc_steps;
  } else {
    for (int f = s.frame; f < m.frames; ++f) {
      ctx.progress.check_cancelled();
      StepStats st;
      liquid_step(m, s, &st);
      pressure_iterations += st.pressure_iterations;
      max_speed = std::max(max_speed, st.max_speed);
      after_frame(m, s);
    }
  }
  if (m.planner.planner != Planner::None) {
    nlohmann::json keys = nlohmann::json::array();
    for (const KeyPose& k : m.source_path.keys)
      keys.push_back({{"time_s", k.time_s},
                      {"position_m", {k.pose.position_m[0], k.pose.position_m[1], k.pose.position_m[2]}},
                      {"tilt_deg", k.pose.tilt_rad * 180 / 3.14159265358979323846}});
    metrics["trajectory"] = keys;
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
  if (samples) {
    // Dataset job: the validated pour's samples and those of random pours.
    std::vector<FeedbackSample> all = samples->samples();
    const auto extra = random_rollout_samples(m, m.planner.sample_rollouts, m.seed + 101, m.planner.interval_s,
                                              &ctx.progress);
    all.insert(all.end(), extra.begin(), extra.end());
    metrics["samples"] = SampleRecorder::to_json(all);
    metrics["samples_count"] = all.size();
  }
  return metrics;
}

}  // namespace pliant::liquid
