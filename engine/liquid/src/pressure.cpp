// Pressure projection: variational cut-face weights (Batty, Bertails, Bridson
// 2007) for solids, ghost-fluid Dirichlet p = 0 at the free surface (Gibou et al.
// 2002), solved by PCG with a MIC(0) preconditioner (Bridson, "Fluid Simulation
// for Computer Graphics", 2nd ed., ch. 5). Unknowns are q = dt p / (rho h), so
// the face update is u -= q_hi - q_lo.
#include <algorithm>
#include <cmath>

#include "flip_grid.h"

namespace pliant::liquid {
namespace {

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  const int n = int(a.size());
#pragma omp parallel for schedule(static) reduction(+ : s) if (n > (1 << 19))
  for (int i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

// Face index of component c on the low (side 0) or high (side 1) side of cell (i,j,k).
inline int face_of(const FlipGrid& g, int c, int i, int j, int k, int side) {
  const auto d = g.face_dims(c);
  if (c == 0) i += side;
  if (c == 1) j += side;
  if (c == 2) k += side;
  return i + d[0] * (j + d[1] * k);
}

inline double ghost_theta(double phi_in, double phi_out) {
  if (phi_in < 0 && phi_out >= 0) return std::max(0.1, phi_in / (phi_in - phi_out));
  return 1.0;
}

}  // namespace

int project_pressure(const FlipGrid& g, const LiquidModel& m, FlipWorkspace& w, double dt) {
  (void)dt;
  const int n = g.cells();
  const int stride[3] = {1, g.nx, g.nx * g.ny};
  const int dims[3] = {g.nx, g.ny, g.nz};
  auto& A0 = w.adiag;
  A0.assign(n, 0.0);
  for (int c = 0; c < 3; ++c) w.aplus[c].assign(n, 0.0);
  w.rhs.assign(n, 0.0);
  w.p.assign(n, 0.0);
  // Assemble rows of fluid cells.
#pragma omp parallel for collapse(2) schedule(static) if (worth_threads(g.cells()))
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const int ci = g.cell(i, j, k);
        if (!w.fluid[ci]) continue;
        const int idx[3] = {i, j, k};
        double diag = 0, div = 0;
        for (int c = 0; c < g.dim; ++c)
          for (int side = 0; side < 2; ++side) {
            const int f = face_of(g, c, i, j, k, side);
            const double a = w.open[c][f];
            const double sign = side ? 1.0 : -1.0;
            div += sign * (a * w.vel[c][f] + (1 - a) * w.solid_vel[c][f]);
            if (a <= 0) continue;
            const int nb_idx = idx[c] + (side ? 1 : -1);
            if (nb_idx < 0 || nb_idx >= dims[c]) continue;  // domain wall (open = 0 there anyway)
            const int nb = ci + (side ? stride[c] : -stride[c]);
            if (w.fluid[nb]) {
              diag += a;
              if (side) w.aplus[c][ci] = -a;
            } else {
              diag += a / ghost_theta(w.phi_liquid[ci], w.phi_liquid[nb]);
            }
          }
        // A tiny shift keeps a pocket of liquid sealed by walls (no air
        // neighbour: a singular Neumann block) solvable.
        A0[ci] = diag > 0 ? diag + 1e-6 : 0.0;
        w.rhs[ci] = diag > 0 ? -div : 0.0;
      }
  // MIC(0) preconditioner (sequential: a lower-triangular sweep).
  auto& pre = w.precon;
  pre.assign(n, 0.0);
  constexpr double tau = 0.97, sigma = 0.25;
  for (int ci = 0; ci < n; ++ci) {
    if (A0[ci] <= 0) continue;
    double e = A0[ci];
    for (int c = 0; c < g.dim; ++c) {
      const int nb = ci - stride[c];
      if (nb < 0 || pre[nb] == 0) continue;
      const double a = w.aplus[c][nb] * pre[nb];
      double fill = 0;
      for (int c2 = 0; c2 < g.dim; ++c2)
        if (c2 != c) fill += w.aplus[c2][nb];
      e -= a * a + tau * w.aplus[c][nb] * fill * pre[nb] * pre[nb];
    }
    if (e < sigma * A0[ci]) e = A0[ci];
    pre[ci] = 1 / std::sqrt(e);
  }
  auto apply_precon = [&](const std::vector<double>& r, std::vector<double>& z) {
    auto& qv = w.q;  // forward solve L q = r, then L^T z = q
    for (int ci = 0; ci < n; ++ci) {
      if (A0[ci] <= 0) { qv[ci] = 0; continue; }
      double t = r[ci];
      for (int c = 0; c < g.dim; ++c) {
        const int nb = ci - stride[c];
        if (nb >= 0) t -= w.aplus[c][nb] * pre[nb] * qv[nb];
      }
      qv[ci] = t * pre[ci];
    }
    for (int ci = n - 1; ci >= 0; --ci) {
      if (A0[ci] <= 0) { z[ci] = 0; continue; }
      double t = qv[ci];
      for (int c = 0; c < g.dim; ++c) {
        const int nb = ci + stride[c];
        if (nb < n) t -= w.aplus[c][ci] * pre[ci] * z[nb];
      }
      z[ci] = t * pre[ci];
    }
  };
  // The MIC(0) sweeps are sequential, so the Krylov vector operations between
  // them are threaded only on large grids (a barrier per operation costs more
  // than it saves below about half a million cells).
  auto matvec = [&](const std::vector<double>& x, std::vector<double>& y) {
#pragma omp parallel for schedule(static) if (n > (1 << 19))
    for (int ci = 0; ci < n; ++ci) {
      if (A0[ci] <= 0) { y[ci] = 0; continue; }
      double t = A0[ci] * x[ci];
      for (int c = 0; c < g.dim; ++c) {
        if (ci - stride[c] >= 0) t += w.aplus[c][ci - stride[c]] * x[ci - stride[c]];
        if (ci + stride[c] < n) t += w.aplus[c][ci] * x[ci + stride[c]];
      }
      y[ci] = t;
    }
  };
  w.r = w.rhs;
  w.z.assign(n, 0.0), w.s.assign(n, 0.0), w.q.assign(n, 0.0);
  double r0 = 0;
  for (double v : w.r) r0 = std::max(r0, std::abs(v));
  int iters = 0;
  if (r0 > 1e-12) {
    apply_precon(w.r, w.z);
    w.s = w.z;
    double rho = dot(w.z, w.r);
    std::vector<double>& As = w.vb;  // scratch borrowed from the viscosity solve
    As.assign(n, 0.0);
    for (iters = 1; iters <= m.pressure_max_iterations; ++iters) {
      matvec(w.s, As);
      const double sas = dot(w.s, As);
      if (!(sas > 0)) break;  // breakdown: keep the iterate so far
      const double alpha = rho / sas;
      double rmax = 0;
#pragma omp parallel for schedule(static) reduction(max : rmax) if (n > (1 << 19))
      for (int i = 0; i < n; ++i) {
        w.p[i] += alpha * w.s[i];
        w.r[i] -= alpha * As[i];
        rmax = std::max(rmax, std::abs(w.r[i]));
      }
      if (rmax <= m.pressure_tolerance * r0) break;
      apply_precon(w.r, w.z);
      const double rho_new = dot(w.z, w.r);
      const double beta = rho_new / rho;
      rho = rho_new;
#pragma omp parallel for schedule(static) if (n > (1 << 19))
      for (int i = 0; i < n; ++i) w.s[i] = w.z[i] + beta * w.s[i];
    }
  }
  // Velocity update on faces touching a fluid cell; mark them valid.
  for (int c = 0; c < g.dim; ++c) {
    const auto d = g.face_dims(c);
#pragma omp parallel for collapse(2) schedule(static) if (worth_threads_light(g.cells()))
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          const int f = i + d[0] * (j + d[1] * k);
          w.valid[c][f] = 0;
          const int idx[3] = {i, j, k};
          const int lo_i = idx[c] - 1, hi_i = idx[c];
          const bool has_lo = lo_i >= 0, has_hi = hi_i < dims[c];
          int lo_cell = -1, hi_cell = -1;
          if (has_lo) { int t[3] = {i, j, k}; t[c] = lo_i; lo_cell = g.cell(t[0], t[1], t[2]); }
          if (has_hi) { int t[3] = {i, j, k}; t[c] = hi_i; hi_cell = g.cell(t[0], t[1], t[2]); }
          const bool flo = lo_cell >= 0 && w.fluid[lo_cell], fhi = hi_cell >= 0 && w.fluid[hi_cell];
          if (!flo && !fhi) continue;
          if (w.open[c][f] <= 0) continue;
          double qlo, qhi;
          if (flo && fhi) {
            qlo = w.p[lo_cell], qhi = w.p[hi_cell];
          } else if (flo) {
            qlo = w.p[lo_cell];
            qhi = qlo - qlo / ghost_theta(w.phi_liquid[lo_cell], w.phi_liquid[hi_cell]);
          } else {
            qhi = w.p[hi_cell];
            qlo = qhi - qhi / ghost_theta(w.phi_liquid[hi_cell], w.phi_liquid[lo_cell]);
          }
          w.vel[c][f] = float(w.vel[c][f] - (qhi - qlo));
          w.valid[c][f] = 1;
        }
  }
  return iters;
}

// Breadth-first: each layer sets the invalid faces next to valid ones to the
// mean of their valid neighbours. Only the band around the liquid is visited
// after one scan of the grid for the first front.
void extrapolate(const FlipGrid& g, FlipWorkspace& w, int layers) {
  for (int c = 0; c < g.dim; ++c) {
    const auto d = g.face_dims(c);
    const int st[3] = {1, d[0], d[0] * d[1]};
    auto& val = w.valid[c];
    auto& mark = w.valid_tmp[c];  // 1 = queued in the front
    auto& v = w.vel[c];
    const int n = g.faces(c);
    mark.assign(n, 0);
    std::vector<int>& front = w.front;
    std::vector<float>& value = w.front_value;
    front.clear();
    auto neighbours = [&](int f, auto&& fn) {
      int rem = f;
      const int i = rem % d[0];
      rem /= d[0];
      const int j = rem % d[1], k = rem / d[1];
      const int idx[3] = {i, j, k};
      for (int a = 0; a < g.dim; ++a) {
        if (idx[a] > 0) fn(f - st[a]);
        if (idx[a] + 1 < d[a]) fn(f + st[a]);
      }
    };
    for (int f = 0; f < n; ++f) {
      if (val[f]) continue;
      bool near = false;
      neighbours(f, [&](int nb) { near = near || val[nb]; });
      if (near) front.push_back(f), mark[f] = 1;
    }
    for (int layer = 0; layer < layers && !front.empty(); ++layer) {
      value.resize(front.size());
      for (size_t q = 0; q < front.size(); ++q) {
        double sum = 0;
        int cnt = 0;
        neighbours(front[q], [&](int nb) {
          if (val[nb]) sum += v[nb], ++cnt;
        });
        value[q] = cnt ? float(sum / cnt) : 0.f;
      }
      for (size_t q = 0; q < front.size(); ++q) v[front[q]] = value[q], val[front[q]] = 1;
      if (layer + 1 == layers) break;
      std::vector<int>& next = w.front_next;
      next.clear();
      for (int f : front)
        neighbours(f, [&](int nb) {
          if (!val[nb] && !mark[nb]) mark[nb] = 1, next.push_back(nb);
        });
      front.swap(next);
    }
  }
}

namespace {
// Tent-kernel stencil of face component c at x: base index, strides, weights.
struct Stencil {
  int base, sy, sz;
  float t[3];
};

inline Stencil stencil(const FlipGrid& g, int c, const float* x) {
  const auto d = g.face_dims(c);
  Stencil s{0, d[0], d[0] * d[1], {0, 0, 0}};
  int i0[3] = {0, 0, 0};
  for (int a = 0; a < g.dim; ++a) {
    const float off = a == c ? 0.f : 0.5f;
    const float f = float((x[a] - g.lo[a]) / g.h) - off;
    const int i = std::clamp(int(std::floor(f)), 0, d[a] - 2);
    i0[a] = i;
    s.t[a] = std::clamp(f - float(i), 0.f, 1.f);
  }
  s.base = i0[0] + d[0] * (i0[1] + d[1] * i0[2]);
  return s;
}

inline float apply(const FlipGrid& g, const Stencil& s, const float* field) {
  const float* p = field + s.base;
  const float* t = s.t;
  const float a00 = p[0] + t[0] * (p[1] - p[0]);
  const float a10 = p[s.sy] + t[0] * (p[s.sy + 1] - p[s.sy]);
  const float b0 = a00 + t[1] * (a10 - a00);
  if (g.dim == 2) return b0;
  const float a01 = p[s.sz] + t[0] * (p[s.sz + 1] - p[s.sz]);
  const float a11 = p[s.sz + s.sy] + t[0] * (p[s.sz + s.sy + 1] - p[s.sz + s.sy]);
  const float b1 = a01 + t[1] * (a11 - a01);
  return b0 + t[2] * (b1 - b0);
}
}  // namespace

float interpolate(const FlipGrid& g, int c, const float* field, const float* x) {
  return apply(g, stencil(g, c, x), field);
}

void interpolate_pair(const FlipGrid& g, int c, const float* a, const float* b, const float* x, float* va,
                      float* vb) {
  const Stencil s = stencil(g, c, x);
  *va = apply(g, s, a);
  *vb = apply(g, s, b);
}

}  // namespace pliant::liquid
