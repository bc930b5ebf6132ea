// Local push (SoftPlayback::push_nodal filled by add_vertex_force): the force at a
// surface vertex keeps the total force of the whole-body push (push_n), so one step
// changes the linear momentum by the same (F + M g) dt, but it also carries the
// moment r x F about the centre of mass, which push_n (mass-proportional, no moment)
// does not. The worm falls freely (no obstacles) so contact does not enter.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"

using namespace pliant;

namespace {
soft::SoftModel pushloc_free_worm() {
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "worm.obj", "resolution": 6, "modes": 4},
    "environment": {"type": "ground", "friction": 0.6},
    "simulation": {"dt_s": 0.04, "frames": 4},
    "controller": {"modes": 2, "kernels": 2, "period_s": 0.4},
    "objectives": {"velocity": {"target_m_per_s": [0.1, 0, 0], "weight": 10}},
    "optimizer": {"method": "lm", "iterations": 1, "horizon_frames": 4}})";
  soft::SoftModel m = soft::soft_compile(parse_scene(text, "push.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
  m.problem.env.obstacles.clear();  // free fall: momentum changes only by push and gravity
  soft::soft_bind(m);
  return m;
}

Eigen::Vector3d pushloc_momentum(const soft::SoftModel& m, const soft::SoftState& s) {
  return m.character.mass_kg * (s.c - s.c_prev) / m.problem.sim.dt_s;
}

// Angular momentum about the COM from the nodes' last displacement.
Eigen::Vector3d pushloc_angular(const soft::SoftModel& m, const soft::SoftState& s) {
  soft::SoftState prev = s;
  prev.q = s.q_prev;
  prev.R = s.R_prev;
  prev.c = s.c_prev;
  Eigen::VectorXd x, xp;
  soft::node_positions(m.character, s, x);
  soft::node_positions(m.character, prev, xp);
  Eigen::Vector3d L = Eigen::Vector3d::Zero();
  for (int j = 0; j < m.character.lattice.nodes(); ++j)
    L += m.character.lattice.node_mass_kg[j] *
         (x.segment<3>(3 * j) - s.c).cross((x.segment<3>(3 * j) - xp.segment<3>(3 * j)) / m.problem.sim.dt_s);
  return L;
}

// The surface vertex farthest from the COM along x (a tip of the worm).
int pushloc_tip(const soft::SoftModel& m) {
  const auto& v = m.character.surface.vertices;
  int best = 0;
  for (size_t i = 0; i < v.size(); ++i)
    if (v[i].x() > v[size_t(best)].x()) best = int(i);
  return best;
}
}  // namespace

TEST(SoftPushLocal, VertexForceKeepsTotalForceAndHasNoMomentAboutTheVertex) {
  const soft::SoftModel m = pushloc_free_worm();
  const soft::Lattice& lat = m.character.lattice;
  const Eigen::Vector3d F(1.5, -0.5, 2.0);
  Eigen::VectorXd f;
  const int v = pushloc_tip(m);
  soft::add_vertex_force(lat, v, F, f);
  ASSERT_EQ(f.size(), 3 * lat.nodes());
  Eigen::Vector3d total = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  // A deformed lattice: the moment about the embedded vertex stays zero.
  Eigen::VectorXd x(3 * lat.nodes());
  for (int j = 0; j < lat.nodes(); ++j)
    x.segment<3>(3 * j) = lat.rest[size_t(j)] + 0.05 * Eigen::Vector3d(std::sin(3.0 * j), std::cos(j), std::sin(j));
  std::vector<Eigen::Vector3d> surf;
  soft::embed_surface(lat, x, surf);
  for (int j = 0; j < lat.nodes(); ++j) {
    total += f.segment<3>(3 * j);
    moment += (x.segment<3>(3 * j) - surf[size_t(v)]).cross(f.segment<3>(3 * j));
  }
  EXPECT_LT((total - F).norm(), 1e-12);
  EXPECT_LT(moment.norm(), 1e-12);
  EXPECT_THROW(soft::add_vertex_force(lat, int(m.character.surface.vertices.size()), F, f), std::out_of_range);
}

TEST(SoftPushLocal, SameMomentumAsWholeBodyPushButTurnsTheBody) {
  const soft::SoftModel m = pushloc_free_worm();
  const Eigen::VectorXd theta = Eigen::VectorXd::Zero(m.problem.dmp.parameters());
  const double dt = m.problem.sim.dt_s, M = m.character.mass_kg;
  const Eigen::Vector3d F(0, 0, 20 * M);  // sideways, at the tip (r along x): yaw
  const int tip = pushloc_tip(m);
  soft::SoftPlayback none = soft::soft_playback_start(m, theta), whole = none, local = none;
  ASSERT_EQ(local.push_nodal.size(), 3 * m.character.lattice.nodes());
  const Eigen::Vector3d r = m.character.surface.vertices[size_t(tip)] - soft::centre_of_mass(m.character, none.state);
  const Eigen::Vector3d p0 = pushloc_momentum(m, none.state), L0 = pushloc_angular(m, none.state);
  whole.push_n = F;
  soft::add_vertex_force(m.character.lattice, tip, F, local.push_nodal);
  soft::soft_playback_step(m, none);
  soft::soft_playback_step(m, whole);
  soft::soft_playback_step(m, local);
  EXPECT_EQ(local.push_nodal.squaredNorm(), 0.0);  // cleared after the step, size kept
  EXPECT_EQ(local.push_nodal.size(), 3 * m.character.lattice.nodes());
  // Linear momentum: (F + M g) dt for both pushes, up to the Newton tolerance.
  const Eigen::Vector3d expect = (F + M * m.problem.env.gravity_m_per_s2) * dt;
  const Eigen::Vector3d dp_whole = pushloc_momentum(m, whole.state) - p0;
  const Eigen::Vector3d dp_local = pushloc_momentum(m, local.state) - p0;
  EXPECT_LT((dp_whole - expect).norm(), 1e-6 * expect.norm());
  EXPECT_LT((dp_local - expect).norm(), 1e-6 * expect.norm());
  EXPECT_LT((dp_local - dp_whole).norm(), 1e-6 * expect.norm());
  // Angular momentum about the COM, relative to the unpushed step: r x F dt for the
  // local push (to first order: the body moves within the step), ~0 for push_n.
  const Eigen::Vector3d torque_dt = r.cross(F) * dt;
  const Eigen::Vector3d dL_none = pushloc_angular(m, none.state) - L0;
  const Eigen::Vector3d dL_whole = pushloc_angular(m, whole.state) - L0 - dL_none;
  const Eigen::Vector3d dL_local = pushloc_angular(m, local.state) - L0 - dL_none;
  std::printf("dp error / |dp|: whole %.2g local %.2g; dL - r x F dt: local %.2g, whole %.2g (of %.3g)\n",
              (dp_whole - expect).norm() / expect.norm(), (dp_local - expect).norm() / expect.norm(),
              (dL_local - torque_dt).norm(), dL_whole.norm(), torque_dt.norm());
  EXPECT_GT(dL_local.dot(torque_dt), 0.5 * torque_dt.squaredNorm());
  EXPECT_LT((dL_local - torque_dt).norm(), 0.15 * torque_dt.norm());  // 4% measured
  EXPECT_LT(dL_whole.norm(), 1e-9 * torque_dt.norm());  // no moment: round-off
  // And the yaw it starts: the tip moves along F faster than under push_n.
  for (int f = 0; f < 3; ++f) {
    soft::soft_playback_step(m, whole);
    soft::soft_playback_step(m, local);
  }
  const Eigen::Vector3d axis_w = whole.state.R.col(0), axis_l = local.state.R.col(0);
  EXPECT_GT(axis_l.z() - axis_w.z(), 0.0);
}
