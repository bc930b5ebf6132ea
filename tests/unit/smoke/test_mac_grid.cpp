#include <gtest/gtest.h>

#include "mac_grid.h"
#include "smoke_test_util.h"

namespace pliant::smoke {
namespace {
using test::make_grid;

TEST(MacGrid, FaceCountsClosedAndPeriodic) {
  const MacGrid c = make_grid(3, {5, 6, 7}, false);
  EXPECT_EQ(c.face_count(0), 6u * 6 * 7);
  EXPECT_EQ(c.face_count(1), 5u * 7 * 7);
  EXPECT_EQ(c.face_count(2), 5u * 6 * 8);
  const MacGrid p = make_grid(3, {5, 6, 7}, true);
  EXPECT_EQ(p.face_count(0), 5u * 6 * 7);
  const MacGrid c2 = make_grid(2, {5, 6, 1}, false);
  EXPECT_EQ(c2.face_count(2), 0u);
  EXPECT_EQ(c2.face_count(1), 5u * 7);
  // The face on the high side of the last periodic cell is face 0.
  EXPECT_EQ(p.face_hi(0, 4, 2, 3), p.face_lo(0, 0, 2, 3));
  EXPECT_EQ(c.face_hi(0, 4, 2, 3), c.face_lo(0, 5, 2, 3));
}

// Trilinear sampling reproduces a linear function exactly inside the sample range.
TEST(MacGrid, SamplingIsExactForLinearFields) {
  const MacGrid g = make_grid(3, {6, 5, 4}, false);
  const FieldLayout l = g.face_layout(1);
  std::vector<float> q(l.count());
  auto f = [](double x, double y, double z) { return 0.5 + 0.25 * x - 0.125 * y + 0.0625 * z; };
  for (int k = 0; k < l.size[2]; ++k)
    for (int j = 0; j < l.size[1]; ++j)
      for (int i = 0; i < l.size[0]; ++i) q[l.index(i, j, k)] = float(f(i + 0.5, j, k + 0.5));
  for (double x : {0.5, 1.3, 3.77, 5.5})
    for (double y : {0.0, 0.2, 2.9, 5.0})
      for (double z : {0.5, 1.1, 3.5}) EXPECT_NEAR(sample(q.data(), l, x, y, z), f(x, y, z), 1e-6);
}

TEST(MacGrid, PeriodicSamplingWraps) {
  const MacGrid g = make_grid(2, {8, 4, 1}, true);
  const FieldLayout l = g.cell_layout();
  std::vector<float> q(l.count());
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 8; ++i) q[l.index(i, j, 0)] = float(i);
  // Halfway between the last cell (7) and the first (0) across the seam.
  EXPECT_NEAR(sample(q.data(), l, 8.0, 1.5, 0.5), 3.5, 1e-12);
  EXPECT_NEAR(sample(q.data(), l, 0.5 + 8 * 3, 1.5, 0.5), 0.0, 1e-12);
  EXPECT_NEAR(sample(q.data(), l, -0.5 + 0.25, 1.5, 0.5), 7 * 0.75, 1e-12);
}

// div(grad phi) with the face gradient equals the 5-point Laplacian.
TEST(MacGrid, DivergenceOfGradientIsLaplacian) {
  for (bool periodic : {false, true}) {
    const MacGrid g = make_grid(2, {7, 6, 1}, periodic, 0.5);
    test::Velocity vel(g);
    std::vector<double> phi(g.cells()), div(g.cells());
    for (size_t c = 0; c < phi.size(); ++c) phi[c] = std::sin(0.7 * double(c));
    subtract_gradient(g, phi.data(), -1.0, vel.mut());  // vel = +grad phi
    divergence(g, vel.view(), div.data());
    PoissonLevel L{2, g.n, periodic};
    std::vector<double> aphi(g.cells());
    poisson_apply(L, phi.data(), aphi.data());
    for (size_t c = 0; c < phi.size(); ++c) EXPECT_NEAR(div[c], -aphi[c] / (g.h * g.h), 1e-5) << c;
  }
}

TEST(MacGrid, CellCentredVelocityAveragesFaces) {
  const MacGrid g = make_grid(2, {3, 2, 1}, false);
  test::Velocity vel(g);
  for (size_t i = 0; i < vel.u.size(); ++i) vel.u[i] = float(i);
  for (size_t i = 0; i < vel.v.size(); ++i) vel.v[i] = float(10 * i);
  std::vector<float> out(g.cells() * 2);
  cell_centred_velocity(g, vel.view(), out.data());
  // Cell (1,1): u faces (1,1)=5 and (2,1)=6; v faces (1,1)=40 and (1,2)=70.
  EXPECT_FLOAT_EQ(out[g.cell(1, 1, 0) * 2 + 0], 5.5f);
  EXPECT_FLOAT_EQ(out[g.cell(1, 1, 0) * 2 + 1], 55.0f);
}

}  // namespace
}  // namespace pliant::smoke
