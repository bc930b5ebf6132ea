// Spacetime Full Approximation Scheme multigrid for the NSO KKT system
// (nso_level.h). Levels halve every spatial axis (time is not coarsened) while the
// grid stays even and >= 8 cells per axis. Each coarse level rediscretises the
// problem (same w, bm; cell size doubled; the linearisation point zbar restricted
// from the finer level). FAS V-cycle (Brandt 1977) at level l:
//   pre-smooth (SCGS); x_c = R x, q_c = R q;
//   (F_c, G_c) = KKT_c(x_c, q_c) + R (residual of level l);
//   V-cycle on level l+1 (or coarsest_sweeps SCGS sweeps on the coarsest level);
//   x += P (x_c - R x), q += P (q_c - R q); post-smooth (reversed colour order).
// The coarse unknowns are full approximations, not corrections, so the same cycle
// would serve a nonlinear operator; here the Levenberg-Marquardt loop of
// nso_solver.h re-linearises between cycles.
#pragma once
#include <vector>

#include "nso_level.h"

namespace pliant::smoke {

class SpacetimeMultigrid {
 public:
  SpacetimeMultigrid(const SpacetimeGrid& fine, int max_levels = 16);
  int levels() const { return int(levels_.size()); }
  NsoLevel& level(int l) { return levels_[l]; }
  NsoLevel& fine() { return levels_[0]; }

  // Linearise every level around the fine level's zbar (restricted down), set w, bm.
  void setup(double dt, double w, double bm);
  // One FAS V-cycle on the fine level's (x, q) for its (F, G). Returns the fine
  // residual norm after the cycle.
  double vcycle();
  // Bytes held by all levels and the cycle's temporaries.
  size_t bytes() const;

  int pre_sweeps = 1, post_sweeps = 1, coarsest_sweeps = 8;

 private:
  void cycle(int l);
  std::vector<NsoLevel> levels_;
  // Per coarse level (index 0 unused, empty): the restricted start and the restricted
  // residual of the FAS cycle.
  std::vector<std::vector<double>> xc0_, qc0_, tmp_mom_, tmp_div_;
};

}  // namespace pliant::smoke
