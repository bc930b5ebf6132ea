// Chain runs shared by the integrator tests (test_sim, test_explicit_integrators,
// test_pbad_step, test_pbad_solver): energy drift of a swinging chain and the whip.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"

namespace pliant::articulated::test {

// Potential energy range of a chain of 0.1 m links: straight horizontal to hanging
// (drifts are normalised by it).
inline double chain_energy_range(const Model& m, int links) {
  double mass = 0;
  for (const Body& b : m.bodies) mass += b.mass;
  return mass / links * 9.81 * 0.1 * links * links / 2.0;
}

// Chain hanging 30 degrees from vertical, swinging in 3D. (Released from horizontal
// the chain whips; PBAD's numerical damping then loses much more: bench_articulated.)
inline double chain_drift(int links, Integrator integ, double dt, double duration) {
  const Model m = model_from_mjcf(chain_mjcf(links), "chain.xml");
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  State s = state_init(m);
  s.qpos[0] = 1.3;  // about y: from along +x towards -z
  s.qvel[1] = 0.3;  // root swings sideways too: a 3D motion
  SimWorkspace ws;
  const double e0 = state_energy(m, o, s, ws).total;
  const double range = chain_energy_range(m, links);
  double drift = 0;
  while (s.time < duration - 1e-9) {
    if (!sim_step(m, o, s, ws)) return 1e9;
    drift = std::max(drift, std::abs(state_energy(m, o, s, ws).total - e0));
  }
  return drift / range;
}

// Kinetic energy of the body points' second-order backward differences over the
// frames q_{i+1}, q_i, q_{i-1}: independent of how joint angles parametrise the pose.
inline double body_point_kinetic_energy(const Model& m, const VecX& q0, const VecX& q1, const VecX& q2, double dt) {
  Kinematics k[3];
  kinematics(m, q0, &k[0]);
  kinematics(m, q1, &k[1]);
  kinematics(m, q2, &k[2]);
  double e = 0;
  for (size_t b = 1; b < m.bodies.size(); ++b) {
    const Body& body = m.bodies[b];
    const Mat3 second_moment = 0.5 * body.inertia.trace() * Mat3::Identity() - body.inertia;
    const Vec3 v = (3 * k[0].xcom[b] - 4 * k[1].xcom[b] + k[2].xcom[b]) / (2 * dt);
    const Mat3 rdot = (3 * k[0].xmat[b] - 4 * k[1].xmat[b] + k[2].xmat[b]) / (2 * dt);
    e += 0.5 * body.mass * v.squaredNorm() + 0.5 * (rdot * second_moment * rdot.transpose()).trace();
  }
  return e;
}

// A chain released horizontally (it whips when it swings down) until `until` s: the
// largest energy drift, the largest gap between the state's kinetic energy and the
// body points' own (from `mismatch_from` s on), and LM iterations per step.
struct WhipRun {
  double drift = 0, mismatch = 0, iterations_per_step = 0;
  bool ok = true;
  double failed_at = -1;
};

inline WhipRun run_whip(int links, Integrator integ, double dt, double until, double mismatch_from) {
  const Model m = model_from_mjcf(chain_mjcf(links), "chain.xml");
  SimOptions o;
  o.integrator = integ;
  o.dt = dt;
  State s = state_init(m);
  s.qvel[1] = 0.5;
  SimWorkspace ws;
  const double range = chain_energy_range(m, links);
  const double e0 = state_energy(m, o, s, ws).total;
  std::vector<VecX> frames;  // q_{i+1}, q_i, q_{i-1}
  WhipRun r;
  int iterations = 0, steps = 0;
  while (s.time < until - 1e-9) {
    StepInfo info;
    if (!sim_step(m, o, s, ws, &info)) {
      r.ok = false;
      r.failed_at = s.time;
      return r;
    }
    iterations += info.iterations;
    ++steps;
    const Energy e = state_energy(m, o, s, ws);
    r.drift = std::max(r.drift, std::abs(e.total - e0) / range);
    frames.insert(frames.begin(), s.qpos);
    if (frames.size() > 3) frames.pop_back();
    if (frames.size() == 3 && s.time >= mismatch_from)
      r.mismatch = std::max(r.mismatch, std::abs(e.kinetic - body_point_kinetic_energy(m, frames[0], frames[1],
                                                                                       frames[2], o.dt)) / range);
  }
  r.iterations_per_step = static_cast<double>(iterations) / std::max(steps, 1);
  return r;
}

}  // namespace pliant::articulated::test
