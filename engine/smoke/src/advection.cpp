#include "advection.h"

#include <algorithm>
#include <cmath>

namespace pliant::smoke {
namespace {

// Grid-unit backtrace with the RK2 midpoint rule from p, whose velocity v0 the
// caller knows; clamped to the box when closed.
inline std::array<double, 3> backtrace(const MacGrid& g, const VelocitySampler& vel, double dt_h,
                                       std::array<double, 3> p, const std::array<double, 3>& v0) {
  auto clamp = [&](std::array<double, 3>& x) {
    if (g.periodic) return;
    for (int a = 0; a < g.dim; ++a) x[a] = x[a] >= 0.0 ? std::min(x[a], double(g.n[a])) : 0.0;
  };
  std::array<double, 3> mid = p;
  for (int a = 0; a < g.dim; ++a) mid[a] -= 0.5 * dt_h * v0[a];
  clamp(mid);
  const auto v1 = vel(mid[0], mid[1], mid[2]);
  for (int a = 0; a < g.dim; ++a) p[a] -= dt_h * v1[a];
  clamp(p);
  return p;
}

// stagger_axis < 0: cell-centred q (v0 = average of the two faces per axis);
// otherwise q is that face component (v0 along it is the face value itself, the
// other components are interpolated). Both skip a full velocity interpolation.
void sl_advect_array(const MacGrid& g, const FaceVelocity& vel, double dt, const FieldLayout& l,
                     int stagger_axis, const float* q_in, float* q_out) {
  const double dt_h = dt / g.h;
  const VelocitySampler sampler(g, vel);
  const float* comp[3] = {vel.u, vel.v, vel.w};
  const FieldLayout* layout[3] = {&sampler.lu, &sampler.lv, &sampler.lw};
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < l.size[2]; ++k)
    for (int j = 0; j < l.size[1]; ++j)
      for (int i = 0; i < l.size[0]; ++i) {
        const size_t e = l.index(i, j, k);
        const std::array<double, 3> p{i + l.offset[0], j + l.offset[1], k + l.offset[2]};
        std::array<double, 3> v0{0, 0, 0};
        if (stagger_axis < 0) {
          for (int a = 0; a < g.dim; ++a)
            v0[a] = 0.5 * (double(comp[a][g.face_lo(a, i, j, k)]) + comp[a][g.face_hi(a, i, j, k)]);
        } else {
          if (!g.periodic) {
            const int ia = stagger_axis == 0 ? i : (stagger_axis == 1 ? j : k);
            if (ia == 0 || ia == g.n[stagger_axis]) {
              q_out[e] = 0.0f;  // closed wall
              continue;
            }
          }
          for (int a = 0; a < g.dim; ++a)
            v0[a] = a == stagger_axis ? double(q_in[e]) : sample(comp[a], *layout[a], p[0], p[1], p[2]);
        }
        const std::array<double, 3> b = backtrace(g, sampler, dt_h, p, v0);
        q_out[e] = float(sample(q_in, l, b[0], b[1], b[2]));
      }
}

// What the flux of one upwind update needs, built once per call.
struct UpwindContext {
  const MacGrid& g;
  const FieldLayout& l;  // layout of the advected array
  bool cells;            // l is the cell layout: CV faces are the MAC faces
  int stagger;           // else: the axis of the advected face component
  FieldLayout face[3];
  const float* comp[3];
};

// Flux (per unit area, in q*m/s) through the control-volume face between element e
// at (i,j,k) and its +1 neighbour along `axis`; 0 where a closed box has no neighbour.
inline double upwind_flux(const UpwindContext& c, const float* q, int axis, int i, int j, int k) {
  std::array<int, 3> nb{i, j, k};
  nb[axis] += 1;
  if (nb[axis] == c.l.size[axis]) {
    if (!c.g.periodic) return 0.0;
    nb[axis] = 0;
  }
  // Advecting velocity at the CV face: the MAC face value for cells, interpolated
  // (the average of two faces) for the staggered momentum control volumes.
  double ua;
  if (c.cells) {
    ua = c.comp[axis][c.g.face_hi(axis, i, j, k)];
  } else if (axis == c.stagger) {
    // CV face at the cell centre between this face and the next of the same component.
    ua = 0.5 * (double(c.comp[axis][c.l.index(i, j, k)]) + c.comp[axis][c.l.index(nb[0], nb[1], nb[2])]);
  } else {
    // CV face on a cell edge: the two `axis` faces either side along the stagger
    // axis, at face index nb[axis] (wall elements never get here, so i-1 >= 0
    // unless periodic).
    const int a = c.stagger;
    std::array<int, 3> lo{i, j, k};
    lo[axis] = nb[axis];
    std::array<int, 3> hi = lo;
    lo[a] = lo[a] == 0 ? c.g.n[a] - 1 : lo[a] - 1;
    const FieldLayout& f = c.face[axis];
    ua = 0.5 * (double(c.comp[axis][f.index(lo[0], lo[1], lo[2])]) + c.comp[axis][f.index(hi[0], hi[1], hi[2])]);
  }
  const double up = ua > 0 ? q[c.l.index(i, j, k)] : q[c.l.index(nb[0], nb[1], nb[2])];
  return ua * up;
}

}  // namespace

void advect_semi_lagrangian_cells(const MacGrid& g, const FaceVelocity& vel, double dt,
                                  const float* q_in, float* q_out) {
  sl_advect_array(g, vel, dt, g.cell_layout(), -1, q_in, q_out);
}

void advect_semi_lagrangian_velocity(const MacGrid& g, const FaceVelocity& vel, double dt,
                                     FaceVelocityMut out) {
  sl_advect_array(g, vel, dt, g.face_layout(0), 0, vel.u, out.u);
  sl_advect_array(g, vel, dt, g.face_layout(1), 1, vel.v, out.v);
  if (g.dim == 3) sl_advect_array(g, vel, dt, g.face_layout(2), 2, vel.w, out.w);
}

int upwind_substeps(const MacGrid& g, const FaceVelocity& vel, double dt, int max_substeps) {
  const int nx = g.n[0], ny = g.n[1], nz = g.n[2];
  double worst = 0;  // largest sum of outgoing face speeds of a cell
#pragma omp parallel for collapse(2) schedule(static) reduction(max : worst)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        double out = std::max(0.0, double(vel.u[g.face_hi(0, i, j, k)])) +
                     std::max(0.0, -double(vel.u[g.face_lo(0, i, j, k)])) +
                     std::max(0.0, double(vel.v[g.face_hi(1, i, j, k)])) +
                     std::max(0.0, -double(vel.v[g.face_lo(1, i, j, k)]));
        if (g.dim == 3)
          out += std::max(0.0, double(vel.w[g.face_hi(2, i, j, k)])) +
                 std::max(0.0, -double(vel.w[g.face_lo(2, i, j, k)]));
        worst = std::max(worst, out);
      }
  const double courant = dt * worst / g.h;
  if (!(courant > 1.0)) return 1;  // also NaN-safe: NaN is caught by the caller's check
  return int(std::min<double>(max_substeps, std::ceil(courant)));
}

void upwind_step(const MacGrid& g, const FieldLayout& l, const FaceVelocity& vel, double dt,
                 float* q, float* scratch) {
  const double dt_h = dt / g.h;
  int stagger = -1;
  for (int a = 0; a < g.dim; ++a)
    if (l.offset[a] == 0.0) stagger = a;
  const UpwindContext ctx{g, l, stagger < 0, stagger, {g.face_layout(0), g.face_layout(1), g.face_layout(2)},
                          {vel.u, vel.v, vel.w}};
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < l.size[2]; ++k)
    for (int j = 0; j < l.size[1]; ++j)
      for (int i = 0; i < l.size[0]; ++i) {
        const size_t e = l.index(i, j, k);
        if (stagger >= 0 && !g.periodic) {
          const int ia = stagger == 0 ? i : (stagger == 1 ? j : k);
          if (ia == 0 || ia == g.n[stagger]) {
            scratch[e] = q[e];
            continue;
          }
        }
        double net = 0;  // sum over axes of F_hi - F_lo
        const std::array<int, 3> c{i, j, k};
        for (int a = 0; a < g.dim; ++a) {
          net += upwind_flux(ctx, q, a, i, j, k);
          std::array<int, 3> lo = c;
          lo[a] -= 1;
          if (lo[a] < 0) {
            if (!g.periodic) continue;  // closed wall: no inflow
            lo[a] = l.size[a] - 1;
          }
          net -= upwind_flux(ctx, q, a, lo[0], lo[1], lo[2]);
        }
        scratch[e] = float(q[e] - dt_h * net);
      }
  std::copy(scratch, scratch + l.count(), q);
}

int advect_upwind_cells(const MacGrid& g, const FaceVelocity& vel, double dt, float* q,
                        float* scratch) {
  const int ns = upwind_substeps(g, vel, dt);
  const FieldLayout l = g.cell_layout();
  for (int s = 0; s < ns; ++s) upwind_step(g, l, vel, dt / ns, q, scratch);
  return ns;
}

int advect_upwind_velocity(const MacGrid& g, const FaceVelocity& vel, double dt, FaceVelocityMut out,
                           float* scratch) {
  const int ns = upwind_substeps(g, vel, dt);
  float* comp[3] = {out.u, out.v, out.w};
  for (int a = 0; a < g.dim; ++a) {
    const FieldLayout l = g.face_layout(a);
    for (int s = 0; s < ns; ++s) upwind_step(g, l, vel, dt / ns, comp[a], scratch);
  }
  return ns;
}

}  // namespace pliant::smoke
