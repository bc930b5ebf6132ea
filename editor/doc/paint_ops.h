// Painting on a keyframe grid (geom::PaintedGrid, 2D): the operations behind the
// keyframe canvas's tools. Coordinates are in cells with +y up, as the grid is
// stored (cell (i, j) covers [i, i+1] x [j, j+1]); values are 0..255 (density 0..1).
// All operations are pure functions of the grid, so a stroke can be replayed and
// an undo restores the bytes exactly.
#pragma once
#include <cstdint>
#include <vector>

#include "pliant/geom/coverage_image.h"
#include "pliant/geom/painted_grid.h"

namespace pliant::editor {

struct Brush {
  double radius = 4;     // cells
  double hardness = 0.7; // fraction of the radius at full strength; linear falloff outside
  bool erase = false;
  double strength = 1.0; // density painted at full coverage (0..1); erase removes this fraction
};

// An empty w x h grid.
geom::PaintedGrid make_painted_grid(int w, int h);
// Density values (clamped to 0..1) -> bytes; cells x-fastest, row 0 at the bottom.
geom::PaintedGrid painted_from_density(const std::vector<float>& density, int w, int h);

// One round dab at (x, y): paint raises cells to strength x the brush's coverage
// (max), erase multiplies them by 1 - strength x coverage; coverage is 1 inside
// hardness * radius, falling linearly to 0 at the radius.
void paint_dab(geom::PaintedGrid& g, double x, double y, const Brush& b);
// Dabs from (x0, y0) to (x1, y1) a quarter radius apart (a stroke segment); the
// first point is not repeated so a stroke is the union of its dabs.
void paint_segment(geom::PaintedGrid& g, double x0, double y0, double x1, double y1, const Brush& b);
// Flood fill (4-connected) of the cells whose value is within `tolerance` of the
// seed cell's, with `value`. The shape tools replace (not max): a fill or shape
// at a low strength also lowers denser cells to that value.
void fill_region(geom::PaintedGrid& g, int x, int y, uint8_t value, int tolerance = 32);
// The axis-aligned ellipse / rectangle spanned by two corners, filled with `value`
// (cell centres inside).
void fill_ellipse(geom::PaintedGrid& g, double x0, double y0, double x1, double y1, uint8_t value);
void fill_rectangle(geom::PaintedGrid& g, double x0, double y0, double x1, double y1, uint8_t value);
// The whole keyframe moved by (dx, dy) cells and scaled by `scale` about the grid
// centre; bilinear, empty outside.
geom::PaintedGrid transform_grid(const geom::PaintedGrid& g, double dx, double dy, double scale);
// A coverage image (text, an imported picture; row 0 on top) stamped with its
// centre at (x, y) and a height of `height` cells (width by its aspect ratio),
// composited with max.
void stamp_coverage(geom::PaintedGrid& g, const geom::CoverageImage& img, double x, double y,
                    double height);
// Number of non-zero cells (tests, "empty keyframe" warnings).
size_t painted_cell_count(const geom::PaintedGrid& g);
// The byte a shape tool writes for a strength 0..1: round(255 strength), clamped.
uint8_t strength_byte(double strength);

}  // namespace pliant::editor
