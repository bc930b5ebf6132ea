// Editor-facing entry points: mode-shape preview, optimization, checkpoint theta and
// frame-by-frame playback. The "soft" job uses the same playback step, so what the
// editor plays is what the take holds.
#include <algorithm>
#include <stdexcept>

#include "pliant/core/blob_field.h"
#include "pliant/soft/soft.h"

namespace pliant::soft {

void soft_mode_shape(const SoftModel& m, const Eigen::VectorXd& q, std::vector<Eigen::Vector3d>& surface,
                     Eigen::VectorXd* nodes) {
  const Character& ch = m.character;
  if (q.size() != ch.basis.r()) throw std::invalid_argument("soft_mode_shape: q needs one value per mode");
  Eigen::VectorXd x;
  local_shape(ch, q, x);  // Xbar + U q, or the rotation-strain shape
  for (int j = 0; j < ch.lattice.nodes(); ++j) x.segment<3>(3 * j) += ch.rest_com;
  embed_surface(ch.lattice, x, surface);
  if (nodes) *nodes = x;
}

Eigen::VectorXd soft_q_from_amplitudes(const SoftModel& m, const Eigen::VectorXd& amplitude_m) {
  return amplitude_m.cwiseQuotient(m.character.mode_scale);
}

void soft_state_surface(const SoftModel& m, const SoftState& s, std::vector<Eigen::Vector3d>& surface) {
  Eigen::VectorXd x;
  node_positions(m.character, s, x);
  embed_surface(m.character.lattice, x, surface);
}

double soft_optimize(const SoftModel& m, OptimizerState& st, const IterationFn& on_iteration,
                     SpacetimeReport* report) {
  const Problem& p = m.problem;
  if (m.optimizer.kind == OptimizerKind::Spacetime) {
    spacetime_optimize(p, m.spacetime, st, on_iteration, report);
    return st.history.back();
  }
  if (st.theta.size() == 0) st.theta = initial_theta(p);
  const ResidualFn rf = [&p](const Eigen::VectorXd& th) { return residuals(p, th); };
  optimize(rf, m.optimizer, st, on_iteration, problem_jacobian(p, m.optimizer),
           problem_residual_jacobian(p, m.optimizer));
  if (st.history.empty()) {
    st.objective = 0.5 * residuals(p, st.theta).squaredNorm();
    st.history.push_back(st.objective);
  }
  return st.history.back();
}

bool soft_take_theta(const std::string& take_dir, const SoftModel& m, Eigen::VectorXd* theta) {
  TakeReader reader(take_dir);
  Record ck;
  if (!reader.latest(RecordKind::Checkpoint, &ck)) return false;
  // The full-precision theta of the job's "optimizer" blob when it has one (the
  // controller the job played back), else the f32 "theta".
  if (const Field* blob = ck.find("optimizer")) {
    try {
      OptimizerState st = optimizer_state_deserialize(field_bytes(*blob));
      if (st.theta.size() == m.problem.dmp.parameters()) {
        *theta = std::move(st.theta);
        return true;
      }
    } catch (const std::runtime_error&) {  // damaged: the f32 copy below
    }
  }
  const Field* th = ck.find("theta");
  if (!th || int(th->data.size()) != m.problem.dmp.parameters()) return false;
  theta->resize(th->data.size());
  for (size_t i = 0; i < th->data.size(); ++i) (*theta)[Eigen::Index(i)] = th->data[i];
  return true;
}

SoftPlayback soft_playback_start(const SoftModel& m, const Eigen::VectorXd& theta) {
  const Problem& p = m.problem;
  if (theta.size() != p.dmp.parameters()) throw std::invalid_argument("soft_playback_start: theta size mismatch");
  SoftPlayback pb;
  pb.theta = theta;
  pb.state = initial_state(m.character, p.start_offset_m, Eigen::Vector3d::Zero(), p.sim.dt_s);
  pb.dmp = dmp_init(p.dmp);
  pb.push_nodal.setZero(3 * m.character.lattice.nodes());
  return pb;
}

void soft_playback_step(const SoftModel& m, SoftPlayback& pb) {
  const Problem& p = m.problem;
  const Character& ch = m.character;
  const Eigen::VectorXd& y = dmp_step(p.dmp, pb.theta, p.sim.dt_s, pb.dmp);
  // Into a per-thread buffer: a playback frame allocates nothing (tested).
  thread_local Eigen::VectorXd u;
  control_force(ch, y, max_activation_m(ch, p.dmp), u);
  const int f = pb.state.frame;
  if ((pb.track_kp > 0 || pb.track_kd > 0) && f >= 1 && f < int(pb.q_ref.size())) {
    // Explicit PD on the current error (state and reference at frame f); gains
    // relative to each mode's stiffness so one pair of numbers suits every mode.
    for (int k = 0; k < std::min(p.dmp.modes, ch.basis.r()); ++k) {
      const double e = pb.q_ref[f][k] - pb.state.q[k];
      const double edot = (pb.q_ref[f][k] - pb.q_ref[f - 1][k]) - (pb.state.q[k] - pb.state.q_prev[k]);
      u[k] += ch.basis.omega2[k] * (pb.track_kp * e + pb.track_kd * edot);
    }
  }
  const int n = ch.lattice.nodes();
  const bool global = pb.push_n.squaredNorm() > 0;
  const bool local = pb.push_nodal.size() == 3 * n && pb.push_nodal.squaredNorm() > 0;
  if (pb.push_nodal.size() != 0 && pb.push_nodal.size() != 3 * n)
    throw std::invalid_argument("soft_playback_step: push_nodal needs 3 values per lattice node");
  if (global || local) {
    thread_local Eigen::VectorXd f;
    if (local)
      f = pb.push_nodal;  // same size every frame: no allocation after the first
    else
      f.setZero(3 * n);
    if (global)
      for (int j = 0; j < n; ++j) f.segment<3>(3 * j) += pb.push_n * (ch.lattice.node_mass_kg[j] / ch.mass_kg);
    reduced_step(ch, p.env, p.sim, u, pb.state, &pb.last, &f);
    pb.push_n.setZero();
    if (local) pb.push_nodal.setZero();
  } else {
    reduced_step(ch, p.env, p.sim, u, pb.state, &pb.last);
  }
}

std::vector<Eigen::VectorXd> soft_reference_q(const SoftModel& m, const Eigen::VectorXd& theta, int frames) {
  SoftPlayback pb = soft_playback_start(m, theta);
  std::vector<Eigen::VectorXd> out{pb.state.q};
  for (int f = 0; f < frames; ++f) {
    soft_playback_step(m, pb);
    out.push_back(pb.state.q);
  }
  return out;
}

}  // namespace pliant::soft
