// Simplified dynamic model (section 2.5): lookup tables and the outflow /
// ballistic-parcel integration. See simplified_model.h for the equations.
#include "pliant/liquid/simplified_model.h"

#include <algorithm>
#include <cmath>

namespace pliant::liquid {
namespace {

struct Voxels {
  std::vector<Vec3> centres;  // cavity below the opening
  double cell_volume = 0;
};

Voxels voxelise(const ContainerShape& c, int dim) {
  const double half_x = c.radius_m, half_z = dim == 3 ? std::max(c.depth_m, c.radius_m) : 0;
  const double v = dim == 3 ? std::min(c.radius_m, c.depth_m) / 12 : c.radius_m / 24;
  Voxels out;
  out.cell_volume = std::pow(v, dim);
  const int nx = int(std::ceil(2 * half_x / v)), ny = int(std::ceil(c.height_m / v));
  const int nz = dim == 3 ? int(std::ceil(2 * half_z / v)) : 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Vec3 p{-half_x + (i + 0.5) * v, (j + 0.5) * v, dim == 3 ? -half_z + (k + 0.5) * v : 0.0};
        if (c.in_cavity(p, dim)) out.centres.push_back(p);
      }
  return out;
}

// Points of the opening plane y = height (2D: a segment) and their area element.
std::vector<Vec3> opening_points(const ContainerShape& c, int dim, double* dA) {
  std::vector<Vec3> pts;
  const double ro = c.opening_radius();
  const double y = c.height_m - 1e-6;
  if (dim == 2) {
    const int n = 96;
    *dA = 2 * ro / n;
    for (int i = 0; i < n; ++i) pts.push_back({-ro + (i + 0.5) * 2 * ro / n, y, 0});
    return pts;
  }
  const double hz = c.type == ContainerShape::Bottle ? ro : std::max(c.depth_m, ro);
  const int n = 40;
  *dA = (2 * ro / n) * (2 * hz / n);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < n; ++i) {
      const Vec3 p{-ro + (i + 0.5) * 2 * ro / n, y, -hz + (k + 0.5) * 2 * hz / n};
      if (c.in_extended_cavity(p, dim)) pts.push_back(p);
    }
  return pts;
}

}  // namespace

OutflowTables build_outflow_tables(const ContainerShape& c, int dim, double g, double max_theta, int n_theta,
                                   int n_vol) {
  OutflowTables t;
  t.dim = dim, t.n_theta = n_theta, t.n_vol = n_vol, t.max_theta = max_theta, t.g = g;
  const Voxels vox = voxelise(c, dim);
  size_t below = 0;
  for (const Vec3& p : vox.centres) below += p[1] < c.height_m;
  t.capacity = below * vox.cell_volume;
  double dA = 0;
  const std::vector<Vec3> open = opening_points(c, dim, &dA);
  t.dh.resize(n_theta * n_vol), t.area.resize(n_theta * n_vol), t.weir.resize(n_theta * n_vol);
  t.vmax.resize(n_theta);
  std::vector<double> z(vox.centres.size()), zo(open.size());
  for (int it = 0; it < n_theta; ++it) {
    const double th = max_theta * it / (n_theta - 1);
    const double ux = -std::sin(th), uy = std::cos(th);  // world up in the container frame
    for (size_t i = 0; i < z.size(); ++i) z[i] = ux * vox.centres[i][0] + uy * vox.centres[i][1];
    std::sort(z.begin(), z.end());
    double lip = 1e30;
    for (size_t i = 0; i < open.size(); ++i) zo[i] = ux * open[i][0] + uy * open[i][1], lip = std::min(lip, zo[i]);
    // Volume held below the lip.
    t.vmax[it] = double(std::lower_bound(z.begin(), z.end(), lip) - z.begin()) * vox.cell_volume;
    for (int iv = 0; iv < n_vol; ++iv) {
      const double vol = t.capacity * iv / (n_vol - 1);
      // Water level: the height below which `vol` of voxels lie (bisection on the
      // sorted heights, linear between neighbours).
      const double k = vol / vox.cell_volume;
      double level;
      if (k <= 0) level = z.front();
      else if (k >= z.size() - 1) level = z.back();
      else {
        const size_t k0 = size_t(k);
        level = z[k0] + (k - k0) * (z[k0 + 1] - z[k0]);
      }
      double a = 0, w = 0;
      for (double zp : zo)
        if (zp < level) a += dA, w += std::sqrt(2 * g * (level - zp)) * dA;
      t.dh[it * n_vol + iv] = level - lip;
      t.area[it * n_vol + iv] = a;
      t.weir[it * n_vol + iv] = w;
    }
  }
  return t;
}

double OutflowTables::lookup(const std::vector<double>& tab, double theta, double vol) const {
  const double ft = std::clamp(theta / max_theta, 0.0, 1.0) * (n_theta - 1);
  const double fv = std::clamp(vol / capacity, 0.0, 1.0) * (n_vol - 1);
  const int i0 = std::min(int(ft), n_theta - 2), j0 = std::min(int(fv), n_vol - 2);
  const double a = ft - i0, b = fv - j0;
  auto at = [&](int i, int j) { return tab[i * n_vol + j]; };
  return (1 - a) * ((1 - b) * at(i0, j0) + b * at(i0, j0 + 1)) + a * ((1 - b) * at(i0 + 1, j0) + b * at(i0 + 1, j0 + 1));
}

double OutflowTables::max_volume(double theta) const {
  const double ft = std::clamp(theta / max_theta, 0.0, 1.0) * (n_theta - 1);
  const int i0 = std::min(int(ft), n_theta - 2);
  const double a = ft - i0;
  return (1 - a) * vmax[i0] + a * vmax[i0 + 1];
}

SimplifiedResult simulate_simplified(const LiquidModel& m, const OutflowTables& t, const Trajectory& path,
                                     double duration_s, double cd, double dt) {
  const ContainerShape& c = m.source.shape;
  const double g = t.g;
  double vol0 = m.fill_fraction * t.capacity;
  if (c.type == ContainerShape::Bottle) vol0 = std::min(vol0, t.capacity);
  double vol = vol0, in = 0, out = 0, collision = 0;
  const double ro = c.opening_radius();
  const double height = m.target.shape.height_m;
  // The stream has a width and the model is coarse: count a parcel as caught
  // only when it lands well inside the opening.
  const double probe = 0.3 * m.target.shape.opening_radius();
  const double reach = m.target.shape.radius_m + m.target.shape.wall_m + 0.01;
  const int steps = int(std::ceil(duration_s / dt));
  for (int s = 0; s < steps; ++s) {
    const double time = s * dt;
    const Pose pose = path.at(time);
    const Pose tp = target_pose_at(m, time);  // FOLLOW: the target moves
    const double rim = tp.position_m[1] + height;
    Vec3 lin;
    double rate;
    path.velocity(time, &lin, &rate);
    // Robot-side penalties: the source must stay above the target's rim over it.
    for (double sx : {-1.0, 1.0})
      for (double ly : {-c.wall_m, c.height_m}) {
        const Vec3 corner = pose.to_world({sx * (c.radius_m + c.wall_m), ly, 0});
        const double dx = corner[0] - tp.position_m[0];
        if (std::abs(dx) < reach && corner[1] < rim + 0.01) collision += std::pow(rim + 0.01 - corner[1], 2) * dt;
        if (corner[1] < m.domain_min_m[1]) collision += std::pow(m.domain_min_m[1] - corner[1], 2) * dt;
      }
    if (vol <= 0) continue;
    const double theta = pose.tilt_rad;
    const double w = t.lookup(t.weir, theta, vol);
    if (w <= 0) continue;
    const double dv = std::min(vol, cd * w * dt);
    vol -= dv;
    const double a = std::max(1e-12, t.lookup(t.area, theta, vol + dv));
    const double speed = cd * w / a;  // Q = A v: the fitted Cd scales the speed too
    const Vec3 lip = pose.to_world({ro + 0.5 * c.wall_m, c.height_m, 0});
    const double wz = -rate;
    Vec3 v{lin[0] - wz * (lip[1] - pose.position_m[1]), lin[1] + wz * (lip[0] - pose.position_m[0]), lin[2]};
    const double half_pi = 1.57079632679489662;
    const double dx = theta < half_pi ? 1.0 : std::sin(theta), dy = theta < half_pi ? 0.0 : std::cos(theta);
    v[0] += speed * dx, v[1] += speed * dy;
    // Ballistic flight to the rim height: y0 + vy t - g t^2 / 2 = rim.
    const double disc = v[1] * v[1] + 2 * g * (lip[1] - rim);
    bool landed_in = false;
    if (disc >= 0) {
      const double tl = (v[1] + std::sqrt(disc)) / g;
      if (tl >= 0) {
        const Vec3 land{lip[0] + v[0] * tl, rim - 1e-4, lip[2] + v[2] * tl};
        landed_in = true;
        const Pose tl_pose = target_pose_at(m, time + tl);  // where the target is on landing
        for (double off : {-probe, probe}) {
          const Vec3 q{land[0] + off, land[1], land[2]};
          landed_in = landed_in && m.target.shape.in_extended_cavity(tl_pose.to_local(q), m.dim);
        }
      }
    }
    (landed_in ? in : out) += dv;
  }
  SimplifiedResult r;
  r.transferred = in / vol0;
  r.spilled = out / vol0;
  r.remaining = vol / vol0;
  r.collision = collision;
  return r;
}

}  // namespace pliant::liquid
