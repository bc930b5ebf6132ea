// Editor API: mode shapes at q = 0 are the rest surface and move linearly with q;
// frame-by-frame playback reproduces simulate() under the same theta; a push moves
// the body; take checkpoints give back theta.
#include <gtest/gtest.h>

#include <cstdio>

#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"
#include "../malloc_counter.h"

using namespace pliant;

namespace {
soft::SoftModel worm_model(int resolution = 6, int modes = 4) {
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "worm.obj", "resolution": )" + std::to_string(resolution) + R"(, "modes": )" +
                           std::to_string(modes) + R"(},
    "environment": {"type": "ground", "friction": 0.6},
    "simulation": {"dt_s": 0.04, "frames": 8},
    "controller": {"modes": 2, "kernels": 2, "period_s": 0.4},
    "objectives": {"velocity": {"target_m_per_s": [0.1, 0, 0], "weight": 10}},
    "optimizer": {"method": "lm", "iterations": 1, "horizon_frames": 6}})";
  soft::SoftModel m = soft::soft_compile(parse_scene(text, "api.json", std::string(PLIANT_ASSETS_DIR) + "/characters"));
  soft::soft_bind(m);
  return m;
}
}  // namespace

TEST(SoftPlayback, ModeShapeIsRestAtZeroAndLinearInQ) {
  const soft::SoftModel m = worm_model();
  const int r = m.character.basis.r();
  std::vector<Eigen::Vector3d> s0, s1, s2;
  soft::soft_mode_shape(m, Eigen::VectorXd::Zero(r), s0);
  ASSERT_EQ(s0.size(), m.character.surface.vertices.size());
  double err = 0;
  for (size_t v = 0; v < s0.size(); ++v) err = std::max(err, (s0[v] - m.character.surface.vertices[v]).norm());
  EXPECT_LT(err, 1e-9);
  Eigen::VectorXd amp = Eigen::VectorXd::Zero(r);
  amp[0] = 0.01;  // 1 cm largest node displacement of mode 0
  Eigen::VectorXd nodes;
  soft::soft_mode_shape(m, soft::soft_q_from_amplitudes(m, amp), s1, &nodes);
  soft::soft_mode_shape(m, soft::soft_q_from_amplitudes(m, 2 * amp), s2);
  double node_max = 0;
  for (int j = 0; j < m.character.lattice.nodes(); ++j)
    node_max = std::max(node_max, (nodes.segment<3>(3 * j) - m.character.rest.segment<3>(3 * j)).norm());
  EXPECT_NEAR(node_max, 0.01, 1e-9);
  for (size_t v = 0; v < s0.size(); ++v) EXPECT_LT((s2[v] - s0[v] - 2 * (s1[v] - s0[v])).norm(), 1e-9);
}

TEST(SoftPlayback, StepByStepMatchesSimulate) {
  const soft::SoftModel m = worm_model();
  const Eigen::VectorXd theta = Eigen::VectorXd::Constant(m.problem.dmp.parameters(), 0.02);
  const soft::SoftState ref = soft::simulate(m.problem, theta, 6);
  soft::SoftPlayback pb = soft::soft_playback_start(m, theta);
  for (int f = 0; f < 6; ++f) soft::soft_playback_step(m, pb);
  EXPECT_EQ(pb.state.frame, ref.frame);
  EXPECT_LT((pb.state.q - ref.q).norm(), 1e-12 * (1 + ref.q.norm()));
  EXPECT_LT((pb.state.c - ref.c).norm(), 1e-12);
  // A sideways push moves the centre of mass along it.
  soft::SoftPlayback pushed = soft::soft_playback_start(m, theta);
  pushed.push_n = Eigen::Vector3d(0, 0, 20 * m.character.mass_kg);
  for (int f = 0; f < 6; ++f) soft::soft_playback_step(m, pushed);
  EXPECT_GT(soft::centre_of_mass(m.character, pushed.state)[2] - soft::centre_of_mass(m.character, pb.state)[2], 1e-3);
}

TEST(SoftPlayback, TrackingRecoversFromAPushBetterThanOpenLoop) {
  const soft::SoftModel m = worm_model();
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(m.problem.dmp.parameters());
  for (int i = 0; i < theta.size(); ++i) theta[i] = 0.05 * std::sin(1.0 + i);
  const int frames = 40;
  const auto ref = soft::soft_reference_q(m, theta, frames);
  ASSERT_EQ(int(ref.size()), frames + 1);
  auto run = [&](double kp, double kd) {
    soft::SoftPlayback pb = soft::soft_playback_start(m, theta);
    pb.q_ref = ref;
    pb.track_kp = kp;
    pb.track_kd = kd;
    double err = 0;
    for (int f = 0; f < frames; ++f) {
      // A sideways and upward shove at frame 5.
      if (f == 5) pb.push_n = Eigen::Vector3d(0, 30, 60) * m.character.mass_kg;
      soft::soft_playback_step(m, pb);
      if (f >= frames - 10) err += (pb.state.q - ref[f + 1]).norm();
    }
    return err;
  };
  const double open = run(0, 0), tracked = run(3, 0.3);
  EXPECT_GT(open, 0);
  EXPECT_LT(tracked, 0.7 * open);
  // Without a push, tracking the reference leaves it (nearly) unchanged.
  soft::SoftPlayback pb = soft::soft_playback_start(m, theta);
  pb.q_ref = ref;
  pb.track_kp = 3;
  pb.track_kd = 0.3;
  for (int f = 0; f < frames; ++f) soft::soft_playback_step(m, pb);
  EXPECT_LT((pb.state.q - ref.back()).norm(), 1e-6 * (1 + ref.back().norm()));
}

// Rotation-strain coordinates in the full playback step (ground contact, friction,
// DMP control): at small deformation they follow the linear modes (first-order
// equal maps), and the body still moves.
TEST(SoftPlayback, RotationStrainPlaybackFollowsLinearModesAtSmallDeformation) {
  const soft::SoftModel lin = worm_model();
  soft::SoftModel rs = lin;
  soft::enable_rotation_strain(rs.character);
  soft::soft_bind(rs);
  const Eigen::VectorXd theta = Eigen::VectorXd::Constant(lin.problem.dmp.parameters(), 0.01);
  soft::SoftPlayback a = soft::soft_playback_start(lin, theta), b = soft::soft_playback_start(rs, theta);
  for (int f = 0; f < 8; ++f) soft::soft_playback_step(lin, a), soft::soft_playback_step(rs, b);
  const double c_moved = (a.state.c - a.state.c_prev).norm() + (a.state.c - lin.character.rest_com).norm();
  std::printf("rotation-strain vs linear playback: |dq|/|q| %.2g, |dc| %.2g m (COM moved %.2g m)\n",
              (b.state.q - a.state.q).norm() / a.state.q.norm(), (b.state.c - a.state.c).norm(), c_moved);
  EXPECT_GT(c_moved, 1e-4);
  EXPECT_GT(a.state.q.norm(), 0);
  EXPECT_LT((b.state.q - a.state.q).norm(), 0.02 * a.state.q.norm());  // 0.2% measured
  EXPECT_LT((b.state.c - a.state.c).norm(), 0.01 * c_moved);
  std::vector<Eigen::Vector3d> surf;
  soft::soft_state_surface(rs, b.state, surf);
  EXPECT_EQ(surf.size(), rs.character.surface.vertices.size());
}

// Rotation-strain playback with the elastic cubature trained on rotation-strain poses
// follows the full-lattice rotation-strain playback (every cell); the opt-in reduced
// reconstruction (POD + cubature) too, within a looser bound. Worm on the ground,
// DMP gait large enough to bend it (theta 0.3).
TEST(SoftPlayback, RotationStrainCubaturePlaybackFollowsTheFullLattice) {
  soft::SoftModel full = worm_model(14, 6);
  soft::enable_rotation_strain(full.character);
  soft::soft_bind(full);
  soft::SoftModel cub = full;
  cub.character.cubature = soft::fit_cubature(cub.character, soft::training_poses(cub.character, 16, 0.05, 11), 0.02,
                                              400, &cub.cubature);
  soft::soft_bind(cub);
  soft::SoftModel red = worm_model(14, 6);
  soft::enable_rotation_strain(red.character, true);
  red.character.cubature = soft::fit_cubature(red.character, soft::training_poses(red.character, 16, 0.05, 11), 0.02,
                                              400, &red.cubature);
  soft::soft_bind(red);
  const Eigen::VectorXd theta = Eigen::VectorXd::Constant(full.problem.dmp.parameters(), 0.3);
  soft::SoftPlayback a = soft::soft_playback_start(full, theta), b = soft::soft_playback_start(cub, theta),
                     c = soft::soft_playback_start(red, theta);
  Eigen::VectorXd xa, xb, xc;
  double eb = 0, ec = 0, amp = 0;
  for (int f = 0; f < 12; ++f) {
    soft::soft_playback_step(full, a), soft::soft_playback_step(cub, b), soft::soft_playback_step(red, c);
    soft::node_positions(full.character, a.state, xa);
    soft::node_positions(cub.character, b.state, xb);
    soft::node_positions(red.character, c.state, xc);
    eb = std::max(eb, (xb - xa).cwiseAbs().maxCoeff());
    ec = std::max(ec, (xc - xa).cwiseAbs().maxCoeff());
    Eigen::VectorXd local;
    soft::local_shape(full.character, a.state.q, local);
    amp = std::max(amp, (local - full.character.rest_local).cwiseAbs().maxCoeff());
  }
  std::printf("rotation-strain playback, worst node offset from the full lattice over 12 frames: cubature %.3g m "
              "(%d of %zu cells), reduced reconstruction %.3g m; deformation %.3g m\n",
              eb, cub.cubature.cells, cub.character.lattice.cells.size(), ec, amp);
  EXPECT_GT(amp, 0.01);        // the worm bends (1.6 cm measured)
  EXPECT_LT(eb, 0.03 * amp);   // 0.7% measured (16 of 56 cells)
  EXPECT_LT(ec, 0.05 * amp);   // 1.3% measured
}

// Allocation counting (malloc_counter.h): -1 under a sanitizer, where only the other
// checks run.
TEST(SoftPlayback, PlaybackFrameAllocatesNothing) {
  const soft::SoftModel m = worm_model();
  const Eigen::VectorXd theta = Eigen::VectorXd::Constant(m.problem.dmp.parameters(), 0.02);
  soft::SoftPlayback pb = soft::soft_playback_start(m, theta);
  soft::soft_playback_step(m, pb);  // first step sizes the per-thread buffers
  pb.push_n = Eigen::Vector3d(0, 0, 5 * m.character.mass_kg);
  soft::soft_playback_step(m, pb);  // and the push buffer
  const long n = pliant::test::count_allocations([&] {
    for (int f = 0; f < 6; ++f) {
      if (f == 3) pb.push_n = Eigen::Vector3d(0, 0, 5 * m.character.mass_kg);
      if (f >= 4) soft::add_vertex_force(m.character.lattice, f, Eigen::Vector3d(0, 0, 5 * m.character.mass_kg), pb.push_nodal);
      soft::soft_playback_step(m, pb);  // ground contact, friction, a push, a local push
    }
  });
#ifdef PLIANT_MALLOC_COUNT
  EXPECT_EQ(n, 0);
#else
  (void)n;
#endif
  EXPECT_EQ(pb.state.frame, 8);
}

// Rotation-strain coordinates: the per-thread reconstruction workspace (CHOLMOD
// buffers, per-sample exp cache, adjoint and curvature buffers) is sized by the
// first frames; later frames with contact, a push, a local push, the kept Jacobian
// and the curvature allocate nothing.
TEST(SoftPlayback, RotationStrainPlaybackFrameAllocatesNothing) {
  soft::SoftModel m = worm_model();
  soft::enable_rotation_strain(m.character);
  soft::soft_bind(m);
  const Eigen::VectorXd theta = Eigen::VectorXd::Constant(m.problem.dmp.parameters(), 0.3);
  soft::SoftPlayback pb = soft::soft_playback_start(m, theta);
  soft::soft_playback_step(m, pb);
  pb.push_n = Eigen::Vector3d(0, 0, 5 * m.character.mass_kg);
  soft::soft_playback_step(m, pb);
  int iterations = 0;
  const long n = pliant::test::count_allocations([&] {
    for (int f = 0; f < 6; ++f) {
      if (f == 3) pb.push_n = Eigen::Vector3d(0, 0, 5 * m.character.mass_kg);
      if (f == 4) soft::add_vertex_force(m.character.lattice, 0, Eigen::Vector3d(0, 0, 5 * m.character.mass_kg), pb.push_nodal);
      soft::soft_playback_step(m, pb);
      iterations += pb.last.newton_iterations;
    }
  });
#ifdef PLIANT_MALLOC_COUNT
  EXPECT_EQ(n, 0);
#else
  (void)n;
#endif
  EXPECT_GT(iterations, 6);  // more than one Newton iteration per frame: the lagged path ran
  EXPECT_GT(pb.state.q.norm(), 0);
}

// Forward sensitivities (sensitivity.cpp): the per-thread step and Jacobian buffers
// are sized by the first Jacobian of a size; a later Jacobian allocates only per call
// (its result, the residual vectors of the central-difference pass), never per step:
// 12 frames allocate as often as 6, with linear and rotation-strain coordinates. Here
// and not in test_sensitivity.cpp because the allocation counter is included by one
// file of the binary.
TEST(SoftPlayback, SensitivityJacobianStepsAllocateNothing) {
  const soft::SoftModel m = worm_model();
  const Eigen::VectorXd theta = Eigen::VectorXd::Constant(m.problem.dmp.parameters(), 0.3);
  soft::Problem shorter = m.problem, longer = m.problem;
  shorter.frames = 6, longer.frames = 12;
  Eigen::MatrixXd J6 = soft::sensitivity_jacobian(shorter, theta);
  const long n6 = pliant::test::count_allocations([&] { J6 = soft::sensitivity_jacobian(shorter, theta); });
  Eigen::MatrixXd J12 = soft::sensitivity_jacobian(longer, theta);
  const long n12 = pliant::test::count_allocations([&] { J12 = soft::sensitivity_jacobian(longer, theta); });
#ifdef PLIANT_MALLOC_COUNT
  EXPECT_EQ(n12, n6);
  // Per call: the result and, per column, two residual evaluations (each builds its
  // start state and residual vector); 44 measured with 6 parameters.
  EXPECT_LT(n6, 8 * theta.size() + 16);
#else
  (void)n6, (void)n12;
#endif
  EXPECT_TRUE(J6.allFinite());
  EXPECT_GT(J12.norm(), 0);
#ifdef PLIANT_MALLOC_COUNT
  // Rotation-strain coordinates: the map's Jacobian and curvature buffers too (only
  // where allocations can be counted: it is the whole point of this part).
  soft::SoftModel rsm = worm_model();
  soft::enable_rotation_strain(rsm.character);
  soft::soft_bind(rsm);
  soft::Problem rs6 = rsm.problem, rs12 = rsm.problem;
  rs6.frames = 6, rs12.frames = 12;
  J6 = soft::sensitivity_jacobian(rs6, theta);
  const long r6 = pliant::test::count_allocations([&] { J6 = soft::sensitivity_jacobian(rs6, theta); });
  J12 = soft::sensitivity_jacobian(rs12, theta);
  const long r12 = pliant::test::count_allocations([&] { J12 = soft::sensitivity_jacobian(rs12, theta); });
  EXPECT_EQ(r12, r6);
#endif
  EXPECT_TRUE(J12.allFinite());
}
