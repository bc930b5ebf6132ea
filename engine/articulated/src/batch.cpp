// Batched rollouts: one LM iteration per trajectory per pass (dissertation Fig. 5.1),
// so a trajectory needing many iterations never blocks the others' progress.
#include <omp.h>

#include "pliant/articulated/mpc.h"

namespace pliant::articulated {

int batch_rollout(const Model& m, const SimOptions& o, std::vector<State>& states, int steps,
                  int threads) {
  const int n = static_cast<int>(states.size());
  const bool pbad = integrator_is_pbad(o.integrator);
  std::vector<SimWorkspace> ws(n);
  std::vector<PbadStep> step(n);
  std::vector<int> done_steps(n, 0);
  std::vector<char> active(n, 0);
  const int nt = threads > 0 ? threads : omp_get_max_threads();
  int passes = 0;
  // Each worker owns every nt-th trajectory and sweeps over them, one LM iteration
  // (or one explicit step) per trajectory per pass; no barrier between passes, so a
  // loaded core delays only its own trajectories.
#pragma omp parallel num_threads(nt) reduction(max : passes)
  {
    const int tid = omp_get_thread_num(), stride = omp_get_num_threads();
    int my_passes = 0;
    for (bool any = true; any;) {
      any = false;
      for (int t = tid; t < n; t += stride) {
        if (done_steps[t] >= steps) continue;
        any = true;
        State& s = states[t];
        if (!pbad) {
          sim_step(m, o, s, ws[t]);
          ++done_steps[t];
          continue;
        }
        if (!active[t]) {
          pbad_begin(m, o, s, step[t], ws[t]);
          active[t] = 1;
        }
        if (pbad_iterate(m, o, s, step[t], ws[t])) {
          pbad_finish(m, o, s, step[t], ws[t]);
          active[t] = 0;
          ++done_steps[t];
        }
      }
      if (any) ++my_passes;
    }
    passes = my_passes;
  }
  return passes;
}

}  // namespace pliant::articulated
