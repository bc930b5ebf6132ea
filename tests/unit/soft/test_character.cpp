// Characters: a POD basis (full-FEM snapshots under random loads) tracks the full FEM
// of a bar under an unseen load better as it grows.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pliant/geom/triangle_mesh.h"
#include "pliant/soft/fem.h"
#include "pliant/soft/simulator.h"

using namespace pliant::soft;

namespace {
// RMS node error of the reduced model against the full FEM for a free bar under a
// body force growing along it (as bench_soft's reduced_vs_full), relative to the
// RMS displacement of the full solution.
double bar_error(const Character& ch, const Character& full, int frames) {
  Environment env;
  env.gravity_m_per_s2.setZero();
  SimParams sp;
  sp.dt_s = 0.01;
  sp.modal_damping_s = 0;
  const int n = full.lattice.nodes();
  Eigen::VectorXd f(3 * n);
  for (int j = 0; j < n; ++j) {
    const double s = full.lattice.rest[j][0] + 0.5;
    f.segment<3>(3 * j) = full.lattice.node_mass_kg[j] * Eigen::Vector3d(0, 20.0 * s * s, 5.0 * s);
  }
  Eigen::VectorXd x = full.rest, xp = full.rest, y;
  SoftState s = initial_state(ch, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), sp.dt_s);
  double num = 0, den = 0;
  for (int k = 0; k < frames; ++k) {
    full_step(full, env, sp, f, x, xp);
    reduced_step(ch, env, sp, Eigen::VectorXd::Zero(ch.basis.r()), s, nullptr, &f);
    node_positions(ch, s, y);
    num += (y - x).squaredNorm();
    den += (x - full.rest).squaredNorm();
  }
  return std::sqrt(num / den);
}

Character bar(int modes, const PodTraining* pod) {
  auto cube = pliant::geom::unit_cube_mesh();
  for (auto& v : cube.vertices) v[1] *= 0.2, v[2] *= 0.2;
  SurfaceMesh s = repair_mesh(cube);
  Lattice lat = build_lattice(s, 6, 1000);
  return make_character(std::move(s), std::move(lat), Material{1000, 5e4, 0.3}, modes, 0, pod);
}
}  // namespace

TEST(Simulator, PodErrorDecreasesWithBasisSize) {
  // Training loads are random cosine fields, not the test load.
  PodTraining t;
  t.runs = 4;
  t.frames = 12;
  t.linear_modes = 3;
  const Character full = bar(1, nullptr);
  const double e4 = bar_error(bar(4, &t), full, 15);
  const double e8 = bar_error(bar(8, &t), full, 15);
  const double e16 = bar_error(bar(16, &t), full, 15);
  std::printf("POD bar error r=4 %.4f r=8 %.4f r=16 %.4f\n", e4, e8, e16);
  EXPECT_LT(e8, e4);
  EXPECT_LT(e16, e8);
  EXPECT_LT(e16, 0.1);
  const Character pod = bar(8, &t);
  EXPECT_EQ(pod.basis.r(), 8);
}
