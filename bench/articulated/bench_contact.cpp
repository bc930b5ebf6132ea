// Contact cases: a box creeping on a slope and sliding to a stop (against MuJoCo), and the body-body pile.
#include <cmath>
#include <cstdio>
#include <tuple>

#include "bench_common.h"

namespace art_bench {
namespace {

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

}  // namespace

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

}  // namespace art_bench
