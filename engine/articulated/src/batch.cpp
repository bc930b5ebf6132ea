// Batched rollouts: one LM iteration per trajectory per pass (dissertation Fig. 5.1),
// so a trajectory needing many iterations never blocks the others' progress.
#include <omp.h>

#include "pliant/articulated/mpc.h"

namespace pliant::articulated {

int batch_rollout(const Model& m, const SimOptions& o, std::vector<State>& states, int steps,
                  int threads) {
  const int n = static_cast<int>(states.size());
  const bool pbad = o.integrator == Integrator::Pbad2 || o.integrator == Integrator::Pbad3;
  std::vector<SimWorkspace> ws(n);
  std::vector<PbadStep> step(n);
  std::vector<int> done_steps(n, 0);
  std::vector<char> active(n, 0);
  int passes = 0, remaining = n;
  const int nt = threads > 0 ? threads : omp_get_max_threads();
  while (remaining > 0) {
    ++passes;
    int finished = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt) reduction(+ : finished)
    for (int t = 0; t < n; ++t) {
      if (done_steps[t] >= steps) continue;
      State& s = states[t];
      if (!pbad) {
        sim_step(m, o, s, ws[t]);
        if (++done_steps[t] == steps) ++finished;
        continue;
      }
      if (!active[t]) {
        pbad_begin(m, o, s, step[t], ws[t]);
        active[t] = 1;
      }
      if (pbad_iterate(m, o, s, step[t], ws[t])) {
        pbad_finish(m, o, s, step[t], ws[t]);
        active[t] = 0;
        if (++done_steps[t] == steps) ++finished;
      }
    }
    remaining -= finished;
  }
  return passes;
}

}  // namespace pliant::articulated
