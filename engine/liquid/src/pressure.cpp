// Pressure projection: variational cut-face weights (Batty, Bertails, Bridson
// 2007) for solids, ghost-fluid Dirichlet p = 0 at the free surface (Gibou et al.
// 2002), solved by PCG with a MIC(0) preconditioner (Bridson, "Fluid Simulation
// for Computer Graphics", 2nd ed., ch. 5) on the fluid rows only; large systems
// use a two-block MIC(0) whose blocks run in parallel. Unknowns are q = dt p / (rho h), so
// the face update is u -= q_hi - q_lo.
#include <algorithm>
#include <cmath>

#include "flip_grid.h"

namespace pliant::liquid {
namespace {

// Systems with at least kParallelRows rows run the PCG's vector operations on
// threads (below, a barrier per operation costs more than it saves, much more on
// a shared machine); from kBlockRows rows the preconditioner is split into two
// blocks whose sweeps (most of an iteration's work) run side by side. The split
// drops the couplings across one plane of cells: on the 60k-particle dam break
// (7.5k rows) that raised PCG iterations from 17 to 28 per substep, more than
// two threads win back, so only large systems split.
constexpr int kParallelRows = 1 << 15;
constexpr int kBlockRows = 1 << 15;

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
  // Compact system: one row per fluid cell with a positive diagonal, in cell
  // order; 6 neighbour slots per row (lower -x -y -z, then upper +x +y +z).
  // The PCG then touches only the liquid, not the whole grid.
  auto& row_of = w.row_of;
  auto& cell_of = w.cell_of;
  row_of.assign(n, -1);
  cell_of.clear();
  for (int ci = 0; ci < n; ++ci)
    if (A0[ci] > 0) row_of[ci] = int(cell_of.size()), cell_of.push_back(ci);
  const int nf = int(cell_of.size());
  const bool par = nf >= kParallelRows;
  auto& nbr = w.nbr;
  auto& off = w.off;
  nbr.resize(6 * size_t(nf));
  off.resize(6 * size_t(nf));
  auto& ad = w.cdiag;
  ad.resize(nf);
  for (auto* v : {&w.cp, &w.cr, &w.cz, &w.cs, &w.cq, &w.cAs, &w.precon}) v->assign(nf, 0.0);
#pragma omp parallel for schedule(static) if (par)
  for (int r = 0; r < nf; ++r) {
    const int ci = cell_of[r];
    ad[r] = A0[ci];
    w.cr[r] = w.rhs[ci];
    for (int c = 0; c < 3; ++c) {
      const int lo = ci - stride[c], hi = ci + stride[c];
      const double a_lo = c < g.dim && lo >= 0 ? w.aplus[c][lo] : 0.0;
      const double a_hi = c < g.dim ? w.aplus[c][ci] : 0.0;
      nbr[6 * r + c] = a_lo != 0 ? row_of[lo] : -1;
      off[6 * r + c] = a_lo;
      nbr[6 * r + 3 + c] = a_hi != 0 ? row_of[hi] : -1;
      off[6 * r + 3 + c] = a_hi;
    }
  }
  // MIC(0) (Bridson's book, ch. 5) on a block-diagonal part of A: large systems
  // are cut into two halves of rows whose couplings to each other are dropped
  // from the preconditioner, so each half's triangular sweeps run on its own
  // thread (the halves depend on the row count only, so results do not depend
  // on the thread count).
  const int blocks = nf >= kBlockRows ? 2 : 1;
  int bound[3] = {0, blocks == 2 ? nf / 2 : nf, nf};
  auto& pre = w.precon;
  constexpr double tau = 0.97, sigma = 0.25;
#pragma omp parallel for schedule(static, 1) num_threads(blocks) if (blocks > 1)
  for (int b = 0; b < blocks; ++b) {
    const int b0 = bound[b], b1 = bound[b + 1];
    for (int r = b0; r < b1; ++r) {
      double e = ad[r];
      for (int c = 0; c < g.dim; ++c) {
        const int nb = nbr[6 * r + c];
        if (nb < b0) continue;  // none, or in the other block
        const double a = off[6 * r + c] * pre[nb];
        double fill = 0;
        for (int c2 = 0; c2 < g.dim; ++c2) {
          const int up = nbr[6 * nb + 3 + c2];
          if (c2 != c && up >= b0 && up < b1) fill += off[6 * nb + 3 + c2];
        }
        e -= a * a + tau * off[6 * r + c] * fill * pre[nb] * pre[nb];
      }
      if (e < sigma * ad[r]) e = ad[r];
      pre[r] = 1 / std::sqrt(e);
    }
  }
  auto apply_precon = [&](const std::vector<double>& rin, std::vector<double>& z) {
    auto& qv = w.cq;  // forward solve L q = r, then L^T z = q, per block
#pragma omp parallel for schedule(static, 1) num_threads(blocks) if (blocks > 1)
    for (int b = 0; b < blocks; ++b) {
      const int b0 = bound[b], b1 = bound[b + 1];
      for (int r = b0; r < b1; ++r) {
        double t = rin[r];
        for (int c = 0; c < g.dim; ++c) {
          const int nb = nbr[6 * r + c];
          if (nb >= b0) t -= off[6 * r + c] * pre[nb] * qv[nb];
        }
        qv[r] = t * pre[r];
      }
      for (int r = b1 - 1; r >= b0; --r) {
        double t = qv[r];
        for (int c = 0; c < g.dim; ++c) {
          const int nb = nbr[6 * r + 3 + c];
          if (nb >= 0 && nb < b1) t -= off[6 * r + 3 + c] * pre[r] * z[nb];
        }
        z[r] = t * pre[r];
      }
    }
  };
  auto matvec = [&](const std::vector<double>& x, std::vector<double>& y) {
#pragma omp parallel for schedule(static) if (par)
    for (int r = 0; r < nf; ++r) {
      double t = ad[r] * x[r];
      for (int d = 0; d < 6; ++d) {
        const int nb = nbr[6 * r + d];
        if (nb >= 0) t += off[6 * r + d] * x[nb];
      }
      y[r] = t;
    }
  };
  auto dot = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
#pragma omp parallel for schedule(static) reduction(+ : s) if (par)
    for (int i = 0; i < nf; ++i) s += a[i] * b[i];
    return s;
  };
  auto &cp = w.cp, &cr = w.cr, &cz = w.cz, &cs = w.cs, &As = w.cAs;
  double r0 = 0;
  for (int i = 0; i < nf; ++i) r0 = std::max(r0, std::abs(cr[i]));
  int iters = 0;
  if (r0 > 1e-12) {
    apply_precon(cr, cz);
    cs = cz;
    double rho = dot(cz, cr);
    for (iters = 1; iters <= m.pressure_max_iterations; ++iters) {
      matvec(cs, As);
      const double sas = dot(cs, As);
      if (!(sas > 0)) break;  // breakdown: keep the iterate so far
      const double alpha = rho / sas;
      double rmax = 0;
#pragma omp parallel for schedule(static) reduction(max : rmax) if (par)
      for (int i = 0; i < nf; ++i) {
        cp[i] += alpha * cs[i];
        cr[i] -= alpha * As[i];
        rmax = std::max(rmax, std::abs(cr[i]));
      }
      if (rmax <= m.pressure_tolerance * r0) break;
      apply_precon(cr, cz);
      const double rho_new = dot(cz, cr);
      const double beta = rho_new / rho;
      rho = rho_new;
#pragma omp parallel for schedule(static) if (par)
      for (int i = 0; i < nf; ++i) cs[i] = cz[i] + beta * cs[i];
    }
  }
  for (int r = 0; r < nf; ++r) w.p[cell_of[r]] = cp[r];
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
  // Components are independent (own scratch each): one per thread.
#pragma omp parallel for schedule(dynamic, 1) if (worth_threads(g.cells()))
  for (int c = 0; c < g.dim; ++c) {
    const auto d = g.face_dims(c);
    const int st[3] = {1, d[0], d[0] * d[1]};
    auto& val = w.valid[c];
    auto& mark = w.valid_tmp[c];  // 1 = queued in the front
    auto& v = w.vel[c];
    const int n = g.faces(c);
    mark.assign(n, 0);
    std::vector<int>& front = w.front[c];
    std::vector<float>& value = w.front_value[c];
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
    // First front: invalid faces with a valid neighbour (loops, no index division).
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j) {
        const int row = d[0] * (j + d[1] * k);
        const bool ylo = j > 0, yhi = j + 1 < d[1], zlo = g.dim == 3 && k > 0, zhi = g.dim == 3 && k + 1 < d[2];
        for (int i = 0; i < d[0]; ++i) {
          const int f = row + i;
          if (val[f]) continue;
          const bool near = (i > 0 && val[f - 1]) || (i + 1 < d[0] && val[f + 1]) || (ylo && val[f - st[1]]) ||
                            (yhi && val[f + st[1]]) || (zlo && val[f - st[2]]) || (zhi && val[f + st[2]]);
          if (near) front.push_back(f), mark[f] = 1;
        }
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
      std::vector<int>& next = w.front_next[c];
      next.clear();
      for (int f : front)
        neighbours(f, [&](int nb) {
          if (!val[nb] && !mark[nb]) mark[nb] = 1, next.push_back(nb);
        });
      front.swap(next);
    }
  }
}

float interpolate(const FlipGrid& g, int c, const float* field, const float* x) {
  const GridMap gm(g);
  GridSamples s;
  gm.samples(x, &s);
  return sample(g.dim, stencil_of(gm, s, c), field);
}

void interpolate_pair(const FlipGrid& g, int c, const float* a, const float* b, const float* x, float* va,
                      float* vb) {
  const GridMap gm(g);
  GridSamples s;
  gm.samples(x, &s);
  const Stencil st = stencil_of(gm, s, c);
  *va = sample(g.dim, st, a);
  *vb = sample(g.dim, st, b);
}

}  // namespace pliant::liquid
