// Rotation-strain map internals: the left Jacobian built from stored coefficients
// (exp_coefficients + so3_left_jacobian) against the direct definition, and the map's
// lazily filled per-sample Jacobians (line-search evaluations skip them) against an
// evaluation that builds them at once; reduced_step's reuse of the last step's start
// shape for q_prev against a cold evaluation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>

#include "pliant/geom/triangle_mesh.h"
#include "pliant/soft/fem.h"
#include "pliant/soft/modes.h"
#include "pliant/soft/rotation_strain.h"
#include "pliant/soft/simulator.h"
#include "rotation_strain_test_lattices.h"
#include "soft_test_scenes.h"
#include "rotation_strain_workspace.h"

using namespace pliant::soft;

namespace {

Eigen::Matrix3d rs_cache_exp(const Eigen::Vector3d& v) {
  const double t = v.norm();
  if (t == 0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(t, v / t).toRotationMatrix();
}

// A soft 0.4 x 0.2 x 0.4 m block on the ground with rotation-strain coordinates.
Character rs_cache_block() {
  auto cube = pliant::geom::unit_cube_mesh();
  for (auto& v : cube.vertices) v[0] *= 0.4, v[1] *= 0.2, v[2] *= 0.4, v[1] += 0.1;
  SurfaceMesh s = repair_mesh(cube);
  Lattice lat = build_lattice(s, 4, 1000);
  Character ch = make_character(std::move(s), std::move(lat), Material{1000, 2e4, 0.3}, 5);
  enable_rotation_strain(ch);
  return ch;
}

bool rs_cache_same(const SoftState& a, const SoftState& b) {
  return a.q == b.q && a.q_prev == b.q_prev && a.R == b.R && a.c == b.c;
}

}  // namespace

// exp([v]x) against Eigen's angle-axis rotation; J against central differences of
// d/dh exp([v + h d]x) exp([v]x)^T = [J d]x, from tiny to large angles.
TEST(RotationStrain, ExpAndLeftJacobianFromCoefficientsMatchTheDefinition) {
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3, -0.8, 0.5).normalized();
  for (double t : {0.0, 3e-5, 2e-3, 0.3, 1.2, 2.9}) {
    const Eigen::Vector3d v = t * dir + (t > 0 ? 0.1 * t : 0.0) * Eigen::Vector3d(0.2, 0.1, -0.3);
    Eigen::Matrix3d E, J, Jlazy;
    exp_and_jacobian(v, &E, &J);
    EXPECT_LT((E - rs_cache_exp(v)).cwiseAbs().maxCoeff(), 1e-14) << "t " << t;
    double s, c, b;
    exp_coefficients(v, &s, &c, &b);
    so3_left_jacobian(v, c, b, &Jlazy);
    EXPECT_EQ((J - Jlazy).cwiseAbs().maxCoeff(), 0.0) << "t " << t;  // the same arithmetic
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k);
      const double h = 1e-6;
      const Eigen::Matrix3d D = (rs_cache_exp(v + h * d) - rs_cache_exp(v - h * d)) / (2 * h) * E.transpose();
      const Eigen::Vector3d Jd = J * d;
      EXPECT_LT((D - cross_matrix(Jd)).cwiseAbs().maxCoeff(), 1e-8) << "t " << t << " direction " << k;
    }
  }
}

// A positions-only evaluation stores no per-sample J; a later Jacobian, vjp or
// curvature at the same z (a cache hit) fills it. Its results must be the bits of an
// evaluation that built J at once (both slots evicted in between).
TEST(RotationStrain, LazyPerSampleJacobiansGiveTheFreshEvaluationsBits) {
  const Lattice lat = pliant::soft::test::beam_lattice();
  const ModalBasis b = linear_modes(lat, lame_from(Material{1000, 1e5, 0.3}), 4);
  const RotationStrain rs = rotation_strain_build(lat, b.U);
  Eigen::VectorXd z(4), x, x2, out1, out2;
  z << 0.9, -0.5, 0.6, 0.4;
  z *= 0.25 / b.U.cwiseAbs().maxCoeff();
  const Eigen::VectorXd g = Eigen::VectorXd::LinSpaced(3 * lat.nodes(), -1, 1);
  Eigen::MatrixXd J1, J2, C1, C2;
  auto evict = [&] {
    rotation_strain_positions(lat, rs, 0.5 * z, x2);
    rotation_strain_positions(lat, rs, -0.7 * z, x2);
  };
  // Lazy: positions first, then each consumer of J.
  rotation_strain_positions(lat, rs, z, x);
  rotation_strain_positions(lat, rs, z, x, &J1);
  evict();
  rotation_strain_positions(lat, rs, z, x);
  rotation_strain_vjp(lat, rs, z, g, out1);
  evict();
  rotation_strain_positions(lat, rs, z, x);
  rotation_strain_curvature(lat, rs, z, g, C1);
  // Fresh: each consumer evaluates the map itself.
  evict();
  rotation_strain_positions(lat, rs, z, x, &J2);
  evict();
  rotation_strain_vjp(lat, rs, z, g, out2);
  evict();
  rotation_strain_curvature(lat, rs, z, g, C2);
  EXPECT_EQ((J1 - J2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((out1 - out2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((C1 - C2).cwiseAbs().maxCoeff(), 0.0);
  // And the Jacobian is the map's: a central difference along z.
  const double h = 1e-5 / b.U.cwiseAbs().maxCoeff();
  Eigen::VectorXd xp, xm;
  rotation_strain_positions(lat, rs, z + h * Eigen::VectorXd::Ones(4), xp);
  rotation_strain_positions(lat, rs, z - h * Eigen::VectorXd::Ones(4), xm);
  const Eigen::VectorXd fd = (xp - xm) / (2 * h), jd = J1.rowwise().sum();
  EXPECT_LT((fd - jd).norm(), 1e-6 * jd.norm());
}

// reduced_step copies the previous step's start shape for q_prev when q_prev has the
// same bits (one map evaluation per frame instead of two); a step must give the same
// bits with the copy as with a cold evaluation, and must not copy for another q_prev.
TEST(RotationStrain, StepReusesThePreviousShapeOnlyForTheSameCoordinates) {
  const Character ch = rs_cache_block();
  const Environment env = pliant::soft::test::ground(0.5);
  SimParams sp;
  sp.dt_s = 0.01;
  const SoftState s0 = initial_state(ch, Eigen::Vector3d::Zero(), Eigen::Vector3d(1, -0.5, 0.3), sp.dt_s);
  const Eigen::VectorXd u = 40.0 * Eigen::VectorXd::LinSpaced(ch.basis.r(), -1, 1);
  SoftState s1 = s0;
  reduced_step(ch, env, sp, u, s1);
  SoftState s2 = s1;
  reduced_step(ch, env, sp, u, s2);
  ASSERT_GT(s2.q.norm(), 1e-4);  // deformed
  auto forget = [&] {            // a step of another state: the kept shape is s0's
    SoftState o = s0;
    reduced_step(ch, env, sp, Eigen::VectorXd::Zero(ch.basis.r()), o);
  };
  // Same q_prev as the kept shape (s2 follows s1): copied, then cold.
  SoftState warm = s2, cold = s2;
  reduced_step(ch, env, sp, u, warm);
  forget();
  reduced_step(ch, env, sp, u, cold);
  EXPECT_TRUE(rs_cache_same(warm, cold));
  // Another q_prev right after the step that kept s2's shape: must not copy it.
  SoftState other = s2, other_cold = s2;
  other.q_prev *= 1.01, other_cold.q_prev *= 1.01;
  SoftState again = s1;
  reduced_step(ch, env, sp, u, again);  // keeps s1's shape, s2.q_prev == s1.q
  reduced_step(ch, env, sp, u, other);
  forget();
  reduced_step(ch, env, sp, u, other_cold);
  EXPECT_TRUE(rs_cache_same(other, other_cold));
  EXPECT_FALSE(rs_cache_same(other, warm));  // q_prev matters
}
