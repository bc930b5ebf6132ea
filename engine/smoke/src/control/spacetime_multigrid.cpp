#include "spacetime_multigrid.h"

#include "spacetime_multigrid_transfer.h"

namespace pliant::smoke {

SpacetimeMultigrid::SpacetimeMultigrid(const SpacetimeGrid& fine, int max_levels) {
  SpacetimeGrid g = fine;
  levels_.emplace_back(g);
  while (g.coarsenable() && int(levels_.size()) < max_levels) {
    g = g.coarsened();
    levels_.emplace_back(g);
  }
  for (size_t l = 0; l < levels_.size(); ++l) {
    const size_t nx = l ? levels_[l].x.size() : 0, nq = l ? levels_[l].q.size() : 0;
    xc0_.emplace_back(nx);
    qc0_.emplace_back(nq);
    tmp_mom_.emplace_back(nx);
    tmp_div_.emplace_back(nq);
  }
}

size_t SpacetimeMultigrid::bytes() const {
  size_t b = 0;
  for (const NsoLevel& L : levels_) b += L.bytes();
  for (size_t l = 0; l < levels_.size(); ++l)
    b += (xc0_[l].capacity() + qc0_[l].capacity() + tmp_mom_[l].capacity() + tmp_div_[l].capacity()) * sizeof(double);
  return b;
}

void SpacetimeMultigrid::setup(double dt, double w, double bm) {
  for (int l = 0; l < levels(); ++l) {
    NsoLevel& L = levels_[l];
    if (l > 0) restrict_faces_series(levels_[l - 1].grid(), L.grid(), levels_[l - 1].zbar.data(), L.zbar.data());
    L.linearise(L.zbar.data(), dt);
    L.set_coefficients(w, bm);
  }
}

void SpacetimeMultigrid::cycle(int l) {
  NsoLevel& L = levels_[l];
  if (l + 1 == levels()) {
    for (int s = 0; s < coarsest_sweeps; ++s) L.smooth(s % 2 == 0);
    return;
  }
  for (int s = 0; s < pre_sweeps; ++s) L.smooth(true);
  L.residual();
  NsoLevel& C = levels_[l + 1];
  const SpacetimeGrid &fg = L.grid(), &cg = C.grid();
  restrict_faces_series(fg, cg, L.x.data(), C.x.data());
  restrict_cells_series(fg, cg, L.q.data(), C.q.data());
  xc0_[l + 1] = C.x;
  qc0_[l + 1] = C.q;
  C.apply(C.x.data(), C.q.data(), C.F.data(), C.G.data());
  restrict_faces_series(fg, cg, L.res_mom.data(), tmp_mom_[l + 1].data());
  restrict_cells_series(fg, cg, L.res_div.data(), tmp_div_[l + 1].data());
  for (size_t e = 0; e < C.F.size(); ++e) C.F[e] += tmp_mom_[l + 1][e];
  for (size_t e = 0; e < C.G.size(); ++e) C.G[e] += tmp_div_[l + 1][e];
  cycle(l + 1);
  for (size_t e = 0; e < C.x.size(); ++e) xc0_[l + 1][e] = C.x[e] - xc0_[l + 1][e];
  for (size_t e = 0; e < C.q.size(); ++e) qc0_[l + 1][e] = C.q[e] - qc0_[l + 1][e];
  prolong_add_faces_series(fg, cg, xc0_[l + 1].data(), L.x.data());
  prolong_add_cells_series(fg, cg, qc0_[l + 1].data(), L.q.data());
  for (int s = 0; s < post_sweeps; ++s) L.smooth(false);
}

double SpacetimeMultigrid::vcycle() {
  cycle(0);
  return levels_[0].residual();
}

}  // namespace pliant::smoke
