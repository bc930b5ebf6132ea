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
    auto &x = w.vx, &b = w.vb, &r = w.vr, &z = w.vz, &s = w.vs, &q = w.vq, &dg = w.vdiag;
    x.assign(n, 0.0), b.assign(n, 0.0), dg.assign(n, 1.0);
#pragma omp parallel for collapse(2) schedule(static) if (worth_threads(g.cells()))
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          const int f = i + d[0] * (j + d[1] * k);
          if (in[f] != 1) continue;
          const int idx[3] = {i, j, k};
          double diag = 1, rhs = w.vel[c][f];
          for (int a = 0; a < g.dim; ++a)
            for (int sgn = -1; sgn <= 1; sgn += 2) {
              const int ni = idx[a] + sgn;
              if (ni < 0 || ni >= d[a]) { diag += alpha; continue; }  // domain wall: no slip
              const int nb = f + sgn * st[a];
              if (in[nb] == 1) diag += alpha;
              else if (in[nb] == 2) diag += alpha, rhs += alpha * w.solid_vel[c][nb];
            }
          dg[f] = diag, b[f] = rhs, x[f] = w.vel[c][f];
        }
    auto matvec = [&](const std::vector<double>& v, std::vector<double>& out) {
#pragma omp parallel for schedule(static) if (worth_threads(g.cells()))
      for (int f = 0; f < n; ++f) {
        if (in[f] != 1) { out[f] = 0; continue; }
        int rem = f;
        const int i = rem % d[0]; rem /= d[0];
        const int j = rem % d[1]; const int k = rem / d[1];
        const int idx[3] = {i, j, k};
        double t = dg[f] * v[f];
        for (int a = 0; a < g.dim; ++a) {
          if (idx[a] > 0 && in[f - st[a]] == 1) t -= alpha * v[f - st[a]];
          if (idx[a] + 1 < d[a] && in[f + st[a]] == 1) t -= alpha * v[f + st[a]];
        }
        out[f] = t;
      }
    };
    r.assign(n, 0.0), z.assign(n, 0.0), s.assign(n, 0.0), q.assign(n, 0.0);
    matvec(x, q);
    double rz = 0, r0 = 0;
    for (int f = 0; f < n; ++f) {
      r[f] = in[f] == 1 ? b[f] - q[f] : 0.0;
      z[f] = r[f] / dg[f];
      s[f] = z[f];
      rz += r[f] * z[f];
      r0 = std::max(r0, std::abs(r[f]));
    }
    const double scale = std::max(1e-6, r0);
    for (int it = 0; it < 500 && r0 > 1e-7 * scale; ++it, ++total) {
      matvec(s, q);
      double sq = 0;
      for (int f = 0; f < n; ++f) sq += s[f] * q[f];
      const double al = rz / std::max(1e-300, sq);
      double rz_new = 0;
      r0 = 0;
      for (int f = 0; f < n; ++f) {
        x[f] += al * s[f];
        r[f] -= al * q[f];
        z[f] = r[f] / dg[f];
        rz_new += r[f] * z[f];
        r0 = std::max(r0, std::abs(r[f]));
      }
      const double beta = rz_new / rz;
      rz = rz_new;
      for (int f = 0; f < n; ++f) s[f] = z[f] + beta * s[f];
    }
    for (int f = 0; f < n; ++f)
      if (in[f] == 1) w.vel[c][f] = float(x[f]);
  }
  return total;
}

}  // namespace pliant::liquid
