// Joint dry friction (MJCF frictionloss) against MuJoCo: a rotor spinning down to
// its analytic stop, and a pendulum held horizontal by friction above its gravity
// torque (how far it creeps in 5 s). Also the same rotor without friction, whose
// speed should not change: PBAD's body-point stencil damps rotation (README,
// "Rotational damping"): dw/dt = -h w^3 (pbad2), -h^3 w^5 (pbad3).
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "bench_common.h"

namespace art_bench {
namespace {

// I = 0.01 kg m^2, w0 = 5 rad/s, F = 0.02 N m: constant deceleration F / I = 2 rad/s^2,
// so it stops at t = 2.5 s after w0^2 / (2 F / I) = 6.25 rad.
const char* kRotorXml = R"(<mujoco><worldbody><body>
  <joint axis="0 0 1" frictionloss="0.02"/>
  <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/></body></worldbody></mujoco>)";
constexpr double kW0 = 5, kStopS = 2.5, kStopAngle = 6.25, kSpinS = 3.0;
const char* kFreeRotorXml = R"(<mujoco><worldbody><body>
  <joint axis="0 0 1"/><inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/></body></worldbody></mujoco>)";

// 1 kg at 0.5 m on a horizontal arm: gravity torque 4.905 N m against F = 6 N m.
const char* kHoldXml = R"(<mujoco><worldbody><body>
  <joint axis="0 1 0" frictionloss="6"/>
  <inertial pos="0.5 0 0" mass="1" diaginertia="0.001 0.001 0.001"/></body></worldbody></mujoco>)";
constexpr double kHoldS = 5.0;

struct Run {
  double angle = 0, chord_speed = 0, stop_s = -1, cpu_per_sim_s = 0;  // chord: the last step's dq / dt
  bool finite = true;
};

Run run_ours(const Model& m, Integrator integ, double dt, double w0, double duration) {
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  o.contact.enabled = false;
  State s = state_init(m);
  s.qvel[0] = w0;
  SimWorkspace ws;
  Run r;
  const int n = static_cast<int>(std::lround(duration / dt));
  double before = s.qpos[0];
  const double c0 = thread_cpu_s();
  for (int i = 0; i < n; ++i) {
    before = s.qpos[0];
    if (!sim_step(m, o, s, ws) || !std::isfinite(s.qpos[0])) {
      r.finite = false;
      break;
    }
    if (w0 > 0 && r.stop_s < 0 && s.qvel[0] < 0.01 * w0) r.stop_s = s.time;
  }
  r.cpu_per_sim_s = (thread_cpu_s() - c0) / duration;
  r.angle = s.qpos[0];
  r.chord_speed = (s.qpos[0] - before) / dt;
  return r;
}

#ifdef PLIANT_HAVE_MUJOCO
Run run_mujoco(mjModel* mm, int integ, double dt, double w0, double duration) {
  mm->opt.integrator = integ;
  mm->opt.timestep = dt;
  mjData* d = mj_makeData(mm);
  d->qvel[0] = w0;
  Run r;
  const int n = static_cast<int>(std::lround(duration / dt));
  double before = d->qpos[0];
  const double c0 = thread_cpu_s();
  for (int i = 0; i < n; ++i) {
    before = d->qpos[0];
    mj_step(mm, d);
    if (!std::isfinite(d->qpos[0])) {
      r.finite = false;
      break;
    }
    if (w0 > 0 && r.stop_s < 0 && d->qvel[0] < 0.01 * w0) r.stop_s = d->time;
  }
  r.cpu_per_sim_s = (thread_cpu_s() - c0) / duration;
  r.angle = d->qpos[0];
  r.chord_speed = (d->qpos[0] - before) / dt;
  mj_deleteData(d);
  return r;
}
#endif

}  // namespace

void joint_friction_case(bool quick) {
  const std::vector<double> dts = quick ? std::vector<double>{0.01} : std::vector<double>{0.001, 0.01, 0.05};
  const std::vector<Integrator> ours = {Integrator::Pbad2, Integrator::Pbad3, Integrator::Pbad4, Integrator::Euler,
                                       Integrator::Rk4};
  const Model rotor = model_from_mjcf(kRotorXml, "rotor.xml"), hold = model_from_mjcf(kHoldXml, "hold.xml"),
              free_rotor = model_from_mjcf(kFreeRotorXml, "free_rotor.xml");
  auto spin_row = [&](const std::string& method, double dt, const Run& r) {
    emit({{"case", "joint_friction_spin"}, {"method", method}, {"dt", dt}, {"stable", r.finite},
          {"angle_rad", r.angle}, {"analytic_rad", kStopAngle}, {"error_rel", r.angle / kStopAngle - 1},
          {"stop_s", r.stop_s}, {"analytic_stop_s", kStopS}, {"wall_per_sim_s", r.cpu_per_sim_s}});
  };
  auto hold_row = [&](const std::string& method, double dt, const Run& r) {
    emit({{"case", "joint_friction_hold"}, {"method", method}, {"dt", dt}, {"stable", r.finite},
          {"creep_rad", std::abs(r.angle)}, {"duration_s", kHoldS}, {"wall_per_sim_s", r.cpu_per_sim_s}});
  };
  auto free_row = [&](const std::string& method, double dt, const Run& r) {
    emit({{"case", "free_rotor"}, {"method", method}, {"dt", dt}, {"stable", r.finite},
          {"speed_ratio", r.chord_speed / kW0}, {"duration_s", kSpinS},
          {"pbad2_law", std::pow(1 + 2 * dt * kSpinS * kW0 * kW0, -0.5)},
          {"pbad3_law", std::pow(1 + 4 * dt * dt * dt * kSpinS * std::pow(kW0, 4), -0.25)}});
  };
  for (double dt : dts)
    for (Integrator integ : ours) {
      spin_row(integrator_name(integ), dt, run_ours(rotor, integ, dt, kW0, kSpinS));
      hold_row(integrator_name(integ), dt, run_ours(hold, integ, dt, 0, kHoldS));
      free_row(integrator_name(integ), dt, run_ours(free_rotor, integ, dt, kW0, kSpinS));
    }
#ifdef PLIANT_HAVE_MUJOCO
  std::string err;
  mjModel* mr = mujoco_load(kRotorXml, &err);
  mjModel* mh = mujoco_load(kHoldXml, &err);
  mjModel* mf = mujoco_load(kFreeRotorXml, &err);
  if (!mr || !mh || !mf) {
    std::fprintf(stderr, "bench_articulated: MuJoCo refused the friction models: %s\n", err.c_str());
    return;
  }
  for (double dt : dts)
    for (auto [name, integ] : {std::tuple{"mujoco_euler", (int)mjINT_EULER}, std::tuple{"mujoco_rk4", (int)mjINT_RK4},
                               std::tuple{"mujoco_implicit", (int)mjINT_IMPLICIT}}) {
      spin_row(name, dt, run_mujoco(mr, integ, dt, kW0, kSpinS));
      hold_row(name, dt, run_mujoco(mh, integ, dt, 0, kHoldS));
      free_row(name, dt, run_mujoco(mf, integ, dt, kW0, kSpinS));
    }
  mj_deleteModel(mf);
  mj_deleteModel(mr);
  mj_deleteModel(mh);
#endif
}

}  // namespace art_bench
