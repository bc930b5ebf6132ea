// Integrators' entry points (sim.h): names, the initial state, sim_step's dispatch and
// the state's energy. PBAD: pbad_step.cpp (begin/finish), pbad_energy.cpp (the step's
// energy), pbad_solver.cpp (LM / L-BFGS); Euler and RK4: explicit_integrators.cpp.
#include "pliant/articulated/sim.h"

#include <algorithm>
#include <stdexcept>

#include "sim_internal.h"

namespace pliant::articulated {
namespace {

bool finite(const VecX& v) { return v.allFinite(); }

}  // namespace

void actuator_forces(const Model& m, const State& s, VecX* tau) {
  tau->setZero(m.nv);
  for (size_t a = 0; a < m.actuators.size() && a < static_cast<size_t>(s.ctrl.size()); ++a) {
    const Actuator& act = m.actuators[a];
    const double c = std::clamp(s.ctrl[a], act.ctrl_min, act.ctrl_max);
    (*tau)[m.joints[act.joint].vadr] += act.gear * c;
  }
}

Integrator integrator_from_name(const std::string& name) {
  if (name == "pbad2") return Integrator::Pbad2;
  if (name == "pbad3") return Integrator::Pbad3;
  if (name == "pbad4") return Integrator::Pbad4;
  if (name == "euler") return Integrator::Euler;
  if (name == "rk4") return Integrator::Rk4;
  throw std::invalid_argument("unknown integrator \"" + name + "\"");
}

std::string integrator_name(Integrator i) {
  switch (i) {
    case Integrator::Pbad2: return "pbad2";
    case Integrator::Pbad3: return "pbad3";
    case Integrator::Pbad4: return "pbad4";
    case Integrator::Euler: return "euler";
    case Integrator::Rk4: return "rk4";
  }
  return "?";
}

bool integrator_is_pbad(Integrator i) {
  return i == Integrator::Pbad2 || i == Integrator::Pbad3 || i == Integrator::Pbad4;
}

void sim_prepare(const Model& m, SimWorkspace& ws) {
  if (ws.cached_for == &m) return;
  ws.points = contact_points(m);
  ws.obstacles = contact_obstacles(m);
  ws.obstacle_trees = obstacle_trees(m, ws.obstacles);
  ws.mesh_trees = moving_mesh_trees(m);
  ws.pairs = contact_geom_pairs(m);
  ws.broadphase = pair_broadphase(m, ws.pairs);
  ws.geom_mix = geom_contact_params_set(m);
  ws.forest = model_forest(m);
  ws.cached_for = &m;
}

State state_init(const Model& m) {
  State s;
  s.qpos = m.qpos0;
  s.qvel = VecX::Zero(m.nv);
  s.ctrl = VecX::Zero(m.actuators.size());
  return s;
}

bool sim_step(const Model& m, const SimOptions& o, State& s, SimWorkspace& ws, StepInfo* info) {
  sim_prepare(m, ws);
  StepInfo si;
  switch (o.integrator) {
    case Integrator::Pbad2:
    case Integrator::Pbad3:
    case Integrator::Pbad4: {
      PbadStep& p = ws.pbad;
      pbad_begin(m, o, s, p, ws);
      while (!pbad_iterate(m, o, s, p, ws)) {
      }
      si.iterations = p.iterations;
      si.converged = p.iterations < o.lm_max_iterations;
      si.energy_residual = ws.grad.lpNorm<Eigen::Infinity>();
      pbad_finish(m, o, s, p, ws);
      break;
    }
    case Integrator::Euler:
      euler_step(m, o, s, ws);
      break;
    case Integrator::Rk4:
      rk4_step(m, o, s, ws);
      break;
  }
  if (info) *info = si;
  return finite(s.qpos) && finite(s.qvel);
}

Energy state_energy(const Model& m, const SimOptions& o, const State& s, SimWorkspace& ws) {
  sim_prepare(m, ws);
  kinematics(m, s.qpos, &ws.kin);
  ws.kin_at.resize(0);
  Energy e;
  e.kinetic = kinetic_energy(m, ws.kin, s.qvel);
  e.potential = potential_energy(m, ws.kin) + limit_terms(m, o, s.qpos, nullptr, nullptr);
  if (o.contact.enabled) {
    find_contacts(m, ws.kin, ws.points, ws.obstacles, ws.obstacle_trees, ws.mesh_trees, &ws.contacts);
    for (const Contact& c : ws.contacts) e.potential += 0.5 * o.contact.stiffness * c.depth * c.depth;
    if (pair_contact_on(m, o.contact)) {
      find_pair_contacts(m, ws.kin, ws.pairs, &ws.pair_contacts, o.contact.self_collision, &ws.broadphase);
      for (const PairContact& c : ws.pair_contacts) e.potential += 0.5 * o.contact.stiffness * c.depth * c.depth;
    }
  }
  e.total = e.kinetic + e.potential;
  return e;
}

}  // namespace pliant::articulated
