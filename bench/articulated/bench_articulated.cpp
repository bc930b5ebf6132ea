// bench_articulated: PBAD (2nd/3rd order) and our Euler/RK4 against MuJoCo 2.2.2's
// Euler, RK4 and implicit integrators on the same MJCF chains, in one process
// (BENCHMARKS.md, "Articulated bodies (PBAD)"). One JSON object per case on stdout;
// all of them in bench/results/articulated.json.
//   chain_swing: chain released horizontally (whips when it swings down);
//   chain_tilt:  chain released 30 degrees from vertical (smooth swing);
//   energy_drift = max |E(t) - E0| / (potential energy range, horizontal to hanging).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <tuple>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unistd.h>
#include <string>
#include <vector>

#include "pliant/articulated/articulated.h"
#include "pliant/articulated/io.h"
#include "pliant/articulated/mpc.h"
#include "pliant/articulated/sim.h"
#include "../bench_machine.h"
#ifdef PLIANT_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

using namespace pliant::articulated;
using Clock = std::chrono::steady_clock;

namespace {

nlohmann::json g_results = nlohmann::json::array();
std::string g_machine;

void emit(nlohmann::json j) {
  j["machine"] = g_machine;
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
  g_results.push_back(std::move(j));
}


struct Outcome {
  double drift = 0, wall = 0, sim_time = 0, iterations = 0;
  int steps = 0;
  bool stable = true;
};

double chain_range(const Model& m, int links, double len) {
  double mass = 0;
  for (const Body& b : m.bodies) mass += b.mass;
  return mass / links * 9.81 * len * links * links / 2.0;
}

State chain_initial(const Model& m, bool tilt) {
  State s = state_init(m);
  if (tilt) s.qpos[0] = 1.3;  // hinge y of the root: 30 degrees from vertical
  s.qvel[1] = tilt ? 0.3 : 0.5;
  return s;
}

double thread_cpu_s() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

SimOptions contact_free_options(Integrator integ, double dt) {
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  o.contact.enabled = false;
  return o;
}

Outcome run_ours(const Model& m, Integrator integ, double dt, double duration, const State& init,
                 double range) {
  const SimOptions o = contact_free_options(integ, dt);
  State s = init;
  SimWorkspace ws;
  Outcome out;
  const double e0 = state_energy(m, o, s, ws).total;
  const int n = static_cast<int>(std::llround(duration / dt));
  for (int i = 0; i < n; ++i) {
    const double t0 = thread_cpu_s();
    StepInfo info;
    const bool ok = sim_step(m, o, s, ws, &info);
    out.wall += thread_cpu_s() - t0;
    out.iterations += info.iterations;
    ++out.steps;
    const double e = ok ? state_energy(m, o, s, ws).total : NAN;
    const double d = std::abs(e - e0) / range;
    if (!std::isfinite(d) || d > 2) {
      out.stable = false;
      out.drift = std::isfinite(d) ? d : INFINITY;
      break;
    }
    out.drift = std::max(out.drift, d);
  }
  out.sim_time = out.steps * dt;
  out.iterations /= std::max(1, out.steps);
  return out;
}

double load_average() {
  double l[1] = {0};
  return getloadavg(l, 1) == 1 ? l[0] : -1;
}

struct Timing {
  double cpu = 0, wall = 0;
};

// Stepping only (the matched re-timing): duration / dt steps from init.
Timing time_ours(const Model& m, Integrator integ, double dt, double duration, const State& init) {
  const SimOptions o = contact_free_options(integ, dt);
  State s = init;
  SimWorkspace ws;
  const int n = static_cast<int>(std::llround(duration / dt));
  const double c0 = thread_cpu_s();
  const auto t0 = Clock::now();
  for (int i = 0; i < n; ++i) sim_step(m, o, s, ws);
  return {thread_cpu_s() - c0, std::chrono::duration<double>(Clock::now() - t0).count()};
}

#ifdef PLIANT_HAVE_MUJOCO
mjModel* mujoco_load(const std::string& xml, std::string* error) {
  const auto path = std::filesystem::temp_directory_path() / ("bench_art_" + std::to_string(::getpid()) + ".xml");
  std::ofstream(path) << xml;
  char err[1000] = "";
  mjModel* mm = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  std::filesystem::remove(path);
  if (!mm) *error = err;
  return mm;
}

Timing time_mujoco(mjModel* mm, const Model& m, int integrator, double dt, double duration, const State& init) {
  mm->opt.integrator = integrator;
  mm->opt.timestep = dt;
  mjData* d = mj_makeData(mm);
  for (int i = 0; i < m.nq; ++i) d->qpos[i] = init.qpos[i];
  for (int i = 0; i < m.nv; ++i) d->qvel[i] = init.qvel[i];
  const int n = static_cast<int>(std::llround(duration / dt));
  const double c0 = thread_cpu_s();
  const auto t0 = Clock::now();
  for (int i = 0; i < n; ++i) mj_step(mm, d);
  const Timing t{thread_cpu_s() - c0, std::chrono::duration<double>(Clock::now() - t0).count()};
  mj_deleteData(d);
  return t;
}

Outcome run_mujoco(mjModel* mm, const Model& m, int integrator, double dt, double duration,
                   const State& init, double range) {
  mm->opt.integrator = integrator;
  mm->opt.timestep = dt;
  mjData* d = mj_makeData(mm);
  for (int i = 0; i < m.nq; ++i) d->qpos[i] = init.qpos[i];
  for (int i = 0; i < m.nv; ++i) d->qvel[i] = init.qvel[i];
  SimOptions o;
  o.contact.enabled = false;
  SimWorkspace ws;
  State s = init;
  Outcome out;
  const double e0 = state_energy(m, o, s, ws).total;
  const int n = static_cast<int>(std::llround(duration / dt));
  for (int i = 0; i < n; ++i) {
    const double t0 = thread_cpu_s();
    mj_step(mm, d);
    out.wall += thread_cpu_s() - t0;
    ++out.steps;
    for (int k = 0; k < m.nq; ++k) s.qpos[k] = d->qpos[k];
    for (int k = 0; k < m.nv; ++k) s.qvel[k] = d->qvel[k];
    const double e = s.qpos.allFinite() && s.qvel.allFinite() ? state_energy(m, o, s, ws).total : NAN;
    const double dd = std::abs(e - e0) / range;
    if (!std::isfinite(dd) || dd > 2 || d->warning[mjWARN_BADQACC].number > 0) {
      out.stable = false;
      out.drift = std::isfinite(dd) ? dd : INFINITY;
      break;
    }
    out.drift = std::max(out.drift, dd);
  }
  out.sim_time = out.steps * dt;
  mj_deleteData(d);
  return out;
}
#endif

nlohmann::json row(const std::string& c, const std::string& method, int links, double dt, const Outcome& o) {
  nlohmann::json j = {{"case", c},
                      {"method", method},
                      {"links", links},
                      {"dt", dt},
                      {"energy_drift", std::isfinite(o.drift) ? nlohmann::json(o.drift) : nlohmann::json("inf")},
                      {"stable", o.stable},
                      {"wall_per_sim_s", o.sim_time > 0 ? o.wall / o.sim_time : 0.0},  // thread CPU time
                      {"wall_per_step_us", o.steps > 0 ? 1e6 * o.wall / o.steps : 0.0},
                      {"simulated_s", o.sim_time}};
  if (method.rfind("pbad", 0) == 0) j["lm_iterations_per_step"] = o.iterations;
  return j;
}

// Box on a plane tilted by `slope` (optionally sliding at v0 along x).
std::string box_xml(double slope, double mu) {
  const Quat q(Eigen::AngleAxisd(slope, Vec3::UnitY()));
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "<mujoco><option timestep=\"0.01\"/><worldbody><geom type=\"plane\" size=\"50 50 0.1\" quat=\"%.17g %.17g %.17g %.17g\" friction=\"%g 0.005 0.0001\"/>"
                "<body name=\"box\" pos=\"0 0 0.1\"><freejoint/><geom type=\"box\" size=\"0.1 0.1 0.1\" mass=\"1\" friction=\"%g 0.005 0.0001\"/></body>"
                "</worldbody></mujoco>",
                q.w(), q.x(), q.y(), q.z(), mu, mu);
  return buf;
}

State box_state(const Model& m, double slope, double stiffness, double v0) {
  const Quat q(Eigen::AngleAxisd(slope, Vec3::UnitY()));
  const Vec3 n = q * Vec3::UnitZ();
  State s = state_init(m);
  s.qpos.head<3>() = n * (0.1 - 9.81 * std::cos(slope) / (4 * stiffness));
  s.qpos.segment<4>(3) << q.w(), q.x(), q.y(), q.z();
  s.qvel[0] = v0;
  return s;
}

void contact_cases(bool quick) {
  const double mu = 0.5, slope = 20 * M_PI / 180, dt = 0.01;
  // Slope creep over 5 s.
  {
    const std::string xml = box_xml(slope, mu);
    const Model m = model_from_mjcf(xml, "box.xml");
    for (Integrator integ : {Integrator::Pbad3, Integrator::Pbad2, Integrator::Pbad4}) {
      SimOptions o;
      o.integrator = integ;
      o.dt = dt;
      o.contact.mu = mu;
      State s = box_state(m, slope, o.contact.stiffness, 0);
      SimWorkspace ws;
      const Vec3 p0 = s.qpos.head<3>();
      const auto t0 = Clock::now();
      for (int i = 0; i < 500; ++i) sim_step(m, o, s, ws);
      const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
      emit({{"case", "slope_creep"}, {"method", integrator_name(integ)}, {"dt", dt}, {"slope_deg", 20}, {"mu", mu},
            {"creep_m", (s.qpos.head<3>() - p0).norm()}, {"wall_s", wall}});
    }
#ifdef PLIANT_HAVE_MUJOCO
    std::string err;
    mjModel* mm = mujoco_load(xml, &err);
    for (auto [name, integ, step] : {std::tuple{"mujoco_euler", (int)mjINT_EULER, 0.01},
                                     std::tuple{"mujoco_euler", (int)mjINT_EULER, 0.002},
                                     std::tuple{"mujoco_implicit", (int)mjINT_IMPLICIT, 0.01}}) {
      mm->opt.integrator = integ;
      mm->opt.timestep = step;
      mjData* d = mj_makeData(mm);
      const State s0 = box_state(m, slope, 1e5, 0);
      for (int i = 0; i < 7; ++i) d->qpos[i] = s0.qpos[i];
      // Let MuJoCo's soft contact settle for 0.5 s, then measure 5 s of creep.
      const int settle = static_cast<int>(0.5 / step), n = static_cast<int>(5.0 / step);
      for (int i = 0; i < settle; ++i) mj_step(mm, d);
      const Vec3 p0(d->qpos[0], d->qpos[1], d->qpos[2]);
      for (int i = 0; i < n; ++i) mj_step(mm, d);
      emit({{"case", "slope_creep"}, {"method", name}, {"dt", step}, {"slope_deg", 20}, {"mu", mu},
            {"creep_m", (Vec3(d->qpos[0], d->qpos[1], d->qpos[2]) - p0).norm()},
            {"note", "MuJoCo defaults (pyramidal cone, default solref/solimp), after 0.5 s settling"}});
      mj_deleteData(d);
    }
    mj_deleteModel(mm);
#endif
  }
  // Box sliding v0 = 2 m/s: analytic stop distance 0.408 m.
  {
    const std::string xml = box_xml(0, mu);
    const Model m = model_from_mjcf(xml, "box.xml");
    const double analytic = 4.0 / (2 * mu * 9.81);
    for (Integrator integ : {Integrator::Pbad3, Integrator::Pbad2, Integrator::Pbad4}) {
      SimOptions o;
      o.integrator = integ;
      o.dt = dt;
      o.contact.mu = mu;
      State s = box_state(m, 0, o.contact.stiffness, 2.0);
      SimWorkspace ws;
      const double x0 = s.qpos[0];
      for (int i = 0; i < 150; ++i) sim_step(m, o, s, ws);
      emit({{"case", "box_slide"}, {"method", integrator_name(integ)}, {"dt", dt}, {"stop_m", s.qpos[0] - x0},
            {"analytic_m", analytic}, {"error_rel", (s.qpos[0] - x0) / analytic - 1}});
    }
#ifdef PLIANT_HAVE_MUJOCO
    std::string err;
    mjModel* mm = mujoco_load(xml, &err);
    mm->opt.timestep = dt;
    mjData* d = mj_makeData(mm);
    const State s0 = box_state(m, 0, 1e5, 0);
    for (int i = 0; i < 7; ++i) d->qpos[i] = s0.qpos[i];
    for (int i = 0; i < 50; ++i) mj_step(mm, d);  // settle
    const double x0 = d->qpos[0];
    d->qvel[0] = 2.0;
    for (int i = 0; i < 150; ++i) mj_step(mm, d);
    emit({{"case", "box_slide"}, {"method", "mujoco_euler"}, {"dt", dt}, {"stop_m", d->qpos[0] - x0},
          {"analytic_m", analytic}, {"error_rel", (d->qpos[0] - x0) / analytic - 1}});
    mj_deleteData(d);
    mj_deleteModel(mm);
#endif
  }
  (void)quick;
}

void batched_case(bool quick) {
  const Model m = model_from_mjcf(chain_mjcf(40), "chain.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.enabled = false;
  const int trajectories = 100, steps = 10;
  std::vector<double> walls;
  for (int threads : {1, omp_get_num_procs()}) {
    double best = 1e300;
    int passes = 0;
    for (int rep = 0; rep < (quick ? 1 : 3); ++rep) {
      std::vector<State> states(trajectories);
      for (int t = 0; t < trajectories; ++t) {
        states[t] = chain_initial(m, true);
        states[t].qvel[1] = 0.3 + 0.01 * t;  // every trajectory different
      }
      const auto t0 = Clock::now();
      passes = batch_rollout(m, o, states, steps, threads);
      best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
    }
    walls.push_back(best);
    emit({{"case", "batched_rollouts"}, {"method", "pbad3"}, {"links", 40}, {"dt", o.dt},
          {"trajectories", trajectories}, {"steps", steps}, {"threads", threads}, {"wall_s", best},
          {"passes", passes}, {"trajectory_steps_per_s", trajectories * steps / best},
          {"speedup_vs_1_thread", walls.front() / best}});
  }
}

// Cost per step from 10 to 100 links at dt 0.05 (issue 6: within 1.5x of linear):
// thread CPU time of 10 s of stepping, fastest of 3 repeats.
void cost_per_step_case() {
  // pbad4 only on the smooth swing: it does not survive the 40/100-link whip (README).
  for (auto [chain_case, integ] : {std::pair{"chain_tilt", Integrator::Pbad3}, std::pair{"chain_swing", Integrator::Pbad3},
                                   std::pair{"chain_tilt", Integrator::Pbad4}}) {
    const bool tilt = std::string(chain_case) == "chain_tilt";
    double per_step[2] = {0, 0}, iterations[2] = {0, 0};
    const int links[2] = {10, 100};
    for (int k = 0; k < 2; ++k) {
      const Model m = model_from_mjcf(chain_mjcf(links[k]), "chain.xml");
      const State init = chain_initial(m, tilt);
      double best = 1e300;
      for (int rep = 0; rep < 3; ++rep) best = std::min(best, time_ours(m, integ, 0.05, 10.0, init).cpu);
      per_step[k] = best / 200;
      iterations[k] = run_ours(m, integ, 0.05, 10.0, init, chain_range(m, links[k], 0.1)).iterations;
    }
    emit({{"case", "cost_per_step"}, {"chain", chain_case}, {"method", integrator_name(integ)}, {"dt", 0.05},
          {"us_per_step_10", 1e6 * per_step[0]}, {"us_per_step_100", 1e6 * per_step[1]},
          {"lm_iterations_10", iterations[0]}, {"lm_iterations_100", iterations[1]},
          {"ratio_vs_linear", per_step[1] / per_step[0] / 10}, {"load_average", load_average()},
          {"timing", "thread CPU time, fastest of 3 runs of 200 steps"}});
  }
}

// `steps` steps from `initial`, the fastest of `reps` runs in thread CPU time; the
// last run's LM iteration and contact statistics (sums over the steps) and its end.
struct TimedRollout {
  double cpu_s = 1e300;
  double iterations = 0, max_iterations = 0;
  double contacts = 0, pair_contacts = 0, max_pair_depth = 0;
  State final;
};
TimedRollout timed_rollout(const Model& m, const SimOptions& o, const State& initial, int steps, int reps) {
  TimedRollout t;
  for (int rep = 0; rep < reps; ++rep) {
    State s = initial;
    SimWorkspace ws;
    double cpu = 0;
    t.iterations = t.max_iterations = t.contacts = t.pair_contacts = t.max_pair_depth = 0;
    for (int i = 0; i < steps; ++i) {
      StepInfo info;
      const double t0 = thread_cpu_s();
      sim_step(m, o, s, ws, &info);
      cpu += thread_cpu_s() - t0;
      t.iterations += info.iterations;
      t.max_iterations = std::max<double>(t.max_iterations, info.iterations);
      t.contacts += ws.contacts.size();
      t.pair_contacts += ws.pair_contacts.size();
      for (const PairContact& c : ws.pair_contacts) t.max_pair_depth = std::max(t.max_pair_depth, c.depth);
    }
    t.cpu_s = std::min(t.cpu_s, cpu);
    t.final = s;
  }
  return t;
}

// One contact evaluation's nearest-triangle queries (points in the mesh's frame)
// through the tree and by the brute-force scan: seconds per evaluation, fastest of
// 3 x 20; `sink` sums the distances so neither loop is optimised away.
struct MeshQuery {
  const MeshShape* mesh;
  const MeshBvh* bvh;
  Vec3 p;
};
void time_tree_vs_scan(const std::vector<MeshQuery>& queries, double* tree, double* scan, double* sink) {
  *tree = *scan = 1e300;
  for (int rep = 0; rep < 3; ++rep) {
    Vec3 n;
    double t0 = thread_cpu_s();
    for (int r = 0; r < 20; ++r)
      for (const MeshQuery& q : queries) *sink += mesh_signed_distance(*q.mesh, *q.bvh, q.p, &n);
    *tree = std::min(*tree, (thread_cpu_s() - t0) / 20);
    t0 = thread_cpu_s();
    for (int r = 0; r < 20; ++r)
      for (const MeshQuery& q : queries) *sink += mesh_signed_distance(*q.mesh, q.p, &n);
    *scan = std::min(*scan, (thread_cpu_s() - t0) / 20);
  }
}

// Body-body contact (assets/scenes/articulated_pile.json: 3 boxes, 2 capsules and a
// ball dropped on each other and the ground, pbad3, dt 0.01, 3 s): cost per step and LM
// iterations with self-collision, and the same bodies without it (they fall through
// each other onto the ground). Thread CPU time, fastest of 3 runs.
void pile_case(bool quick) {
  const std::string path = std::string(PLIANT_RESULTS_DIR) + "/../../assets/scenes/articulated_pile.json";
  const ArticulatedScene a = articulated_compile(pliant::load_scene(path));
  double per_step[2] = {0, 0};
  for (int on = 1; on >= 0; --on) {
    SimOptions o = a.options;
    o.contact.self_collision = on;
    const TimedRollout t = timed_rollout(a.model, o, a.initial, a.steps, quick ? 1 : 3);
    const double best = t.cpu_s, iterations = t.iterations, max_iterations = t.max_iterations;
    const double max_depth = on ? t.max_pair_depth : 0, contacts = on ? t.pair_contacts : 0;
    per_step[on] = best / a.steps;
    emit({{"case", "pile"}, {"method", "pbad3"}, {"self_collision", bool(on)}, {"dt", a.options.dt},
          {"bodies", a.model.bodies.size() - 1}, {"steps", a.steps}, {"us_per_step", 1e6 * per_step[on]},
          {"lm_iterations", iterations / a.steps}, {"lm_iterations_max", max_iterations},
          {"pair_contacts_per_step", contacts / a.steps}, {"max_pair_depth_m", max_depth},
          {"cost_vs_without", on ? nlohmann::json(nullptr) : nlohmann::json(per_step[1] / per_step[0])},
          {"load_average", load_average()}, {"timing", "thread CPU time, fastest of 3 runs (1 in --quick)"}});
  }
}

// Mesh-mesh contact (assets/scenes/articulated_mesh_stack.json: three 320-triangle
// pebbles dropped on a fixed 192-triangle slab and on each other, pbad3, dt 0.01, 2 s):
// cost per step, LM iterations, contacts; then, at the final state, the nearest-
// triangle queries of one contact evaluation (samples inside the other mesh's box)
// timed through the tree and by the brute-force scan. Thread CPU time, fastest of 3.
void mesh_mesh_case(bool quick) {
  const std::string path = std::string(PLIANT_RESULTS_DIR) + "/../../assets/scenes/articulated_mesh_stack.json";
  const ArticulatedScene a = articulated_compile(pliant::load_scene(path));
  const TimedRollout t = timed_rollout(a.model, a.options, a.initial, a.steps, quick ? 1 : 3);
  const double best = t.cpu_s, iterations = t.iterations, max_iterations = t.max_iterations;
  const double contacts = t.pair_contacts, max_depth = t.max_pair_depth;
  const State& s = t.final;
  // The final state's queries: each mesh's samples inside the other's bounding box.
  Kinematics k;
  kinematics(a.model, s.qpos, &k);
  std::vector<MeshQuery> queries;
  const std::vector<GeomPair> pairs = contact_geom_pairs(a.model);
  for (const GeomPair& pr : pairs) {
    if (!pr.mesh_a || !pr.mesh_b) continue;
    for (int side = 0; side < 2; ++side) {
      const Geom& gs = a.model.geoms[side ? pr.b : pr.a];
      const Geom& gm = a.model.geoms[side ? pr.a : pr.b];
      const MeshCollider& from = side ? *pr.mesh_b : *pr.mesh_a;
      const MeshCollider& to = side ? *pr.mesh_a : *pr.mesh_b;
      const Mat3 rs = k.xmat[gs.body] * gs.quat.toRotationMatrix(), rm = k.xmat[gm.body] * gm.quat.toRotationMatrix();
      const Vec3 cs = k.xpos[gs.body] + k.xmat[gs.body] * gs.pos, cm = k.xpos[gm.body] + k.xmat[gm.body] * gm.pos;
      for (const Vec3& v : from.samples) {
        const Vec3 p = rm.transpose() * (cs + rs * v - cm);
        if (((to.bvh.nodes[0].lo - p).cwiseMax(p - to.bvh.nodes[0].hi).array() < 0).all())
          queries.push_back({gm.mesh.get(), &to.bvh, p});
      }
    }
  }
  double tree, scan, sink = 0;
  time_tree_vs_scan(queries, &tree, &scan, &sink);
  emit({{"case", "mesh_mesh"}, {"method", "pbad3"}, {"dt", a.options.dt}, {"bodies", a.model.bodies.size() - 1},
        {"steps", a.steps}, {"us_per_step", 1e6 * best / a.steps}, {"lm_iterations", iterations / a.steps},
        {"lm_iterations_max", max_iterations}, {"pair_contacts_per_step", contacts / a.steps},
        {"max_pair_depth_m", max_depth}, {"final_queries_per_evaluation", queries.size()},
        {"final_xyz_m", std::vector<double>{s.qpos[0], s.qpos[1], s.qpos[2], s.qpos[7], s.qpos[8], s.qpos[9], s.qpos[14], s.qpos[15], s.qpos[16]}},  // the pebbles' centres
        {"query_us_tree", 1e6 * tree}, {"query_us_scan", 1e6 * scan}, {"checksum", sink},
        {"load_average", load_average()},
        {"timing", "thread CPU time, fastest of 3 runs (1 in --quick); queries: one evaluation's, fastest of 3 x 20"}});
}

// Static mesh obstacle (robotics environments load as static meshes): a closed
// heightfield block, n x n cells over 1 m x 1 m (top 2n^2 triangles, flat bottom
// 2n^2, sides 8n: 6720 triangles at n 40), written to a temporary OBJ, with three
// boxes, two balls and a capsule dropped on it; pbad3, dt 0.01, 1 s, Coulomb mu 0.6.
// Cost per step and LM iterations; then, at the final state, every contact point's
// distance to the terrain timed through the tree and by the scan. Thread CPU time,
// fastest of 3 (1 in --quick).
double terrain_height(double x, double y) { return 0.02 * std::sin(6 * x) * std::cos(5 * y); }

std::string write_terrain_obj(int n) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("pliant_bench_terrain_" + std::to_string(::getpid()) + ".obj")).string();
  std::ofstream out(path);
  const auto at = [n](int i) { return -0.5 + double(i) / n; };
  // Vertices: top grid (n+1)^2, then bottom grid (n+1)^2 at z = -0.2 (1-based ids).
  for (int layer = 0; layer < 2; ++layer)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        out << "v " << at(i) << " " << at(j) << " " << (layer ? -0.2 : terrain_height(at(i), at(j))) << "\n";
  const auto id = [n](int layer, int i, int j) { return 1 + layer * (n + 1) * (n + 1) + j * (n + 1) + i; };
  const auto quad = [&](int a, int b, int c, int d) {  // counter-clockwise from outside
    out << "f " << a << " " << b << " " << c << "\nf " << a << " " << c << " " << d << "\n";
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      quad(id(0, i, j), id(0, i + 1, j), id(0, i + 1, j + 1), id(0, i, j + 1));  // top, normal +z
      quad(id(1, i, j), id(1, i, j + 1), id(1, i + 1, j + 1), id(1, i + 1, j));  // bottom, -z
    }
  for (int i = 0; i < n; ++i) {
    quad(id(1, i, 0), id(1, i + 1, 0), id(0, i + 1, 0), id(0, i, 0));          // y = -0.5
    quad(id(1, i + 1, n), id(1, i, n), id(0, i, n), id(0, i + 1, n));          // y = +0.5
    quad(id(1, 0, i + 1), id(1, 0, i), id(0, 0, i), id(0, 0, i + 1));          // x = -0.5
    quad(id(1, n, i), id(1, n, i + 1), id(0, n, i + 1), id(0, n, i));          // x = +0.5
  }
  return path;
}

void mesh_terrain_case(bool quick) {
  const int n = 40;
  const std::string obj = write_terrain_obj(n);
  std::string bodies;
  const double xy[6][2] = {{-0.25, -0.2}, {0.05, -0.25}, {0.3, 0.1}, {-0.2, 0.25}, {0.1, 0.2}, {-0.05, 0.0}};
  for (int b = 0; b < 6; ++b) {
    const double x = xy[b][0], y = xy[b][1], z = terrain_height(x, y) + 0.07;
    const std::string geom = b < 3 ? "<geom type=\"box\" size=\"0.04 0.03 0.025\" mass=\"0.5\"/>"
                             : b < 5 ? "<geom type=\"sphere\" size=\"0.03\" mass=\"0.3\"/>"
                                     : "<geom type=\"capsule\" size=\"0.02 0.06\" euler=\"0 90 20\" mass=\"0.3\"/>";
    bodies += "<body pos=\"" + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\"><freejoint/>" +
              geom + "</body>";
  }
  const Model m = model_from_mjcf("<mujoco><asset><mesh name=\"terrain\" file=\"" + obj +
                                      "\"/></asset><worldbody><geom type=\"mesh\" mesh=\"terrain\"/>" + bodies +
                                      "</worldbody></mujoco>",
                                  "terrain.xml");
  std::filesystem::remove(obj);
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.mu = 0.6;
  const int steps = 100;
  const TimedRollout t = timed_rollout(m, o, state_init(m), steps, quick ? 1 : 3);
  const double best = t.cpu_s, iterations = t.iterations, contacts = t.contacts;
  const State& s = t.final;
  // One energy evaluation's distance queries at the final state: every contact point
  // against the terrain (mesh frame = world here), tree and scan.
  Kinematics k;
  kinematics(m, s.qpos, &k);
  const MeshShape& mesh = *m.geoms[0].mesh;
  const MeshBvh bvh = mesh_bvh(mesh);
  std::vector<MeshQuery> queries;
  for (const ContactPoint& cp : contact_points(m))
    queries.push_back({&mesh, &bvh, k.xpos[cp.body] + k.xmat[cp.body] * cp.local});
  double tree, scan, sink = 0;
  time_tree_vs_scan(queries, &tree, &scan, &sink);
  std::vector<double> z;
  for (int b = 0; b < 6; ++b) z.push_back(s.qpos[7 * b + 2]);
  emit({{"case", "mesh_terrain"}, {"method", "pbad3"}, {"dt", o.dt}, {"triangles", mesh.triangles.size()},
        {"bodies", m.bodies.size() - 1}, {"steps", steps}, {"us_per_step", 1e6 * best / steps},
        {"lm_iterations", iterations / steps}, {"contacts_per_step", contacts / steps}, {"final_z_m", z},
        {"queries_per_evaluation", queries.size()}, {"query_us_tree", 1e6 * tree}, {"query_us_scan", 1e6 * scan},
        {"checksum", sink}, {"load_average", load_average()},
        {"timing", "thread CPU time, fastest of 3 runs (1 in --quick); queries: one evaluation's, fastest of 3 x 20"}});
}

// Static box corners and spheres against moving meshes (mesh_feature_contacts): two
// 320-triangle pebbles (assets/models/pebble.obj), one dropped on a tripod of three
// 1 cm static spheres, one on a static box standing on its corner, a plane below;
// pbad3, dt 0.01, 1 s, Coulomb mu 0.8. Cost per step, LM iterations, contacts, final
// centres. Thread CPU time, fastest of 3 (1 in --quick).
void mesh_features_case(bool quick) {
  const std::string obj = std::string(PLIANT_RESULTS_DIR) + "/../../assets/models/pebble.obj";
  const std::string xml =
      "<mujoco><asset><mesh name=\"pebble\" file=\"" + obj + "\"/></asset><worldbody>"
      "<geom type=\"plane\" pos=\"0 0 -0.2\" size=\"1 1 0.1\"/>"
      "<geom type=\"sphere\" size=\"0.01\" pos=\"0.02 0 0\"/>"
      "<geom type=\"sphere\" size=\"0.01\" pos=\"-0.01 0.0173 0\"/>"
      "<geom type=\"sphere\" size=\"0.01\" pos=\"-0.01 -0.0173 0\"/>"
      "<geom type=\"box\" size=\"0.04 0.04 0.04\" pos=\"0.5 0 0\" quat=\"0.8880738 0.3250576 -0.3250576 0\"/>"
      "<body pos=\"0.003 0.002 0.04\"><freejoint/><geom type=\"mesh\" mesh=\"pebble\" mass=\"0.1\"/></body>"
      "<body pos=\"0.5 0.004 0.1\"><freejoint/><geom type=\"mesh\" mesh=\"pebble\" mass=\"0.1\"/></body>"
      "</worldbody></mujoco>";
  const Model m = model_from_mjcf(xml, "mesh_features.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.mu = 0.8;
  const int steps = 100;
  const TimedRollout t = timed_rollout(m, o, state_init(m), steps, quick ? 1 : 3);
  const State& s = t.final;
  emit({{"case", "mesh_features"}, {"method", "pbad3"}, {"dt", o.dt}, {"triangles_per_mesh", m.geoms.back().mesh->triangles.size()},
        {"bodies", m.bodies.size() - 1}, {"steps", steps}, {"us_per_step", 1e6 * t.cpu_s / steps},
        {"lm_iterations", t.iterations / steps}, {"contacts_per_step", t.contacts / steps},
        {"final_xyz_m", std::vector<double>{s.qpos[0], s.qpos[1], s.qpos[2], s.qpos[7], s.qpos[8], s.qpos[9]}},
        {"load_average", load_average()}, {"timing", "thread CPU time, fastest of 3 runs (1 in --quick)"}});
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, chains_only = false, filtered = false;
  std::string out = std::string(PLIANT_RESULTS_DIR) + "/articulated.json";
  std::vector<int> only_links;
  std::vector<double> only_dts;
  std::string only_case, only_methods;
  auto parse_list = [](const char* text) {
    std::vector<double> v;
    for (const char* c = text; *c;) {
      char* end = nullptr;
      v.push_back(std::strtod(c, &end));
      if (end == c) break;
      c = *end == ',' ? end + 1 : end;
    }
    return v;
  };
  // Filters for exploring one corner (--links 10,40 --dt 0.05 --case chain_tilt
  // --chains-only); a filtered run writes a results file only with an explicit --out.
  bool explicit_out = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--chains-only")) chains_only = filtered = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i], explicit_out = true;
    else if (!std::strcmp(argv[i], "--links") && i + 1 < argc) {
      for (double l : parse_list(argv[++i])) only_links.push_back(static_cast<int>(l));
      filtered = true;
    } else if (!std::strcmp(argv[i], "--dt") && i + 1 < argc) only_dts = parse_list(argv[++i]), filtered = true;
    else if (!std::strcmp(argv[i], "--case") && i + 1 < argc) only_case = argv[++i], filtered = true;
    else if (!std::strcmp(argv[i], "--methods") && i + 1 < argc) only_methods = argv[++i], filtered = true;
    else {
      std::fprintf(stderr, "usage: bench_articulated [--quick] [--out FILE] [--links 10,40] [--dt 0.02,0.05] "
                           "[--case chain_swing|chain_tilt|pile|mesh_mesh|mesh_terrain|mesh_features] [--methods pbad3,pbad4,mujoco] [--chains-only]\n");
      return 2;
    }
  }
  g_machine = pliant::bench::machine_description();
  if (only_case == "pile" || only_case == "mesh_mesh" || only_case == "mesh_terrain" || only_case == "mesh_features") {
    (only_case == "pile"        ? pile_case
     : only_case == "mesh_mesh" ? mesh_mesh_case
     : only_case == "mesh_terrain" ? mesh_terrain_case
                                   : mesh_features_case)(quick);
    if (explicit_out) std::ofstream(out) << g_results.dump(1) << "\n";
    return 0;
  }
  const double duration = quick ? 2.0 : 10.0;
  std::vector<int> link_counts = quick ? std::vector<int>{10, 40} : std::vector<int>{10, 40, 100};
  std::vector<double> dts = quick ? std::vector<double>{0.005, 0.01, 0.05}
                                  : std::vector<double>{0.001, 0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.1};
  if (!only_links.empty()) link_counts = only_links;
  if (!only_dts.empty()) dts = only_dts;
  // Matched accuracy bookkeeping: best wall per simulated second at drift <= 1%.
  for (const char* chain_case : {"chain_swing", "chain_tilt"}) {
    const bool tilt = std::string(chain_case) == "chain_tilt";
    if (!only_case.empty() && only_case != chain_case) continue;
    for (int links : link_counts) {
      const std::string xml = chain_mjcf(links);
      const Model m = model_from_mjcf(xml, "chain.xml");
      const double range = chain_range(m, links, 0.1);
      const State init = chain_initial(m, tilt);
      // Every run within the drift bound is a candidate for the matched comparison.
      std::vector<std::pair<std::string, double>> candidates;
      auto note = [&](const std::string& method, double dt, const Outcome& o) {
        if (o.stable && o.drift <= 0.01) candidates.emplace_back(method, dt);
      };
      for (double dt : dts) {
        for (Integrator integ :
             {Integrator::Pbad2, Integrator::Pbad3, Integrator::Pbad4, Integrator::Euler, Integrator::Rk4}) {
          if (!only_methods.empty() && only_methods.find(integrator_name(integ)) == std::string::npos) continue;
          const Outcome o = run_ours(m, integ, dt, duration, init, range);
          emit(row(chain_case, integrator_name(integ), links, dt, o));
          note(integrator_name(integ), dt, o);
        }
#ifdef PLIANT_HAVE_MUJOCO
        std::string err;
        mjModel* mm = mujoco_load(xml, &err);
        for (auto [name, integ] : {std::pair{"mujoco_euler", (int)mjINT_EULER}, std::pair{"mujoco_rk4", (int)mjINT_RK4},
                                   std::pair{"mujoco_implicit", (int)mjINT_IMPLICIT}}) {
          if (!only_methods.empty() && only_methods.find("mujoco") == std::string::npos) continue;
          if (!mm) {
            emit({{"case", chain_case}, {"method", name}, {"links", links}, {"dt", dt}, {"refused", true},
                  {"stable", false}, {"error", err}});
            continue;
          }
          const Outcome o = run_mujoco(mm, m, integ, dt, duration, init, range);
          emit(row(chain_case, name, links, dt, o));
          note(name, dt, o);
        }
        if (mm) mj_deleteModel(mm);
#endif
      }
      // Matched accuracy: each family's cheapest run (time per simulated s) with drift
      // <= 1%. The sweep's single wall times on a shared machine are noisy, so each
      // method's candidate with the largest dt within the bound (fewest steps; the
      // cheapest unless iterations grow faster than dt) is re-timed: stepping only,
      // thread CPU time (a descheduled process does not count), kReps repeats
      // interleaving Pliant and MuJoCo (order reversed every repeat); the fastest
      // repeat counts, the spread of the repeats and the per-repeat ratio are reported.
      constexpr int kReps = 5;
      std::map<std::string, double> largest_dt;
      for (const auto& [meth, dt] : candidates) largest_dt[meth] = std::max(largest_dt[meth], dt);
      std::vector<std::pair<std::string, double>> timed(largest_dt.begin(), largest_dt.end());
#ifdef PLIANT_HAVE_MUJOCO
      std::string mj_err;
      mjModel* mm = mujoco_load(xml, &mj_err);
#endif
      std::map<std::pair<std::string, double>, std::vector<double>> cpu_times, wall_times;
      for (int rep = 0; rep < kReps; ++rep)
        for (size_t ci = 0; ci < timed.size(); ++ci) {
          const auto& [meth, dt] = timed[rep % 2 ? timed.size() - 1 - ci : ci];
          Timing t;
          if (meth.rfind("mujoco_", 0) == 0) {
#ifdef PLIANT_HAVE_MUJOCO
            if (!mm) continue;
            const int integ = meth == "mujoco_euler" ? mjINT_EULER : meth == "mujoco_rk4" ? mjINT_RK4 : mjINT_IMPLICIT;
            t = time_mujoco(mm, m, integ, dt, duration, init);
#endif
          } else {
            t = time_ours(m, integrator_from_name(meth), dt, duration, init);
          }
          cpu_times[{meth, dt}].push_back(t.cpu / duration);
          wall_times[{meth, dt}].push_back(t.wall / duration);
        }
#ifdef PLIANT_HAVE_MUJOCO
      if (mm) mj_deleteModel(mm);
#endif
      std::map<std::pair<std::string, double>, double> fastest;
      for (const auto& [key, v] : cpu_times) fastest[key] = *std::min_element(v.begin(), v.end());
      auto best_of = [&](std::initializer_list<const char*> methods, std::string* which, double* dt) {
        double w = 0;
        for (const auto& [key, wall] : fastest) {
          bool in = false;
          for (const char* meth : methods) in = in || key.first == meth;
          if (!in) continue;
          if (w == 0 || wall < w) {
            w = wall;
            *which = key.first;
            *dt = key.second;
          }
        }
        return w;
      };
      std::string ours_m, mj_m;
      double ours_dt = 0, mj_dt = 0;
      const double ours_w = best_of({"pbad2", "pbad3", "pbad4"}, &ours_m, &ours_dt);
      const double mj_w = best_of({"mujoco_euler", "mujoco_rk4", "mujoco_implicit"}, &mj_m, &mj_dt);
      nlohmann::json j = {{"case", std::string("matched_") + chain_case}, {"links", links}, {"drift_bound", 0.01},
                          {"timing", "thread CPU time of stepping only (no energy evaluation), fastest of " +
                                         std::to_string(kReps) + " repeats interleaving Pliant and MuJoCo; "
                                         "*_wall_per_sim_s = CPU s per simulated s"},
                          {"load_average", load_average()}};
      j["pliant_method"] = ours_w > 0 ? nlohmann::json(ours_m) : nlohmann::json("none reached 1%");
      j["mujoco_method"] = mj_w > 0 ? nlohmann::json(mj_m) : nlohmann::json("none reached 1%");
      auto spread = [&](const std::pair<std::string, double>& key) {
        const std::vector<double>& v = cpu_times[key];
        return *std::max_element(v.begin(), v.end()) / *std::min_element(v.begin(), v.end());
      };
      auto wall_min = [&](const std::pair<std::string, double>& key) {
        const std::vector<double>& v = wall_times[key];
        return *std::min_element(v.begin(), v.end());
      };
      if (ours_w > 0) {
        j["pliant_dt"] = ours_dt, j["pliant_wall_per_sim_s"] = ours_w;
        j["pliant_spread"] = spread({ours_m, ours_dt});
        j["pliant_wallclock_per_sim_s"] = wall_min({ours_m, ours_dt});
      }
      if (mj_w > 0) {
        j["mujoco_dt"] = mj_dt, j["mujoco_wall_per_sim_s"] = mj_w;
        j["mujoco_spread"] = spread({mj_m, mj_dt});
        j["mujoco_wallclock_per_sim_s"] = wall_min({mj_m, mj_dt});
      }
      if (ours_w > 0 && mj_w > 0) {
        j["ratio_vs_mujoco"] = ours_w / mj_w;
        const std::vector<double>& po = cpu_times[{ours_m, ours_dt}];
        const std::vector<double>& pm = cpu_times[{mj_m, mj_dt}];
        std::vector<double> ratios;
        for (size_t r = 0; r < po.size() && r < pm.size(); ++r) ratios.push_back(po[r] / pm[r]);
        j["ratio_per_repeat"] = ratios;
        j["ratio_wallclock"] = wall_min({ours_m, ours_dt}) / wall_min({mj_m, mj_dt});
      }
      std::string ex_m;
      double ex_dt = 0;
      const double ex_w = best_of({"euler", "rk4"}, &ex_m, &ex_dt);
      if (ex_w > 0) j["pliant_explicit_method"] = ex_m, j["pliant_explicit_dt"] = ex_dt, j["pliant_explicit_wall_per_sim_s"] = ex_w;
      emit(j);
    }
  }
  if (!chains_only) {
    cost_per_step_case();
    contact_cases(quick);
    batched_case(quick);
    pile_case(quick);
    mesh_mesh_case(quick);
    mesh_terrain_case(quick);
    mesh_features_case(quick);
  }
  if (filtered && !explicit_out) return 0;
  std::filesystem::create_directories(std::filesystem::path(out).parent_path());
  std::ofstream(out) << g_results.dump(1) << "\n";
  std::fprintf(stderr, "wrote %s\n", out.c_str());
  return 0;
}
