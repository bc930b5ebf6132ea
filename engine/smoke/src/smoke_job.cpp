// Take records and the "smoke" job kind (forward simulation).
#include <omp.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pliant/smoke/smoke.h"
#include "smoke_workspace.h"

namespace pliant::smoke {
namespace {

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
  const SmokeModel m = smoke_compile(ctx.scene);
  if (ctx.threads > 0) omp_set_num_threads(ctx.threads);
  const MacGrid g = model_grid(m);
  const auto t0 = std::chrono::steady_clock::now();

  SmokeState s = smoke_init(m);
  ctx.progress.stage("simulate", m.frames);
  ctx.take.append(smoke_frame_record(m, s));
  ctx.events.frame(0);

  long long pressure_iterations = 0;
  double max_div = 0, total = 0;
  for (int f = 1; f <= m.frames; ++f) {
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
    ctx.progress.report(f, total);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cell_steps = double(g.cells()) * m.frames * m.substeps;
  return {{"frames", m.frames},
          {"cells", g.cells()},
          {"wall_s", wall},
          {"cell_steps_per_s", wall > 0 ? cell_steps / wall : 0.0},
          {"mean_pressure_iterations", double(pressure_iterations) / (double(m.frames) * m.substeps)},
          {"max_divergence_per_s", max_div},
          {"total_density", total}};
}

}  // namespace pliant::smoke
