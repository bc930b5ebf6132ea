// Implicit viscosity: backward Euler on du/dt = (mu/rho) lap u, one velocity
// component at a time (the components decouple for constant mu). Faces inside
// the liquid are unknowns; solid faces (open fraction 0) are Dirichlet u = q
// (no slip on the container, so a viscous liquid follows it); air faces are
// zero-gradient. Symmetric positive definite: Jacobi-preconditioned CG.
#include <algorithm>
#include <cmath>

#include "flip_grid.h"

namespace pliant::liquid {

int apply_viscosity(const FlipGrid& g, const LiquidModel& m, FlipWorkspace& w, double dt) {
  if (m.viscosity_pa_s <= 0) return 0;
  const double alpha = dt * m.viscosity_pa_s / (m.density_kg_per_m3 * g.h * g.h);
  const int cdims[3] = {g.nx, g.ny, g.nz};
  int total = 0;
  for (int c = 0; c < g.dim; ++c) {
    const auto d = g.face_dims(c);
    const int n = g.faces(c);
    const int st[3] = {1, d[0], d[0] * d[1]};
    auto& in = w.vindex;  // 1 = unknown, 2 = Dirichlet (solid), 0 = air
    in.assign(n, 0);
#pragma omp parallel for collapse(2) schedule(static) if (worth_threads(g.cells()))
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          const int f = i + d[0] * (j + d[1] * k);
          if (w.open[c][f] <= 0) { in[f] = 2; continue; }
          int t[3] = {i, j, k};
          bool fl = false;
          for (int s = -1; s <= 0; ++s) {
            int u[3] = {t[0], t[1], t[2]};
            u[c] += s;
            if (u[c] >= 0 && u[c] < cdims[c]) fl = fl || w.fluid[g.cell(u[0], u[1], u[2])];
          }
          in[f] = fl ? 1 : 0;
        }
    // Compact system: one row per unknown face, 2 dim neighbour slots (unknown
    // neighbours only; Dirichlet ones are folded into the right-hand side).
    auto& rows = w.vrows;
    auto& row_of = w.vrow_of;
    rows.clear();
    row_of.assign(n, -1);
    for (int f = 0; f < n; ++f)
      if (in[f] == 1) row_of[f] = int(rows.size()), rows.push_back(f);
    const int nr = int(rows.size());
    auto &x = w.vx, &b = w.vb, &r = w.vr, &z = w.vz, &s = w.vs, &q = w.vq, &dg = w.vdiag;
    auto& nbr = w.vnbr;
    for (auto* v : {&x, &b, &r, &z, &s, &q, &dg}) v->assign(nr, 0.0);
    nbr.assign(6 * size_t(nr), -1);
#pragma omp parallel for schedule(static) if (worth_threads(nr))
    for (int row = 0; row < nr; ++row) {
      const int f = rows[row];
      const int idx[3] = {f % d[0], (f / d[0]) % d[1], f / (d[0] * d[1])};
      double diag = 1, rhs = w.vel[c][f];
      for (int a = 0; a < g.dim; ++a)
        for (int side = 0; side < 2; ++side) {
          const int ni = idx[a] + (side ? 1 : -1);
          if (ni < 0 || ni >= d[a]) { diag += alpha; continue; }  // domain wall: no slip
          const int nb = f + (side ? st[a] : -st[a]);
          if (in[nb] == 1) diag += alpha, nbr[6 * row + 2 * a + side] = row_of[nb];
          else if (in[nb] == 2) diag += alpha, rhs += alpha * w.solid_vel[c][nb];
        }
      dg[row] = diag, b[row] = rhs, x[row] = w.vel[c][f];
    }
    auto matvec = [&](const std::vector<double>& v, std::vector<double>& out) {
#pragma omp parallel for schedule(static) if (worth_threads_light(nr))
      for (int row = 0; row < nr; ++row) {
        double t = dg[row] * v[row];
        for (int e = 0; e < 6; ++e) {
          const int nb = nbr[6 * row + e];
          if (nb >= 0) t -= alpha * v[nb];
        }
        out[row] = t;
      }
    };
    matvec(x, q);
    double rz = 0, r0 = 0;
    for (int i = 0; i < nr; ++i) {
      r[i] = b[i] - q[i];
      z[i] = r[i] / dg[i];
      s[i] = z[i];
      rz += r[i] * z[i];
      r0 = std::max(r0, std::abs(r[i]));
    }
    const double scale = std::max(1e-6, r0);
    for (int it = 0; it < 500 && r0 > 1e-7 * scale; ++it, ++total) {
      matvec(s, q);
      double sq = 0;
      for (int i = 0; i < nr; ++i) sq += s[i] * q[i];
      const double al = rz / std::max(1e-300, sq);
      double rz_new = 0;
      r0 = 0;
      for (int i = 0; i < nr; ++i) {
        x[i] += al * s[i];
        r[i] -= al * q[i];
        z[i] = r[i] / dg[i];
        rz_new += r[i] * z[i];
        r0 = std::max(r0, std::abs(r[i]));
      }
      const double beta = rz_new / rz;
      rz = rz_new;
      for (int i = 0; i < nr; ++i) s[i] = z[i] + beta * s[i];
    }
    for (int row = 0; row < nr; ++row) w.vel[c][rows[row]] = float(x[row]);
  }
  return total;
}

}  // namespace pliant::liquid
