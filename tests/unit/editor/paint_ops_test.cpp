// Keyframe canvas operations on painted grids (editor/doc/paint_ops).
#include "doc/paint_ops.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pliant::editor {
namespace {

double mass(const geom::PaintedGrid& g) {
  double s = 0;
  for (uint8_t v : g.value) s += v / 255.0;
  return s;
}

TEST(PaintOps, HardDabCoversTheDiscArea) {
  geom::PaintedGrid g = make_painted_grid(64, 64);
  paint_dab(g, 32, 32, Brush{10, 1.0, false});
  // Cell centres inside a radius-10 disc: pi r^2 ~ 314 (lattice count 317).
  EXPECT_NEAR(double(painted_cell_count(g)), M_PI * 100, 12);
  EXPECT_EQ(g.value[32 * 64 + 32], 255);
  EXPECT_EQ(g.value[32 * 64 + 44], 0);
}

TEST(PaintOps, SoftDabFallsOffLinearly) {
  geom::PaintedGrid g = make_painted_grid(64, 64);
  paint_dab(g, 32.5, 32.5, Brush{10, 0.0, false});
  // Coverage (r - d) / r at the cell centre 5 cells from the dab centre.
  EXPECT_NEAR(g.value[32 * 64 + 37], 255 * 0.5, 1);
  EXPECT_EQ(g.value[32 * 64 + 32], 255);
}

TEST(PaintOps, EraserUndoesPaintAndStrokeIsTheUnionOfDabs) {
  geom::PaintedGrid g = make_painted_grid(48, 48);
  Brush b{3, 1.0, false};
  paint_segment(g, 5, 24, 40, 24, b);
  for (int x = 6; x <= 40; ++x) EXPECT_EQ(g.value[24 * 48 + x], 255) << x;  // no gaps along the stroke
  EXPECT_EQ(g.value[30 * 48 + 20], 0);
  b.erase = true;
  b.radius = 6;
  paint_segment(g, 0, 24, 47, 24, b);
  EXPECT_EQ(painted_cell_count(g), 0u);
}

TEST(PaintOps, FillStopsAtARing) {
  geom::PaintedGrid g = make_painted_grid(40, 40);
  fill_ellipse(g, 5, 5, 35, 35, 255);
  fill_ellipse(g, 9, 9, 31, 31, 0);  // a ring
  const size_t ring = painted_cell_count(g);
  fill_region(g, 20, 20, 255);  // fills the hole only
  const size_t filled = painted_cell_count(g);
  geom::PaintedGrid disc = make_painted_grid(40, 40);
  fill_ellipse(disc, 5, 5, 35, 35, 255);
  EXPECT_GT(filled, ring);
  EXPECT_EQ(filled, painted_cell_count(disc));
  EXPECT_EQ(g.value[0], 0);  // the outside stayed empty
}

TEST(PaintOps, RectangleAndEllipseAreas) {
  geom::PaintedGrid g = make_painted_grid(50, 50);
  fill_rectangle(g, 10, 10, 30, 20, 200);
  EXPECT_EQ(painted_cell_count(g), 20u * 10u);
  geom::PaintedGrid e = make_painted_grid(100, 100);
  fill_ellipse(e, 10, 30, 90, 70, 255);  // semi-axes 40 and 20
  EXPECT_NEAR(double(painted_cell_count(e)), M_PI * 40 * 20, 30);
}

TEST(PaintOps, StrengthSetsTheDensityTheToolsPaint) {
  EXPECT_EQ(strength_byte(1.0), 255);
  EXPECT_EQ(strength_byte(0.5), 128);  // round(127.5)
  EXPECT_EQ(strength_byte(-1.0), 0);
  // Brush: cells raised to strength x coverage (max with what is there).
  geom::PaintedGrid g = make_painted_grid(32, 32);
  paint_dab(g, 16, 16, Brush{4, 1.0, false, 0.5});
  EXPECT_EQ(g.value[16 * 32 + 16], 128);
  g.value[17 * 32 + 16] = 200;
  paint_dab(g, 16, 16, Brush{4, 1.0, false, 0.5});
  EXPECT_EQ(g.value[17 * 32 + 16], 200) << "painting never lowers a denser cell";
  // Eraser at strength 0.5 removes half.
  paint_dab(g, 16, 16, Brush{4, 1.0, true, 0.5});
  EXPECT_EQ(g.value[16 * 32 + 16], 64);
  EXPECT_EQ(g.value[17 * 32 + 16], 100);
  // Strength 1 is the full-strength brush bit for bit.
  geom::PaintedGrid a = make_painted_grid(32, 32), b = a;
  paint_segment(a, 3, 4, 25, 20, Brush{3.5, 0.3, false});
  paint_segment(b, 3, 4, 25, 20, Brush{3.5, 0.3, false, 1.0});
  EXPECT_EQ(a.value, b.value);
}

TEST(PaintOps, MoveByWholeCellsIsExactAndScaleKeepsTheCentre) {
  geom::PaintedGrid g = make_painted_grid(32, 32);
  fill_rectangle(g, 4, 4, 10, 12, 255);
  geom::PaintedGrid m = transform_grid(g, 5, 3, 1.0);
  EXPECT_EQ(painted_cell_count(m), painted_cell_count(g));
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i) {
      const uint8_t want = (i >= 9 && i < 15 && j >= 7 && j < 15) ? 255 : 0;
      ASSERT_EQ(m.value[j * 32 + i], want) << i << "," << j;
    }
  geom::PaintedGrid c = make_painted_grid(64, 64);
  fill_ellipse(c, 24, 24, 40, 40, 255);
  geom::PaintedGrid s = transform_grid(c, 0, 0, 2.0);
  EXPECT_NEAR(mass(s) / mass(c), 4.0, 0.25);  // area scales by s^2
  EXPECT_EQ(s.value[32 * 64 + 32], 255);
}

TEST(PaintOps, StampPlacesACoverageImageWithRowZeroOnTop) {
  geom::CoverageImage img;
  img.width = 2;
  img.height = 2;
  img.value = {1, 1, 0, 0};  // top row full
  geom::PaintedGrid g = make_painted_grid(20, 20);
  stamp_coverage(g, img, 10, 10, 10);
  // Cells above the centre (larger y) are painted, below are not.
  EXPECT_GT(g.value[13 * 20 + 10], 200);
  EXPECT_LT(g.value[7 * 20 + 10], 50);
}

}  // namespace
}  // namespace pliant::editor
