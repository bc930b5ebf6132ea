// Job kind "soft": optimize the DMP parameters, then re-simulate and write frames.
#include <chrono>
#include <cmath>

#include "pliant/core/blob_field.h"
#include "pliant/core/byte_stream.h"
#include "pliant/core/crc32.h"
#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"
#include "pliant/soft/soft.h"
#include "pliant/soft/spacetime_state.h"

namespace pliant::soft {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Field vector_field(const std::string& name, const std::vector<double>& v) {
  Field f{name, {uint32_t(v.size())}, {}};
  for (double x : v) f.data.push_back(float(x));
  return f;
}

// The scene a checkpoint's optimizer memory belongs to: a CRC of the document less
// optimizer.iterations (a resume may raise the budget; anything else that changed
// can change the residuals, so the memory is then dropped).
uint32_t scene_tag(const Scene& scene) {
  nlohmann::json d = scene.doc;
  if (d.is_object() && d.contains("optimizer") && d["optimizer"].is_object()) d["optimizer"].erase("iterations");
  const std::string text = d.dump();
  return crc32(text.data(), text.size());
}

}  // namespace

Record soft_frame_record(const SoftModel& m, const SoftState& s, int index, bool with_triangles) {
  Record r;
  r.kind = RecordKind::Frame;
  r.index = index;
  r.time_s = s.time_s;
  Eigen::VectorXd x;
  node_positions(m.character, s, x);
  std::vector<Eigen::Vector3d> verts;
  embed_surface(m.character.lattice, x, verts);
  Field fv{"vertices", {uint32_t(verts.size()), 3}, {}};
  fv.data.reserve(verts.size() * 3);
  for (const auto& v : verts)
    for (int a = 0; a < 3; ++a) fv.data.push_back(float(v[a]));
  r.fields.push_back(std::move(fv));
  if (with_triangles) {
    const auto& tris = m.character.surface.triangles;
    Field ft{"triangles", {uint32_t(tris.size()), 3}, {}};
    for (const auto& t : tris)
      for (int a = 0; a < 3; ++a) ft.data.push_back(float(t[a]));
    r.fields.push_back(std::move(ft));
  }
  const Eigen::Vector3d com = centre_of_mass(m.character, s);
  r.fields.push_back(Field{"com", {3}, {float(com[0]), float(com[1]), float(com[2])}});
  return r;
}

int soft_job_frames(const Scene& scene) {
  // Cheap: frames are read without building the body.
  int frames = 100;
  if (scene.doc.contains("simulation") && scene.doc["simulation"].is_object()) {
    JsonReader s(scene.doc["simulation"], scene.file, "/simulation");
    frames = int(s.integer("frames", 100, 1, 100000));
  }
  return frames;
}

nlohmann::json soft_summary(const Scene& scene) {
  SoftModel m = soft_compile(scene);
  return {{"frames", m.frames},
          {"lattice_cells", m.character.lattice.cells.size()},
          {"lattice_nodes", m.character.lattice.nodes()},
          {"modes", m.character.basis.r()},
          {"surface_vertices", m.character.surface.vertices.size()},
          {"parameters", m.problem.dmp.parameters()}};
}

namespace {

// Navigation: optimize (or take cached) gaits, measure their primitives, plan with
// RRT* and execute; frames carry the usual fields plus "gait" [1].
nlohmann::json run_navigation(JobContext& ctx, SoftModel& m, std::chrono::steady_clock::time_point t0) {
  const NavSettings& nav = m.navigation;
  const char* names[3] = {"forward", "left", "right"};
  std::vector<Gait> gaits;
  nlohmann::json gait_json = nlohmann::json::object(), gait_theta = nlohmann::json::object();
  const auto t_opt = std::chrono::steady_clock::now();
  ctx.progress.stage("gaits", 3);
  // Every checkpoint holds every gait so far: once done its theta (gait_theta_<name>
  // in f32, gait_theta_f64_<name> as doubles in bytes), and for an optimized gait its
  // optimizer state (gait_optimizer_<name>, the "PLSO" blob; one checkpoint per
  // iteration while it runs, without the memory once done). --resume takes the done
  // gaits as they are and continues an unfinished one from its state exactly.
  Record cached;
  if (ctx.resume) {
    TakeReader reader(ctx.take.dir());
    reader.latest(RecordKind::Checkpoint, &cached);
  }
  const uint32_t tag = scene_tag(ctx.scene);
  std::vector<Field> done;  // the gaits done, repeated in every checkpoint
  nlohmann::json gait_optimization = nlohmann::json::object();
  for (int k = 0; k < 3; ++k) {
    Problem pk = m.problem;
    pk.obj = gait_objectives(nav, k);
    pk.obj.w_effort = m.problem.obj.w_effort;
    const int n = pk.dmp.parameters();
    const std::string name = names[k];
    Eigen::VectorXd theta;
    const Field* fc = cached.find("gait_theta_" + name);
    // Full precision; checkpoints written before it existed hold the f32 copy only.
    const Field* fc64 = cached.find("gait_theta_f64_" + name);
    OptimizerState st;
    bool have_state = false;  // st is this gait's optimization
    // The gait's optimizer state in the take, if any (a damaged one is an InputError).
    auto restore = [&] {
      const Field* fo = cached.find("gait_optimizer_" + name);
      if (!fo) return;
      auto fail = [&](const std::string& problem) {
        throw InputError(ctx.scene.file, "/navigation",
                         "take " + ctx.take.dir().string() + ": gait " + name + ": " + problem +
                             "; the take cannot be resumed, run without --resume");
      };
      uint32_t ck_tag = 0;
      try {
        st = optimizer_state_deserialize(field_bytes(*fo), &ck_tag);
      } catch (const std::runtime_error& e) {
        fail(e.what());
      }
      if (st.theta.size() != n)
        fail("its checkpoint has " + std::to_string(st.theta.size()) + " parameters, the scene " +
             std::to_string(n));
      if (ck_tag != tag) st.memory = OptimizerMemory();  // scene changed: as the main job does
      have_state = true;
    };
    const std::vector<uint8_t> b64 = fc64 ? field_bytes(*fc64) : std::vector<uint8_t>();
    if (!nav.cached_theta.empty()) {
      theta = nav.cached_theta[k];
    } else if (k == 2 && mirror_gait(pk, gaits[1].theta, &theta)) {
      // Symmetric body: turning right is the mirror image of turning left.
    } else if (fc64 && b64.size() == size_t(n) * sizeof(double)) {
      theta.resize(n);
      ByteReader(b64, "gait theta").get_values(theta.data(), size_t(n));
      restore();
    } else if (fc && int(fc->data.size()) == n) {
      theta.resize(n);
      for (int i = 0; i < n; ++i) theta[i] = fc->data[i];
      restore();
    } else {
      restore();
      if (!have_state) st.theta = initial_theta(pk);
      have_state = true;
      const ResidualFn rf = [&pk](const Eigen::VectorXd& th) { return residuals(pk, th); };
      optimize(
          rf, m.optimizer, st,
          [&](const OptimizerState& s) {
            Record r;
            r.kind = RecordKind::Checkpoint;
            r.index = k;
            r.fields = done;
            r.fields.push_back(bytes_field("gait_optimizer_" + name, optimizer_state_serialize(s, tag)));
            ctx.take.append(r);
            ctx.progress.check_cancelled();
            return true;
          },
          problem_jacobian(pk, m.optimizer), problem_residual_jacobian(pk, m.optimizer));
      theta = st.theta;
    }
    done.push_back(vector_field("gait_theta_" + name, std::vector<double>(theta.data(), theta.data() + theta.size())));
    std::vector<uint8_t> bytes;
    append_doubles(bytes, theta.data(), size_t(theta.size()));
    done.push_back(bytes_field("gait_theta_f64_" + name, bytes));
    if (have_state) {
      st.memory = OptimizerMemory();  // done: only the record is kept
      done.push_back(bytes_field("gait_optimizer_" + name, optimizer_state_serialize(st, tag)));
      gait_optimization[name] = {{"iterations", st.iteration},
                                 {"rollouts", st.evaluations},
                                 {"objective_history", st.history},
                                 {"step_kinds", st.step_kinds}};
    }
    Record ck;
    ck.kind = RecordKind::Checkpoint;
    ck.index = k;
    ck.fields = done;
    ctx.take.append(ck);
    gaits.push_back(measure_gait(pk, names[k], theta, nav.body_axis));
    const Gait& g = gaits.back();
    gait_json[names[k]] = {{"forward_m", g.forward_m}, {"side_m", g.side_m}, {"yaw_rad", g.yaw_rad}};
    gait_theta[names[k]] = std::vector<double>(theta.data(), theta.data() + theta.size());
    ctx.progress.report(k + 1);
  }
  const double gaits_s = seconds_since(t_opt);
  ctx.progress.stage("navigate", nav.max_frames);
  SoftState s0 = initial_state(m.character, m.problem.start_offset_m, Eigen::Vector3d::Zero(), m.problem.sim.dt_s);
  Record r0 = soft_frame_record(m, s0, 0, true);
  r0.fields.push_back(Field{"gait", {1}, {0.0f}});
  ctx.take.append(r0);
  ctx.events.frame(0);
  int frame = 0;
  const auto t_nav = std::chrono::steady_clock::now();
  NavResult res;
  try {
    res = navigate(m.problem, gaits, nav, [&](const SoftState& s, int gait) {
    ++frame;
    Record r = soft_frame_record(m, s, frame, false);
    r.fields.push_back(Field{"gait", {1}, {float(gait)}});
    ctx.take.append(r);
    ctx.events.frame(frame);
    ctx.progress.report(frame);
    ctx.progress.check_cancelled();
    });
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + "; gait primitives per period: " + gait_json.dump());
  }
  // The planned path, about 50 poses (x, z, yaw).
  std::vector<std::vector<double>> planned;
  const size_t stride = std::max<size_t>(1, res.planned.size() / 50);
  for (size_t i = 0; i < res.planned.size(); i += stride)
    planned.push_back({res.planned[i][0], res.planned[i][1], res.planned[i][2]});
  if (!res.planned.empty()) planned.push_back({res.planned.back()[0], res.planned.back()[1], res.planned.back()[2]});
  return {{"navigation", true},
          {"reached", res.reached},
          {"final_distance_m", res.final_distance_m},
          {"min_clearance_m", res.min_clearance_m},
          {"turning_radius_m", res.turning_radius_m},
          {"gait_sequence", res.gait_sequence},
          {"frames_simulated", frame + 1},
          {"planned_path", planned},
          {"gaits", gait_json},
          {"gait_theta", gait_theta},
          {"gaits_cached", !nav.cached_theta.empty()},
          {"gait_optimization", gait_optimization},
          {"gaits_s", gaits_s},
          {"navigate_s", seconds_since(t_nav)},
          {"wall_s", seconds_since(t0)}};
}

}  // namespace

nlohmann::json soft_run_job(JobContext& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  ctx.progress.stage("compile");
  SoftModel m = soft_compile(ctx.scene);
  soft_bind(m);
  const double compile_s = seconds_since(t0);
  if (m.navigation.enabled) {
    nlohmann::json metrics = run_navigation(ctx, m, t0);
    metrics["compile_s"] = compile_s;
    return metrics;
  }
  const Problem& p = m.problem;

  // Resume from the last checkpoint when asked: its "optimizer" blob (the whole
  // OptimizerState in doubles, optimizer_state.cpp) continues exactly; checkpoints
  // without one (written before it existed) hold theta and the history in f32 and
  // four scalars, and the run continues from those with fresh optimizer memory.
  // A spacetime run also carries its point, weights and report ("spacetime" blob,
  // spacetime_state.cpp); without one (older takes) it restarts from theta's rollout.
  const bool is_spacetime = m.optimizer.kind == OptimizerKind::Spacetime;
  SpacetimeCarry carry;
  SpacetimeReport spacetime;
  OptimizerState st;
  st.theta = initial_theta(p);
  const uint32_t tag = scene_tag(ctx.scene);
  if (ctx.resume) {
    TakeReader reader(ctx.take.dir());
    Record ck;
    const Field* blob = nullptr;
    if (reader.latest(RecordKind::Checkpoint, &ck) && (blob = ck.find("optimizer"))) {
      auto fail = [&](const std::string& problem) {
        throw InputError(ctx.scene.file, "/optimizer",
                         "take " + ctx.take.dir().string() + ": " + problem +
                             "; the take cannot be resumed, run without --resume");
      };
      OptimizerState c;
      uint32_t ck_tag = 0;
      try {
        c = optimizer_state_deserialize(field_bytes(*blob), &ck_tag);
      } catch (const std::runtime_error& e) {
        fail(e.what());
      }
      if (c.theta.size() != st.theta.size())
        fail("its checkpoint was made for a controller of " + std::to_string(c.theta.size()) +
             " parameters, the scene has " + std::to_string(st.theta.size()));
      if (ck_tag != tag) {
        c.memory = OptimizerMemory();
        ctx.events.log("info", "the scene changed since the checkpoint (beyond optimizer.iterations): the "
                               "optimizer continues from its theta with fresh memory");
      }
      st = std::move(c);
      const Field* sb = is_spacetime ? ck.find("spacetime") : nullptr;
      if (sb) {
        SpacetimeCheckpoint sc;
        uint32_t sc_tag = 0;
        try {
          sc = spacetime_checkpoint_deserialize(field_bytes(*sb), &sc_tag);
        } catch (const std::runtime_error& e) {
          fail(e.what());
        }
        const SpacetimeVars& v = sc.carry.vars;
        const int ns = spacetime_state_size(p), modes = p.dmp.modes;
        if (sc.iteration != st.iteration || v.theta.size() != st.theta.size() || int(v.frames.size()) != p.frames ||
            v.act.rows() != modes || v.frames.front().q.size() != ns - 6 || sc.carry.res.size() <= p.frames * (ns + modes))
          fail("its spacetime state does not fit its optimizer state or the scene");
        if (sc_tag == tag) {  // a changed scene: continue from theta's rollout, as the memory is dropped
          carry = std::move(sc.carry);
          spacetime = std::move(sc.report);
        }
      }
    } else {
      const Field* th = ck.find("theta");
      const Field* hist = ck.find("objective_history");
      const Field* state = ck.find("optimizer_state");
      if (th && hist && state && int(th->data.size()) == st.theta.size() && state->data.size() == 4) {
        for (int i = 0; i < st.theta.size(); ++i) st.theta[i] = th->data[i];
        for (float v : hist->data) st.history.push_back(v);
        st.iteration = int(state->data[0]);
        st.lambda = state->data[1];
        st.in_lbfgs = state->data[2] != 0;
        st.evaluations = int(state->data[3]);
      }
    }
  }
  const auto t_opt = std::chrono::steady_clock::now();
  ctx.progress.stage("optimize", m.optimizer.max_iterations);
  const IterationFn checkpoint = [&](const OptimizerState& s) {
    Record ck;
    ck.kind = RecordKind::Checkpoint;
    ck.index = s.iteration;
    ck.fields.push_back(vector_field("theta", std::vector<double>(s.theta.data(), s.theta.data() + s.theta.size())));
    ck.fields.push_back(vector_field("objective_history", s.history));
    ck.fields.push_back(vector_field(
        "optimizer_state", {double(s.iteration), s.lambda, s.in_lbfgs ? 1.0 : 0.0, double(s.evaluations)}));
    // The f32 fields above are for older readers; this one resumes (and gives the editor theta).
    ck.fields.push_back(bytes_field("optimizer", optimizer_state_serialize(s, tag)));
    if (is_spacetime)
      ck.fields.push_back(bytes_field("spacetime", spacetime_checkpoint_serialize({s.iteration, carry, spacetime}, tag)));
    ctx.take.append(ck);
    ctx.progress.report(s.iteration, s.objective);
    ctx.progress.check_cancelled();
    return true;
  };
  if (is_spacetime)
    spacetime_optimize(p, m.spacetime, st, checkpoint, &spacetime, &carry);
  else
    soft_optimize(m, st, checkpoint);
  const double optimize_s = seconds_since(t_opt);

  // Re-simulate the whole take under the optimized controller.
  ctx.progress.stage("playback", m.frames);
  SoftPlayback pb = soft_playback_start(m, st.theta);
  const SoftState& s = pb.state;
  const Eigen::Vector3d com0 = centre_of_mass(m.character, s);
  ctx.take.append(soft_frame_record(m, s, 0, true));
  ctx.events.frame(0);
  double sim_s = 0, max_gain = 0, max_tilt = 0;
  for (int f = 1; f < m.frames; ++f) {
    const auto ts = std::chrono::steady_clock::now();
    soft_playback_step(m, pb);
    sim_s += seconds_since(ts);
    max_gain = std::max(max_gain, centre_of_mass(m.character, s)[1] - com0[1]);
    max_tilt = std::max(max_tilt, tilt_from_up_deg(s, p.obj.upright_axis));
    ctx.take.append(soft_frame_record(m, s, f, false));
    ctx.events.frame(f);
    ctx.progress.report(f + 1);
    ctx.progress.check_cancelled();
  }
  const Eigen::Vector3d disp = centre_of_mass(m.character, s) - com0;
  const double horizontal = std::hypot(disp[0], disp[2]);
  const double sim_time = (m.frames - 1) * p.sim.dt_s;
  nlohmann::json metrics = {
      {"objective_history", st.history},
      {"objective_initial", st.history.front()},
      {"objective_final", st.history.back()},
      {"iterations", st.iteration},
      {"rollouts", st.evaluations},
      {"optimizer", optimizer_name(m.optimizer.kind)},
      {"step_kinds", st.step_kinds},
      {"distance_m", horizontal},
      {"displacement_m", {disp[0], disp[1], disp[2]}},
      {"distance_per_s", sim_time > 0 ? horizontal / sim_time : 0.0},
      {"max_height_gain_m", max_gain},
      // The upright term's body axis (+y unless set) from +y: a body that lands on its
      // side ends near 90, a fish rolled belly-up near 180.
      {"final_tilt_deg", tilt_from_up_deg(s, p.obj.upright_axis)},
      {"max_tilt_deg", max_tilt},
      {"playback_fps", sim_s > 0 ? (m.frames - 1) / sim_s : 0.0},
      {"compile_s", compile_s},
      {"optimize_s", optimize_s},
      {"wall_s", seconds_since(t0)},
      {"lattice_cells", m.character.lattice.cells.size()},
      {"lattice_nodes", m.character.lattice.nodes()},
      {"pieces_dropped", m.character.lattice.pieces_dropped},
      {"welded_vertices", m.repair.welded_vertices},
      {"dropped_triangles", m.repair.dropped_triangles},
      {"modes", m.character.basis.r()},
      {"dmp_parameters", p.dmp.parameters()},
      {"cubature_cells", m.cubature.cells},
      {"cubature_kept_fraction", m.cubature.kept_fraction}};
  if (is_spacetime)
    metrics["spacetime"] = {{"merit", spacetime.merit},
                            {"physics_violation_m", spacetime.physics_violation},
                            {"dmp_mismatch_m", spacetime.dmp_mismatch},
                            {"dmp_weight", spacetime.w_dmp},
                            {"resimulated_objective", spacetime.resimulated},
                            {"steps", spacetime.steps}};
  return metrics;
}

}  // namespace pliant::soft
