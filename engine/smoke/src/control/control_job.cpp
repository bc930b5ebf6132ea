// The job for smoke scenes with a "control" section: solve (ADMM or L-BFGS) with a
// checkpoint record per outer iteration (--resume continues from the latest one),
// coarse previews when the solver offers them, then the re-simulated trajectory as
// frames 0..T ("density", cell-centred "velocity" and "force") and the metrics.
//
// Checkpoints: every outer iteration while a checkpoint is <= 4 MB, otherwise at
// most one per 30 s of wall time. Record: kind Checkpoint, index = iteration, fields
//   "state"       the control_state_serialize bytes packed into floats (memcpy,
//                 zero-padded to a multiple of 4; the take stores them bit-exact)
//   "state_bytes" [n / 4096, n % 4096] (two floats, exact for n < 2^36).
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "control_coarse_to_fine.h"
#include "control_forward_model.h"
#include "control_trace.h"
#include "pliant/core/error.h"
#include "pliant/smoke/control.h"
// after control.h: smoke_workspace.h needs SmokeModel declared
#include "../smoke_workspace.h"

namespace pliant::smoke {
namespace {

constexpr size_t kSmallCheckpointBytes = size_t(4) << 20;
constexpr double kCheckpointEvery_s = 30.0;
constexpr size_t kTracePoints = 300;

Record checkpoint_record(const ControlState& s) {
  const std::vector<uint8_t> bytes = control_state_serialize(s);
  Record r;
  r.kind = RecordKind::Checkpoint;
  r.index = s.iteration;
  Field f{"state", {uint32_t((bytes.size() + 3) / 4)}, {}};
  f.data.assign(f.shape[0], 0.0f);
  std::memcpy(f.data.data(), bytes.data(), bytes.size());
  r.fields.push_back(std::move(f));
  r.fields.push_back(Field{"state_bytes", {2}, {float(bytes.size() / 4096), float(bytes.size() % 4096)}});
  return r;
}

ControlState state_from_record(const Record& r) {
  const Field* f = r.find("state");
  const Field* n = r.find("state_bytes");
  if (!f || !n || n->data.size() != 2) throw std::runtime_error("control checkpoint record lacks state/state_bytes");
  const size_t bytes = size_t(n->data[0]) * 4096 + size_t(n->data[1]);
  if (bytes > f->data.size() * 4) throw std::runtime_error("control checkpoint: byte count exceeds the state field");
  std::vector<uint8_t> b(bytes);
  std::memcpy(b.data(), f->data.data(), bytes);
  return control_state_deserialize(b);
}

std::vector<uint32_t> cell_shape(const MacGrid& g) {
  std::vector<uint32_t> s;
  if (g.dim == 3) s.push_back(uint32_t(g.n[2]));
  s.push_back(uint32_t(g.n[1]));
  s.push_back(uint32_t(g.n[0]));
  return s;
}

Field cell_vector_field(const MacGrid& g, const std::string& name, const std::vector<float>& faces) {
  Field v{name, cell_shape(g), {}};
  v.shape.push_back(uint32_t(g.dim));
  v.data.resize(g.cells() * g.dim);
  const size_t nu = g.face_count(0), nv = g.face_count(1);
  cell_centred_velocity(g, FaceVelocity{faces.data(), faces.data() + nu, g.dim == 3 ? faces.data() + nu + nv : nullptr},
                        v.data.data());
  return v;
}

}  // namespace

bool scene_has_control(const Scene& scene) {
  return scene.kind == "smoke" && scene.doc.is_object() && scene.doc.contains("control");
}

int smoke_control_job_frames(const Scene& scene) {
  Scene plain = scene;
  plain.doc.erase("control");
  return smoke_job_frames(plain);
}

nlohmann::json smoke_control_run_job(JobContext& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  const ControlModel m = control_compile(ctx.scene);
  if (ctx.threads > 0) omp_set_num_threads(ctx.threads);
  const MacGrid g = model_grid(m.sim);
  const int T = m.sim.frames;

  ControlState s = control_init(m);
  int resumed_from = -1, resumed_level = -1;
  if (ctx.resume) {
    TakeReader reader(ctx.take.dir());
    Record r;
    if (reader.latest(RecordKind::Checkpoint, &r)) {
      ControlState c;
      try {
        c = state_from_record(r);
      } catch (const std::runtime_error& e) {  // an older checkpoint format, or damage
        throw InputError(ctx.scene.file, "/control",
                         std::string(e.what()) + "; the take cannot be resumed, run without --resume");
      }
      if (!control_state_fits(m, c))
        throw InputError(ctx.scene.file, "/control",
                         "the take's checkpoint was made for a different grid or frame count; run without --resume");
      s = std::move(c);
      resumed_from = s.iteration;
      resumed_level = s.level;
      ctx.events.log("info", "resuming from the checkpoint of iteration " + std::to_string(s.iteration) +
                                 (s.level > 0 ? " of coarse level " + std::to_string(s.level) : std::string()));
    }
  }

  int previews = 0;
  ControlCallbacks cb;
  // A checkpoint per outer iteration while they are small; large ones (an ADMM state
  // at 128^2 x 40 is ~20 MB: 60 of them would make a 1.2 GB take) at most every
  // kCheckpointEvery_s of wall time, so a kill loses at most that much work.
  auto last_checkpoint = std::chrono::steady_clock::now();
  cb.on_iteration = [&](const ControlState& st) {
    Record r = checkpoint_record(st);
    const auto now = std::chrono::steady_clock::now();
    const bool small = r.fields[0].data.size() * 4 <= kSmallCheckpointBytes;
    if (small || std::chrono::duration<double>(now - last_checkpoint).count() >= kCheckpointEvery_s) {
      ctx.take.append(r);
      last_checkpoint = now;
    }
  };
  cb.on_preview = [&](const GridDims& d, const std::vector<std::vector<float>>& density) {
    Record r;
    r.kind = RecordKind::Preview;
    r.index = previews++;
    Field f{"density", {uint32_t(density.size())}, {}};
    if (d.dim == 3) f.shape.push_back(uint32_t(d.n[2]));
    f.shape.push_back(uint32_t(d.n[1]));
    f.shape.push_back(uint32_t(d.n[0]));
    for (const auto& fr : density) f.data.insert(f.data.end(), fr.begin(), fr.end());
    r.fields.push_back(std::move(f));
    ctx.take.append(r);
  };
  const auto ts = std::chrono::steady_clock::now();
  if (m.method == ControlMethod::Lbfgs) control_solve_lbfgs(m, s, ctx.progress, cb);
  else control_solve_admm(m, s, ctx.progress, cb);
  const double solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
  ctx.progress.check_cancelled();

  // Re-simulate the forces with the plain forward model and write the frames.
  ctx.progress.stage("resimulate", T);
  using namespace control_detail;
  ForwardOps ops(m, kControlPressureTolerance);
  const SerialBelow serial(ops.cells());
  TrajectoryD t;
  forward_d(m, ops, to_double(s.force), t);
  const std::vector<float> no_force(ops.faces(), 0.0f);
  for (int i = 0; i <= T; ++i) {
    ctx.progress.check_cancelled();
    Record r;
    r.kind = RecordKind::Frame;
    r.index = i;
    r.time_s = i * m.sim.dt_s;
    Field d{"density", cell_shape(g), std::vector<float>(t.rho[i].begin(), t.rho[i].end())};
    r.fields.push_back(std::move(d));
    r.fields.push_back(cell_vector_field(g, "velocity", std::vector<float>(t.u[i].begin(), t.u[i].end())));
    r.fields.push_back(cell_vector_field(g, "force", i < T ? s.force[i] : no_force));
    ctx.take.append(r);
    ctx.events.frame(i);
    if (i > 0) ctx.progress.report(i);
  }
  const ControlMetrics cm = control_evaluate(m, s.force);
  nlohmann::json kf = nlohmann::json::array();
  for (size_t k = 0; k < cm.keyframes.size(); ++k)
    kf.push_back({{"frame", cm.keyframes[k].frame},
                  {"relative_l2", cm.keyframes[k].relative_l2},
                  {"iou", cm.keyframes[k].iou},
                  {"source", m.keyframes[k].source}});
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {{"method", m.method == ControlMethod::Lbfgs ? "lbfgs" : "admm"},
          {"frames", T},
          {"cells", g.cells()},
          {"iterations", s.iteration},
          {"resumed_from_iteration", resumed_from},
          {"resumed_from_level", resumed_level},
          {"objective", cm.objective},
          {"control_energy", cm.control_energy},
          {"max_divergence_per_s", cm.max_divergence},
          {"iou_min", cm.iou_min},
          {"keyframes", kf},
          {"solve_wall_s", solve_s},
          {"solver_wall_s_total", s.wall_s},
          {"wall_s", wall},
          {"objective_history", s.objective_history},
          // [wall seconds since the solve started, E] at new bests of the scene's grid
          // (coarse levels add time only; <= 300 points, evenly by index).
          {"objective_trace", control_detail::decimate_trace(s.objective_trace, kTracePoints)},
          {"primal_residual_history", s.primal_residual_history},
          {"dual_residual_history", s.dual_residual_history}};
}

}  // namespace pliant::smoke
