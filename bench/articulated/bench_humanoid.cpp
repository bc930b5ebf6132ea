// MuJoCo's own humanoid (libmujoco-samples' humanoid.xml, unchanged) dropped limp on
// the floor for 3 s (assets/scenes/articulated_humanoid_fall.json), and 22 of them
// (22_humanoids.xml): Pliant's pbad3 and Euler at several dt against MuJoCo's Euler,
// RK4 and implicit on the same file. A contact-rich fall has no analytic answer, so the
// rows report what a user checks: it stayed finite, came to rest lying on the floor
// (torso height and kinetic energy at the end), how deep bodies sank into the floor,
// and the thread CPU time per simulated second.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_common.h"
#include "pliant/core/scene.h"

namespace art_bench {
namespace {

constexpr double kDuration = 3.0;
const std::string kModelDir = "/usr/share/mujoco/model/";  // Debian's libmujoco-samples

struct FallOutcome {
  double cpu_s = 0, torso_z_min = 0, torso_z_max = 0, kinetic_end = 0, max_depth = 0, contacts = 0, iterations = 0;
  int steps = 0;
  bool finite = true;
};

// Free joints' heights: every humanoid's torso (its root) has qpos[qadr + 2].
void torso_heights(const std::vector<int>& adr, const double* qpos, FallOutcome* f) {
  f->torso_z_min = 1e300, f->torso_z_max = -1e300;
  for (int a : adr) {
    f->torso_z_min = std::min(f->torso_z_min, qpos[a + 2]);
    f->torso_z_max = std::max(f->torso_z_max, qpos[a + 2]);
  }
}

FallOutcome fall_ours(const ArticulatedScene& a, Integrator integ, double dt, double duration) {
  SimOptions o = a.options;
  o.integrator = integ;
  o.dt = dt;
  State s = a.initial;
  SimWorkspace ws;
  FallOutcome f;
  f.steps = static_cast<int>(std::lround(duration / dt));
  for (int i = 0; i < f.steps; ++i) {
    StepInfo info;
    const double t0 = thread_cpu_s();
    const bool ok = sim_step(a.model, o, s, ws, &info);
    f.cpu_s += thread_cpu_s() - t0;
    f.iterations += info.iterations;
    f.contacts += ws.contacts.size() + ws.pair_contacts.size();
    for (const Contact& c : ws.contacts) f.max_depth = std::max(f.max_depth, c.depth);
    if (!ok || !s.qpos.allFinite()) {
      f.finite = false;
      f.steps = i + 1;
      break;
    }
  }
  std::vector<int> roots;
  for (const Joint& j : a.model.joints)
    if (j.type == JointType::Free) roots.push_back(j.qadr);
  torso_heights(roots, s.qpos.data(), &f);
  if (f.finite) f.kinetic_end = state_energy(a.model, o, s, ws).kinetic;
  return f;
}

#ifdef PLIANT_HAVE_MUJOCO
FallOutcome fall_mujoco(mjModel* mm, int integrator, double dt, double duration) {
  mm->opt.integrator = integrator;
  mm->opt.timestep = dt;
  mm->opt.enableflags |= mjENBL_ENERGY;
  mjData* d = mj_makeData(mm);
  FallOutcome f;
  f.steps = static_cast<int>(std::lround(duration / dt));
  const double t0 = thread_cpu_s();
  for (int i = 0; i < f.steps; ++i) {
    mj_step(mm, d);
    f.contacts += d->ncon;
    for (int c = 0; c < d->ncon; ++c)
      if (mm->geom_bodyid[d->contact[c].geom1] == 0 || mm->geom_bodyid[d->contact[c].geom2] == 0)
        f.max_depth = std::max(f.max_depth, -d->contact[c].dist);
  }
  f.cpu_s = thread_cpu_s() - t0;
  for (int k = 0; k < mm->nq; ++k) f.finite = f.finite && std::isfinite(d->qpos[k]);
  // MuJoCo resets the state when its accelerations go bad: count that as unstable too.
  f.finite = f.finite && d->warning[mjWARN_BADQACC].number == 0;
  std::vector<int> roots;
  for (int j = 0; j < mm->njnt; ++j)
    if (mm->jnt_type[j] == mjJNT_FREE) roots.push_back(mm->jnt_qposadr[j]);
  torso_heights(roots, d->qpos, &f);
  mj_forward(mm, d);
  f.kinetic_end = d->energy[1];
  mj_deleteData(d);
  return f;
}
#endif

void emit_fall(const char* c, const std::string& method, double dt, int humanoids, const FallOutcome& f) {
  // At rest lying down: every torso below 0.4 m (standing it is at ~1.3 m) and under
  // 0.5 J of kinetic energy per humanoid.
  const bool at_rest = f.finite && f.torso_z_max < 0.4 && f.torso_z_min > -0.05 && f.kinetic_end < 0.5 * humanoids;
  nlohmann::json j = {{"case", c}, {"method", method}, {"dt", dt}, {"humanoids", humanoids}, {"stable", f.finite},
                      {"at_rest_lying", at_rest}, {"torso_z_end_min", f.torso_z_min}, {"torso_z_end_max", f.torso_z_max},
                      {"kinetic_end_j", f.kinetic_end}, {"max_floor_depth_m", f.max_depth},
                      {"contacts_per_step", f.steps ? f.contacts / f.steps : 0.0},
                      {"wall_per_sim_s", f.cpu_s / (f.steps * dt)}, {"us_per_step", 1e6 * f.cpu_s / f.steps},
                      {"simulated_s", f.steps * dt}, {"load_average", load_average()},
                      {"timing", "thread CPU time, fastest of 3 runs (1 in --quick)"}};
  if (method.rfind("pbad", 0) == 0) j["lm_iterations_per_step"] = f.iterations / f.steps;
  emit(j);
}

// The fastest of `reps` runs (the runs are deterministic: only the time differs).
template <class Run>
FallOutcome fastest(int reps, Run run) {
  FallOutcome best = run();
  for (int r = 1; r < reps; ++r) {
    const FallOutcome f = run();
    if (f.cpu_s < best.cpu_s) best = f;
  }
  return best;
}

}  // namespace

void humanoid_case(bool quick) {
  const std::string scene = std::string(PLIANT_RESULTS_DIR) + "/../../assets/scenes/articulated_humanoid_fall.json";
  const ArticulatedScene one = articulated_compile(pliant::load_scene(scene));
  const double duration = quick ? 1.0 : kDuration;
  const int reps = quick ? 1 : 3;
  for (double dt : {0.005, 0.01, 0.02, 0.05})
    emit_fall("humanoid_fall", "pbad3", dt, 1, fastest(reps, [&] { return fall_ours(one, Integrator::Pbad3, dt, duration); }));
  for (double dt : {0.001, 0.005})
    emit_fall("humanoid_fall", "euler", dt, 1, fastest(reps, [&] { return fall_ours(one, Integrator::Euler, dt, duration); }));
#ifdef PLIANT_HAVE_MUJOCO
  char buf[1000] = "";
  mjModel* mm = mj_loadXML((kModelDir + "humanoid/humanoid.xml").c_str(), nullptr, buf, sizeof buf);
  if (!mm) {
    std::fprintf(stderr, "bench_humanoid: MuJoCo cannot load humanoid.xml: %s\n", buf);
    return;
  }
  for (auto [name, integ] : {std::pair{"mujoco_euler", (int)mjINT_EULER}, std::pair{"mujoco_rk4", (int)mjINT_RK4},
                             std::pair{"mujoco_implicit", (int)mjINT_IMPLICIT}})
    for (double dt : {0.005, 0.01, 0.02, 0.05})
      emit_fall("humanoid_fall", name, dt, 1,
                fastest(reps, [&, integ = integ] { return fall_mujoco(mm, integ, dt, duration); }));
  mj_deleteModel(mm);
#endif
  // 22 humanoids in one scene (self-collision among all of them): the same scene's
  // options with MuJoCo's 22_humanoids.xml.
  ArticulatedScene many = one;
  MjcfOptions options;
  options.ignore_solver_params = true;
  many.model = model_load_file(kModelDir + "humanoid/22_humanoids.xml", "22_humanoids.xml", options);
  many.initial = state_init(many.model);
  emit_fall("humanoids22_fall", "pbad3", 0.02, 22,
            fastest(reps, [&] { return fall_ours(many, Integrator::Pbad3, 0.02, duration); }));
#ifdef PLIANT_HAVE_MUJOCO
  mm = mj_loadXML((kModelDir + "humanoid/22_humanoids.xml").c_str(), nullptr, buf, sizeof buf);
  if (!mm) return;
  for (double dt : {0.005, 0.02})
    emit_fall("humanoids22_fall", "mujoco_euler", dt, 22, fastest(reps, [&] { return fall_mujoco(mm, mjINT_EULER, dt, duration); }));
  mj_deleteModel(mm);
#endif
  // humanoid100.xml: the humanoid and 100 free capsules, ellipsoids, boxes, cylinders
  // and spheres dropped into a walled square (1 s, one run: Pliant's mesh-sampled
  // ellipsoids and cylinders make it slow). "At rest" is not expected after 1 s.
  ArticulatedScene objects = one;
  objects.model = model_load_file(kModelDir + "humanoid100/humanoid100.xml", "humanoid100.xml", options);
  objects.initial = state_init(objects.model);
  const double objects_s = quick ? 0.2 : 1.0;
  emit_fall("humanoid100_fall", "pbad3", 0.02, 1, fall_ours(objects, Integrator::Pbad3, 0.02, objects_s));
#ifdef PLIANT_HAVE_MUJOCO
  mm = mj_loadXML((kModelDir + "humanoid100/humanoid100.xml").c_str(), nullptr, buf, sizeof buf);
  if (!mm) return;
  for (double dt : {0.005, 0.02}) emit_fall("humanoid100_fall", "mujoco_euler", dt, 1, fall_mujoco(mm, mjINT_EULER, dt, objects_s));
  mj_deleteModel(mm);
#endif
}

}  // namespace art_bench
