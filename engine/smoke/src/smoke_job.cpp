// Take records and the "smoke" job kind (forward simulation).
//
// Checkpoints: every kCheckpointEveryFrames frames the job appends a Checkpoint
// record holding the exact MAC state (density, u, v, w, pressure warm start; flat
// arrays). `--resume` restarts from the latest checkpoint that fits the scene's
// grid, so a resumed take is bitwise equal to an uninterrupted one (the step is
// deterministic for a fixed thread count); without one it starts from frame 0.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "pliant/smoke/control.h"
#include "pliant/smoke/smoke.h"
#include "smoke_workspace.h"

namespace pliant::smoke {
namespace {

constexpr int kCheckpointEveryFrames = 10;

Field flat(const char* name, const std::vector<float>& a) {
  return Field{name, {uint32_t(a.size())}, a};
}

Record checkpoint_record(const SmokeState& s) {
  Record r;
  r.kind = RecordKind::Checkpoint;
  r.index = s.frame;
  r.time_s = s.time_s;
  r.fields = {flat("density", s.density), flat("u", s.u), flat("v", s.v), flat("pressure", s.pressure)};
  if (!s.w.empty()) r.fields.push_back(flat("w", s.w));  // no zero-length fields in 2D
  return r;
}

// Restores `s` from a checkpoint when every array has the size the model expects.
bool restore_checkpoint(const SmokeModel& m, const Record& r, SmokeState& s) {
  if (r.index < 0 || r.index > m.frames) return false;
  SmokeState out = smoke_init(m);
  for (auto [name, dst] : {std::pair{"density", &out.density}, std::pair{"u", &out.u},
                           std::pair{"v", &out.v}, std::pair{"w", &out.w}, std::pair{"pressure", &out.pressure}}) {
    const Field* f = r.find(name);
    if (dst->empty() && !f) continue;  // w in 2D
    if (!f || f->data.size() != dst->size()) return false;
    *dst = f->data;
  }
  out.frame = r.index;
  out.time_s = r.index * m.dt_s;
  s = std::move(out);
  return true;
}

// Name of the first field holding a NaN/Inf, or nullptr.
const char* first_non_finite(const SmokeState& s) {
  auto bad = [](const std::vector<float>& a) {
    bool found = false;
    const size_t n = a.size();
    const float* p = a.data();
#pragma omp parallel for schedule(static) reduction(|| : found)
    for (size_t i = 0; i < n; ++i) found = found || !std::isfinite(p[i]);
    return found;
  };
  if (bad(s.u) || bad(s.v) || bad(s.w)) return "velocity";
  if (bad(s.density)) return "density";
  if (bad(s.pressure)) return "pressure";
  return nullptr;
}

}  // namespace

Record smoke_frame_record(const SmokeModel& m, const SmokeState& s) {
  const MacGrid g = model_grid(m);
  Record r;
  r.kind = RecordKind::Frame;
  r.index = s.frame;
  r.time_s = s.time_s;
  std::vector<uint32_t> shape;
  if (g.dim == 3) shape.push_back(uint32_t(g.n[2]));
  shape.push_back(uint32_t(g.n[1]));
  shape.push_back(uint32_t(g.n[0]));
  r.fields.push_back(Field{"density", shape, s.density});
  if (m.write_velocity) {
    Field v{"velocity", shape, {}};
    v.shape.push_back(uint32_t(g.dim));
    v.data.resize(g.cells() * g.dim);
    cell_centred_velocity(g, FaceVelocity{s.u.data(), s.v.data(), g.dim == 3 ? s.w.data() : nullptr},
                          v.data.data());
    r.fields.push_back(std::move(v));
  }
  return r;
}

nlohmann::json smoke_run_job(JobContext& ctx) {
  if (scene_has_control(ctx.scene)) return smoke_control_run_job(ctx);  // keyframe control (control.h)
  const SmokeModel m = smoke_compile(ctx.scene);
  if (ctx.threads > 0) omp_set_num_threads(ctx.threads);
  const MacGrid g = model_grid(m);
  const auto t0 = std::chrono::steady_clock::now();

  SmokeState s = smoke_init(m);
  int start = 0;
  if (ctx.resume) {
    Record cp;
    if (TakeReader(ctx.take.dir()).latest(RecordKind::Checkpoint, &cp) && restore_checkpoint(m, cp, s))
      start = s.frame;
  }
  ctx.progress.stage("simulate", m.frames);
  if (start == 0) {
    ctx.take.append(smoke_frame_record(m, s));
    ctx.events.frame(0);
  }

  long long pressure_iterations = 0;
  double max_div = 0, total = 0;
  if (start > 0)  // the density total when nothing is left to simulate
    for (float x : s.density) total += x;
  for (int f = start + 1; f <= m.frames; ++f) {
    ctx.progress.check_cancelled();
    StepStats st;
    smoke_step(m, s, &st);
    if (const char* field = first_non_finite(s))
      throw std::runtime_error("smoke: NaN in " + std::string(field) + " at frame " + std::to_string(f) +
                               "; try a smaller dt_s or more substeps");
    pressure_iterations += st.pressure_iterations;
    max_div = std::max(max_div, st.max_divergence);
    total = st.total_density;
    if (f % m.write_every == 0) {
      ctx.take.append(smoke_frame_record(m, s));
      ctx.events.frame(f);
    }
    if (f % kCheckpointEveryFrames == 0 && f < m.frames) ctx.take.append(checkpoint_record(s));
    ctx.progress.report(f, total);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const int simulated = m.frames - start;
  const double cell_steps = double(g.cells()) * simulated * m.substeps;
  return {{"frames", m.frames},
          {"cells", g.cells()},
          {"wall_s", wall},
          {"cell_steps_per_s", wall > 0 ? cell_steps / wall : 0.0},
          {"mean_pressure_iterations", double(pressure_iterations) / (std::max(1.0, double(simulated)) * m.substeps)},
          {"resumed_from_frame", start},
          {"max_divergence_per_s", max_div},
          {"total_density", total}};
}

}  // namespace pliant::smoke
