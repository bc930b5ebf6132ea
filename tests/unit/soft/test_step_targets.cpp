// Per-step contact targets: the swept-segment contact planes keep a thin sheet dropped
// fast from tunnelling through the ground.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pliant/geom/triangle_mesh.h"
#include "pliant/soft/fem.h"
#include "pliant/soft/simulator.h"
#include "soft_test_scenes.h"

using namespace pliant::soft;

using pliant::soft::test::ground;

TEST(Simulator, ThinSheetDroppedFastDoesNotTunnelThroughTheGround) {
  // A 30 cm sheet one lattice cell (2.5 cm) thick hits the ground at 30 m/s: its
  // inertial target is 1 m below the ground. The plain penalty would stop it about
  // D / (1 + k dt^2) = 4 cm deep (the whole sheet under the ground); the swept-segment
  // contact planes stop every node within a quarter cell.
  auto cube = pliant::geom::unit_cube_mesh();
  for (auto& v : cube.vertices) v[0] *= 0.3, v[1] *= 0.004, v[2] *= 0.3;
  SurfaceMesh s = repair_mesh(cube);
  Lattice lat = build_lattice(s, 12, 1000);
  const Character ch = make_character(std::move(s), std::move(lat), Material{1000, 1e5, 0.3}, 6);
  const Environment env = ground(0.5);
  SimParams sp;
  sp.dt_s = 1.0 / 30;
  SoftState st = initial_state(ch, Eigen::Vector3d(0, 0.5, 0), Eigen::Vector3d(0, -30, 0), sp.dt_s);
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(ch.basis.r());
  const double cell = ch.lattice.cell_size_m;
  double deepest = 0, lowest_top = 1e9;
  Eigen::VectorXd x;
  for (int f = 0; f < 10; ++f) {
    reduced_step(ch, env, sp, u, st);
    node_positions(ch, st, x);
    double lo = 1e9, hi = -1e9;
    for (int j = 0; j < ch.lattice.nodes(); ++j) lo = std::min(lo, x[3 * j + 1]), hi = std::max(hi, x[3 * j + 1]);
    deepest = std::max(deepest, -lo);
    lowest_top = std::min(lowest_top, hi);
  }
  EXPECT_LT(deepest, 0.5 * cell);  // within the quarter-cell target, with slack for elasticity
  EXPECT_GT(lowest_top, 0.0);      // never entirely below the ground
  EXPECT_GT(st.c[1], -0.25 * cell);  // and it rests on top at the end
}
