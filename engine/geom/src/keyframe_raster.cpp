// Analytic shapes and placed coverage images rasterised with supersampling: each
// cell averages ss^dim point samples (inside tests at the sample points).
#include "pliant/geom/keyframe_raster.h"

#include <cmath>
#include <numbers>

namespace pliant::geom {
namespace {

// Calls inside(x, y, z) (metres) at ss^dim sub-samples of every cell and stores the
// fraction that is inside (or the mean of a value in [0,1]).
template <class F>
std::vector<float> raster(const RasterGrid& g, int ss, F value) {
  ss = std::max(1, ss);
  const int nz = g.dim == 3 ? g.n[2] : 1;
  const int ssz = g.dim == 3 ? ss : 1;
  std::vector<float> out(g.cells(), 0.0f);
  const double h = g.cell_size_m, sub = h / ss;
  const double norm = 1.0 / (double(ss) * ss * ssz);
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i) {
        double acc = 0;
        for (int c = 0; c < ssz; ++c)
          for (int b = 0; b < ss; ++b)
            for (int a = 0; a < ss; ++a) {
              const double x = i * h + (a + 0.5) * sub, y = j * h + (b + 0.5) * sub;
              const double z = g.dim == 3 ? k * h + (c + 0.5) * sub : 0.0;
              acc += value(x, y, z);
            }
        out[i + size_t(g.n[0]) * (j + size_t(g.n[1]) * k)] = float(acc * norm);
      }
  return out;
}

// Point (metres) in the placement's local frame (inverse rotation R^T, then /scale).
struct LocalFrame {
  explicit LocalFrame(const Placement& p) : p(p), R(placement_rotation(p)) {}
  std::array<double, 3> operator()(double x, double y, double z) const {
    const double d[3] = {x - p.center_m[0], y - p.center_m[1], z - p.center_m[2]};
    std::array<double, 3> q;
    for (int a = 0; a < 3; ++a) q[a] = (R[0][a] * d[0] + R[1][a] * d[1] + R[2][a] * d[2]) / p.scale;
    return q;
  }
  Placement p;
  Rotation3 R;
};

}  // namespace

Rotation3 placement_rotation(const Placement& p) {
  const auto& v = p.rotation_axis;
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(len > 0)) throw GeomError("rotation_axis must not be zero");
  const double k[3] = {v[0] / len, v[1] / len, v[2] / len};
  const double a = p.rotation_deg * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
  // R = c I + s [k]x + (1 - c) k k^T
  Rotation3 R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R[i][j] = (i == j ? c : 0.0) + (1 - c) * k[i] * k[j];
  R[0][1] -= s * k[2], R[0][2] += s * k[1];
  R[1][0] += s * k[2], R[1][2] -= s * k[0];
  R[2][0] -= s * k[1], R[2][1] += s * k[0];
  return R;
}

std::vector<float> raster_sphere(const RasterGrid& g, const Placement& p, double radius_m, int supersample) {
  const LocalFrame L(p);
  const double r2 = radius_m * radius_m;
  return raster(g, supersample, [&](double x, double y, double z) {
    const auto q = L(x, y, z);
    const double d2 = q[0] * q[0] + q[1] * q[1] + (g.dim == 3 ? q[2] * q[2] : 0.0);
    return d2 <= r2 ? 1.0 : 0.0;
  });
}

std::vector<float> raster_box(const RasterGrid& g, const Placement& p, const std::array<double, 3>& half_size_m,
                              int supersample) {
  const LocalFrame L(p);
  return raster(g, supersample, [&](double x, double y, double z) {
    const auto q = L(x, y, z);
    bool in = std::abs(q[0]) <= half_size_m[0] && std::abs(q[1]) <= half_size_m[1];
    if (g.dim == 3) in = in && std::abs(q[2]) <= half_size_m[2];
    return in ? 1.0 : 0.0;
  });
}

std::vector<float> raster_image(const RasterGrid& g, const CoverageImage& img, const Placement& p,
                                double height_m, double depth_m, int supersample) {
  const LocalFrame L(p);
  const double H = height_m, W = height_m * img.width / std::max(1, img.height);
  return raster(g, supersample, [&](double x, double y, double z) {
    const auto q = L(x, y, z);
    if (g.dim == 3 && std::abs(q[2]) > 0.5 * depth_m) return 0.0;
    return img.sample(q[0] / W + 0.5, 0.5 - q[1] / H);
  });
}

double raster_measure(const RasterGrid& g, const std::vector<float>& density) {
  double s = 0;
  for (float v : density) s += v;
  return s * std::pow(g.cell_size_m, g.dim);
}

}  // namespace pliant::geom
