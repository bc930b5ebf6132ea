#include "doc/paint_ops.h"

#include <algorithm>
#include <cmath>

namespace pliant::editor {

namespace {
inline uint8_t& at(geom::PaintedGrid& g, int i, int j) { return g.value[size_t(j) * g.n[0] + i]; }
inline uint8_t to_byte(double v) { return uint8_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }
}  // namespace

geom::PaintedGrid make_painted_grid(int w, int h) {
  geom::PaintedGrid g;
  g.dim = 2;
  g.n = {w, h, 1};
  g.value.assign(g.cells(), 0);
  return g;
}

geom::PaintedGrid painted_from_density(const std::vector<float>& density, int w, int h) {
  geom::PaintedGrid g = make_painted_grid(w, h);
  for (size_t c = 0; c < g.value.size() && c < density.size(); ++c) g.value[c] = to_byte(density[c]);
  return g;
}

void paint_dab(geom::PaintedGrid& g, double x, double y, const Brush& b) {
  const double r = std::max(0.5, b.radius);
  const double hard = std::clamp(b.hardness, 0.0, 1.0) * r;
  const int i0 = std::max(0, int(std::floor(x - r))), i1 = std::min(g.n[0] - 1, int(std::ceil(x + r)));
  const int j0 = std::max(0, int(std::floor(y - r))), j1 = std::min(g.n[1] - 1, int(std::ceil(y + r)));
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const double d = std::hypot(i + 0.5 - x, j + 0.5 - y);
      if (d >= r) continue;
      const double cov = (d <= hard ? 1.0 : (r - d) / (r - hard)) * std::clamp(b.strength, 0.0, 1.0);
      uint8_t& v = at(g, i, j);
      if (b.erase) v = uint8_t(std::lround(v * (1.0 - cov)));
      else v = std::max(v, to_byte(cov));
    }
}

void paint_segment(geom::PaintedGrid& g, double x0, double y0, double x1, double y1, const Brush& b) {
  const double len = std::hypot(x1 - x0, y1 - y0);
  const double step = std::max(0.25, 0.25 * b.radius);
  const int n = std::max(1, int(std::ceil(len / step)));
  for (int k = 1; k <= n; ++k) {
    const double t = double(k) / n;
    paint_dab(g, x0 + (x1 - x0) * t, y0 + (y1 - y0) * t, b);
  }
}

void fill_region(geom::PaintedGrid& g, int x, int y, uint8_t value, int tolerance) {
  const int w = g.n[0], h = g.n[1];
  if (x < 0 || y < 0 || x >= w || y >= h) return;
  const int seed = at(g, x, y);
  std::vector<uint8_t> seen(g.value.size(), 0);
  std::vector<int> stack{y * w + x};
  seen[size_t(y) * w + x] = 1;
  std::vector<int> region;
  while (!stack.empty()) {
    const int c = stack.back();
    stack.pop_back();
    region.push_back(c);
    const int i = c % w, j = c / w;
    const int nb[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
    for (const auto& q : nb) {
      if (q[0] < 0 || q[1] < 0 || q[0] >= w || q[1] >= h) continue;
      const int d = q[1] * w + q[0];
      if (seen[d] || std::abs(int(g.value[d]) - seed) > tolerance) continue;
      seen[d] = 1;
      stack.push_back(d);
    }
  }
  for (int c : region) g.value[c] = value;  // after the search: the fill never feeds itself
}

void fill_ellipse(geom::PaintedGrid& g, double x0, double y0, double x1, double y1, uint8_t value) {
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  const double rx = std::max(0.5, 0.5 * std::abs(x1 - x0)), ry = std::max(0.5, 0.5 * std::abs(y1 - y0));
  for (int j = 0; j < g.n[1]; ++j)
    for (int i = 0; i < g.n[0]; ++i) {
      const double u = (i + 0.5 - cx) / rx, v = (j + 0.5 - cy) / ry;
      if (u * u + v * v <= 1.0) at(g, i, j) = value;
    }
}

void fill_rectangle(geom::PaintedGrid& g, double x0, double y0, double x1, double y1, uint8_t value) {
  const double lx = std::min(x0, x1), hx = std::max(x0, x1), ly = std::min(y0, y1), hy = std::max(y0, y1);
  for (int j = 0; j < g.n[1]; ++j)
    for (int i = 0; i < g.n[0]; ++i)
      if (i + 0.5 >= lx && i + 0.5 <= hx && j + 0.5 >= ly && j + 0.5 <= hy) at(g, i, j) = value;
}

geom::PaintedGrid transform_grid(const geom::PaintedGrid& g, double dx, double dy, double scale) {
  geom::PaintedGrid out = make_painted_grid(g.n[0], g.n[1]);
  const int w = g.n[0], h = g.n[1];
  const double cx = 0.5 * w, cy = 0.5 * h, s = std::max(1e-3, scale);
  auto src = [&](int i, int j) -> double {
    if (i < 0 || j < 0 || i >= w || j >= h) return 0.0;
    return g.value[size_t(j) * w + i];
  };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      // Inverse map of the cell centre, then bilinear on source cell centres.
      const double x = (i + 0.5 - cx - dx) / s + cx - 0.5, y = (j + 0.5 - cy - dy) / s + cy - 0.5;
      const int xi = int(std::floor(x)), yi = int(std::floor(y));
      const double fx = x - xi, fy = y - yi;
      const double v = (1 - fy) * ((1 - fx) * src(xi, yi) + fx * src(xi + 1, yi)) +
                       fy * ((1 - fx) * src(xi, yi + 1) + fx * src(xi + 1, yi + 1));
      out.value[size_t(j) * w + i] = uint8_t(std::lround(std::clamp(v, 0.0, 255.0)));
    }
  return out;
}

void stamp_coverage(geom::PaintedGrid& g, const geom::CoverageImage& img, double x, double y,
                    double height) {
  if (img.width <= 0 || img.height <= 0 || height <= 0) return;
  const double width = height * img.width / img.height;
  const double left = x - 0.5 * width, bottom = y - 0.5 * height;
  for (int j = 0; j < g.n[1]; ++j)
    for (int i = 0; i < g.n[0]; ++i) {
      const double s = (i + 0.5 - left) / width, t = 1.0 - (j + 0.5 - bottom) / height;
      if (s < 0 || s > 1 || t < 0 || t > 1) continue;
      uint8_t& v = at(g, i, j);
      v = std::max(v, to_byte(img.sample(s, t)));
    }
}

uint8_t strength_byte(double strength) { return to_byte(strength); }

size_t painted_cell_count(const geom::PaintedGrid& g) {
  return size_t(std::count_if(g.value.begin(), g.value.end(), [](uint8_t v) { return v != 0; }));
}

}  // namespace pliant::editor
