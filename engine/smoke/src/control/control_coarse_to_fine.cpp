#include "control_coarse_to_fine.h"

#include <stdexcept>
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


std::vector<ControlModel> level_chain(const ControlModel& m, int levels) {
  std::vector<ControlModel> chain{m};
  ControlModel c;
  while (int(chain.size()) < levels && chain.back().sim.n[0] > 32 && admm_coarsen_model(chain.back(), c))
    chain.push_back(c);
  return chain;
}

size_t face_count(const ControlModel& m) {
  const MacGrid g = model_grid(m.sim);
  return g.face_count(0) + g.face_count(1) + g.face_count(2);
}

}  // namespace

bool control_state_fits(const ControlModel& m, const ControlState& s) {
  if (s.level > 0 && !m.progressive_preview) return false;  // the scene no longer solves coarse levels
  const auto chain = level_chain(m, kCoarseToFineLevels);
  if (s.level < 0 || s.level >= int(chain.size()) || int(s.force.size()) != m.sim.frames) return false;
  const size_t nf = face_count(chain[s.level]);
  for (const auto& f : s.force)
    if (f.size() != nf) return false;
  return true;
}

bool control_coarse_to_fine(const ControlModel& m, ControlState& s, int levels, const ControlCallbacks& cb,
                            const SolveLevelFn& solve_level) {
  const bool resume_level = s.level > 0;
  if (!resume_level) {
    if (s.iteration != 0 || !s.objective_history.empty() || !s.split.empty()) return false;
    for (const auto& f : s.force)
      for (float x : f)
        if (x != 0.0f) return false;  // an explicit start: keep it
  }
  const std::vector<ControlModel> chain = level_chain(m, levels);
  if (resume_level && s.level >= int(chain.size()))
    throw std::invalid_argument("control_coarse_to_fine: the state's level " + std::to_string(s.level) +
                                " does not exist for this model");
  if (chain.size() < 2) return false;
  const int T = m.sim.frames;
  FaceSeries force;
  double trace_s = s.trace_s;  // the solver clock goes on through the levels (control_trace.h)
  const int first = resume_level ? s.level : int(chain.size()) - 1;
  for (int l = first; l >= 1; --l) {
    ControlModel cm = chain[l];
    cm.progressive_preview = false;
    if (m.coarse_iterations >= 0) cm.max_iterations = m.coarse_iterations;
    if (m.coarse_polish_iterations >= 0) cm.polish_iterations = m.coarse_polish_iterations;
    // ADMM only on the coarsest coarse_admm_levels levels (it finds the transport path
    // there cheaply); the finer coarse levels start from the prolonged forces and polish.
    if (m.method == ControlMethod::Admm && m.coarse_admm_levels >= 0 && l < int(chain.size()) - m.coarse_admm_levels)
      cm.max_iterations = 0;
    // Each level reports its own stage ("admm 32x32"), so a progress curve can
    // tell the scales apart (objectives differ by the cell count).
    cm.stage_label = std::to_string(cm.sim.n[0]) + "x" + std::to_string(cm.sim.n[1]) +
                     (cm.sim.dim == 3 ? "x" + std::to_string(cm.sim.n[2]) : std::string());
    ControlState cs;
    if (l == first && resume_level) {
      cs = std::move(s);
    } else {
      cs = control_init(cm);
      if (!force.empty()) cs.force = force;
      cs.trace_s = trace_s;
    }
    cs.level = l;
    ControlCallbacks level_cb;
    level_cb.clock = cb.clock;
    int level_iterations = 0;
    level_cb.on_iteration = [&](const ControlState& st) {
      ++level_iterations;
      if (cb.on_preview && (level_iterations & (level_iterations - 1)) == 0) emit_preview(cm, st, cb);  // powers of two
      if (cb.on_iteration) cb.on_iteration(st);  // the level's checkpoint (st.level = l)
    };
    solve_level(cm, cs, level_cb);
    trace_s = cs.trace_s;
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
  s = control_init(m);
  s.force = force;
  s.trace_s = trace_s;
  return true;
}

}  // namespace pliant::smoke
