#include "control_coarse_to_fine.h"

#include <string>
#include <vector>

#include "../smoke_workspace.h"
#include "admm_solver.h"
#include "control_forward_model.h"
#include "spacetime_multigrid_transfer.h"

namespace pliant::smoke {

namespace {

// Re-simulates the level's forces and hands the density to on_preview.
void emit_preview(const ControlModel& cm, const ControlState& cs, const ControlCallbacks& cb) {
  control_detail::ForwardOps ops(cm, control_detail::kControlPressureTolerance);
  control_detail::TrajectoryD tr;
  control_detail::forward_d(cm, ops, control_detail::to_double(cs.force), tr);
  GridDims gd;
  gd.dim = cm.sim.dim;
  gd.n = cm.sim.n;
  std::vector<std::vector<float>> dens;
  for (const auto& r : tr.rho) dens.emplace_back(r.begin(), r.end());
  cb.on_preview(gd, dens);
}

}  // namespace

bool control_coarse_to_fine(const ControlModel& m, ControlState& s, int levels, const ControlCallbacks& cb,
                            const SolveLevelFn& solve_level) {
  if (s.iteration != 0 || !s.objective_history.empty() || !s.split.empty()) return false;
  for (const auto& f : s.force)
    for (float x : f)
      if (x != 0.0f) return false;  // an explicit start: keep it
  std::vector<ControlModel> chain{m};
  ControlModel c;
  while (int(chain.size()) < levels && chain.back().sim.n[0] > 32 && admm_coarsen_model(chain.back(), c))
    chain.push_back(c);
  if (chain.size() < 2) return false;
  const int T = m.sim.frames;
  FaceSeries force;
  for (int l = int(chain.size()) - 1; l >= 1; --l) {
    ControlModel cm = chain[l];
    cm.progressive_preview = false;
    // Each level reports its own stage ("admm 32x32"), so a progress curve can
    // tell the scales apart (objectives differ by the cell count).
    cm.stage_label = std::to_string(cm.sim.n[0]) + "x" + std::to_string(cm.sim.n[1]) +
                     (cm.sim.dim == 3 ? "x" + std::to_string(cm.sim.n[2]) : std::string());
    ControlState cs = control_init(cm);
    if (!force.empty()) cs.force = force;
    ControlCallbacks level_cb;
    int level_iterations = 0;
    if (cb.on_preview)
      level_cb.on_iteration = [&](const ControlState& st) {
        ++level_iterations;
        if ((level_iterations & (level_iterations - 1)) == 0) emit_preview(cm, st, cb);  // powers of two
      };
    solve_level(cm, cs, level_cb);
    if (cb.on_preview) emit_preview(cm, cs, cb);
    // Prolong the forces to the next finer level.
    const SpacetimeGrid fg(model_grid(chain[l - 1].sim), 1), cg(model_grid(cm.sim), 1);
    force.assign(T, {});
    for (int t = 0; t < T; ++t) {
      std::vector<double> xc(cs.force[t].begin(), cs.force[t].end()), xf(fg.faces());
      prolong_faces(fg, cg, xc.data(), xf.data());
      force[t].assign(xf.begin(), xf.end());
    }
  }
  s.force = force;
  return true;
}

}  // namespace pliant::smoke
