// The container walls on the FLIP grid: face open fractions and wall velocities
// per substep (build_solids), solid faces' velocities (set_solid_faces), the walls'
// signed distance (solid_sdf) and the particle push-out (push_out).
#include <algorithm>
#include <cmath>

#include "container_mesh.h"
#include "flip_grid.h"

namespace pliant::liquid {
namespace {

constexpr float kFarAway = 1e3f;

// A pose with its rotation precomputed: build_solids maps every face near a
// container into its frame each substep (same formula as Pose::to_local).
struct FramePose {
  double c, s;
  Vec3 p;
  explicit FramePose(const Pose& q) : c(std::cos(q.tilt_rad)), s(std::sin(q.tilt_rad)), p(q.position_m) {}
  Vec3 to_local(const Vec3& w) const {
    const double x = w[0] - p[0], y = w[1] - p[1];
    return {c * x - s * y, s * x + c * y, w[2] - p[2]};
  }
};

}  // namespace

Vec3 source_point_velocity(const LiquidModel& m, double t, const Pose& pose, const Vec3& x) {
  Vec3 lin;
  double tilt_rate;
  m.source_path.velocity(t, &lin, &tilt_rate);
  const double wz = -tilt_rate;  // world rotation is by -tilt about z
  return {lin[0] - wz * (x[1] - pose.position_m[1]), lin[1] + wz * (x[0] - pose.position_m[0]), lin[2]};
}

// Reach of a container from its origin (bounding sphere radius).
double container_reach(const ContainerShape& c) {
  if (c.type == ContainerShape::Mesh) return c.mesh->reach_m;
  const double r = c.radius_m + c.wall_m + (c.type == ContainerShape::Cup ? 0.6 * c.height_m : 0.0);
  return std::sqrt(r * r + std::max(c.depth_m, r) * std::max(c.depth_m, r) + c.height_m * c.height_m) + c.wall_m;
}

// Face open fractions and solid velocities for the source (and a moving
// target) at time t. A static target's distances are computed once and cached.
void build_solids(const FlipGrid& g, const LiquidModel& m, FlipWorkspace& w, double t) {
  const bool static_target = m.has_target && !target_moves(m);
  const bool moving_target = m.has_target && !static_target;
  if (w.solids_fixed) return;  // nothing moves: last substep's fractions hold
  if (!w.static_ready) {
    for (int c = 0; c < g.dim; ++c) {
      const auto d = g.face_dims(c);
      w.static_phi[c].assign(g.faces(c), kFarAway);
      if (!static_target) continue;
#pragma omp parallel for collapse(2) schedule(static) if (worth_threads(g.cells()))
      for (int k = 0; k < d[2]; ++k)
        for (int j = 0; j < d[1]; ++j)
          for (int i = 0; i < d[0]; ++i)
            w.static_phi[c][i + d[0] * (j + d[1] * k)] =
                float(m.target.shape.wall_sdf(m.target.pose.to_local(g.face_pos(c, i, j, k)), g.dim));
    }
    w.static_ready = true;
  }
  const Pose pose = source_pose_at(m, t);
  const FramePose sframe(pose);
  Vec3 slin;  // source rigid motion at t: linear velocity and angular rate about z
  double tilt_rate;
  m.source_path.velocity(t, &slin, &tilt_rate);
  const double wz = -tilt_rate;  // world rotation is by -tilt about z
  const double reach = container_reach(m.source.shape) + 2 * g.h;
  const Pose tpose = target_pose_at(m, t);
  const FramePose tframe(tpose);
  const double treach = container_reach(m.target.shape) + 2 * g.h;
  auto near_target = [&](const Vec3& x) {
    const double dx = x[0] - tpose.position_m[0], dy = x[1] - tpose.position_m[1], dz = x[2] - tpose.position_m[2];
    return moving_target && dx * dx + dy * dy + dz * dz < treach * treach;
  };
  for (int c = 0; c < g.dim; ++c) {
    const auto d = g.face_dims(c);
    w.open[c].resize(g.faces(c));
    w.solid_vel[c].resize(g.faces(c));
    int lo[3] = {0, 0, 0}, hi[3] = {d[0] - 1, d[1] - 1, d[2] - 1};
#pragma omp parallel for collapse(2) schedule(static) if (worth_threads_light(g.cells()))
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          const int f = i + d[0] * (j + d[1] * k);
          const int idx[3] = {i, j, k};
          if (idx[c] == 0 || idx[c] == d[c] - 1) {  // domain wall
            w.open[c][f] = 0, w.solid_vel[c][f] = 0;
            continue;
          }
          double phi = w.static_phi[c][f];
          float sv = 0;
          const Vec3 x = g.face_pos(c, i, j, k);
          if (near_target(x)) {
            const double pt = m.target.shape.wall_sdf(tframe.to_local(x), g.dim);
            if (pt < phi) phi = pt, sv = float(m.target_velocity_mps[c]);
          }
          if (m.has_source) {
            const double dx = x[0] - pose.position_m[0], dy = x[1] - pose.position_m[1],
                         dz = x[2] - pose.position_m[2];
            if (dx * dx + dy * dy + dz * dz < reach * reach) {
              const double ps = m.source.shape.wall_sdf(sframe.to_local(x), g.dim);
              if (ps < phi) {
                phi = ps;
                sv = float(c == 0 ? slin[0] - wz * (x[1] - pose.position_m[1])
                           : c == 1 ? slin[1] + wz * (x[0] - pose.position_m[0])
                                    : slin[2]);
              }
            }
          }
          w.open[c][f] = float(std::clamp(0.5 + phi / g.h, 0.0, 1.0));
          w.solid_vel[c][f] = sv;
        }
    (void)lo, (void)hi;
  }
  // Cells whose centre lies in a wall are solid: faces touching them are closed
  // (open = 0, u = q), so the pressure solve never sees them as air.
  if (w.static_phi_cell.empty()) {
    w.static_phi_cell.assign(g.cells(), kFarAway);
    if (static_target)
      for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
          for (int i = 0; i < g.nx; ++i)
            w.static_phi_cell[g.cell(i, j, k)] =
                float(m.target.shape.wall_sdf(m.target.pose.to_local(g.cell_pos(i, j, k)), g.dim));
  }
  w.solid_cell.resize(g.cells());
#pragma omp parallel for collapse(2) schedule(static) if (worth_threads_light(g.cells()))
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const int ci = g.cell(i, j, k);
        double phi = w.static_phi_cell[ci];
        const Vec3 x = g.cell_pos(i, j, k);
        if (near_target(x)) phi = std::min(phi, m.target.shape.wall_sdf(tframe.to_local(x), g.dim));
        if (m.has_source) {
          const double dx = x[0] - pose.position_m[0], dy = x[1] - pose.position_m[1], dz = x[2] - pose.position_m[2];
          if (dx * dx + dy * dy + dz * dz < reach * reach)
            phi = std::min(phi, m.source.shape.wall_sdf(sframe.to_local(x), g.dim));
        }
        w.solid_cell[ci] = phi < 0;
      }
  const int dims[3] = {g.nx, g.ny, g.nz};
  for (int c = 0; c < g.dim; ++c) {
    const auto d = g.face_dims(c);
#pragma omp parallel for collapse(2) schedule(static) if (worth_threads_light(g.cells()))
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          const int idx[3] = {i, j, k};
          if (idx[c] == 0 || idx[c] == dims[c]) continue;
          int t[3] = {i, j, k};
          const int hi_cell = g.cell(t[0], t[1], t[2]);
          t[c] -= 1;
          const int lo_cell = g.cell(t[0], t[1], t[2]);
          if (w.solid_cell[hi_cell] || w.solid_cell[lo_cell]) w.open[c][i + d[0] * (j + d[1] * k)] = 0;
        }
  }
  w.solids_fixed = !m.has_source && !moving_target;
}

void set_solid_faces(const FlipGrid& g, FlipWorkspace& w) {
  for (int c = 0; c < g.dim; ++c) {
    const int n = g.faces(c);
#pragma omp parallel for schedule(static) if (worth_threads_light(g.cells()))
    for (int f = 0; f < n; ++f)
      if (w.open[c][f] <= 0) w.vel[c][f] = w.solid_vel[c][f];
  }
}

// Moves x out of solids (and into the domain), removing the inward relative
// normal velocity.
void push_out(const FlipGrid& g, const LiquidModel& m, const Pose& pose, const Pose& tpose, double t, float* x,
              float* v) {
  const double margin = 0.25 * g.h;
  Vec3 p{x[0], x[1], g.dim == 3 ? x[2] : 0.0};
  bool src = false;
  const double d = solid_sdf(m, pose, tpose, p, &src);
  if (d < margin) {
    const double e = 0.1 * g.h;
    Vec3 n{0, 0, 0};
    for (int a = 0; a < g.dim; ++a) {
      Vec3 xp = p, xm = p;
      xp[a] += e, xm[a] -= e;
      bool dummy;
      n[a] = solid_sdf(m, pose, tpose, xp, &dummy) - solid_sdf(m, pose, tpose, xm, &dummy);
    }
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 1e-12) {
      for (int a = 0; a < 3; ++a) n[a] /= len;
      for (int a = 0; a < g.dim; ++a) p[a] += (margin - d) * n[a];
      const Vec3 sv = src ? source_point_velocity(m, t, pose, p) : m.target_velocity_mps;
      double vn = 0;
      for (int a = 0; a < g.dim; ++a) vn += (v[a] - sv[a]) * n[a];
      if (vn < 0)
        for (int a = 0; a < g.dim; ++a) v[a] -= float(vn * n[a]);
    }
  }
  const double hi[3] = {g.lo[0] + g.nx * g.h, g.lo[1] + g.ny * g.h, g.lo[2] + g.nz * g.h};
  for (int a = 0; a < g.dim; ++a) {
    if (p[a] < g.lo[a] + margin) p[a] = g.lo[a] + margin, v[a] = std::max(v[a], 0.f);
    if (p[a] > hi[a] - margin) p[a] = hi[a] - margin, v[a] = std::min(v[a], 0.f);
  }
  for (int a = 0; a < g.dim; ++a) x[a] = float(p[a]);
}

double solid_sdf(const LiquidModel& m, const Pose& source_pose, const Pose& target_pose, const Vec3& x,
                 bool* source_closest) {
  double d = 1e30;
  *source_closest = false;
  if (m.has_target) d = m.target.shape.wall_sdf(target_pose.to_local(x), m.dim);
  if (m.has_source) {
    const double ds = m.source.shape.wall_sdf(source_pose.to_local(x), m.dim);
    if (ds < d) d = ds, *source_closest = true;
  }
  return d;
}

}  // namespace pliant::liquid
