// The converged comparison of issue 3 (bench_smoke_control --converged): Pliant's solver
// run as users run it (the scene's settings, coarse-to-fine) to its end gives the
// re-simulated objective E*; then L-BFGS (discrete adjoint, one continuous LBFGS++ run
// without the production solver's 20-iteration chunks, unlimited iterations) gets a CPU
// budget of `budget_factor` x Pliant's CPU time to reach E*, from rest on the fine level
// ("plain") and from the coarse-to-fine start ("lbfgs_c2f", the stronger baseline).
// speedup = L-BFGS CPU time to E* / Pliant's CPU time; when L-BFGS does not reach E*
// (budget spent, line search failure without progress, convergence) it is a lower bound
// (lbfgs_reached false, lbfgs_stop_reason, the objective it reached).
#pragma once
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "pliant/smoke/control.h"

namespace pliant::smoke::bench {

struct ConvergedOptions {
  double budget_factor = 20;   // L-BFGS CPU budget in units of Pliant's CPU time
  double deadline_unix = 0;    // > 0: stop every run at this wall-clock time (reason "deadline")
  bool plain = true, c2f = true;  // which baselines to run
  // > 0: Pliant's result from an earlier run of the same case (E*, CPU s, IoU min), so a
  // second process can run the other baseline without repeating Pliant's solve.
  double given_objective = 0, given_pliant_s = 0, given_iou_min = 0;
};

// One JSON row per baseline (case "<name> converged lbfgs" / "... lbfgs coarse-to-fine"),
// each with the Pliant run's figures; `emit` is called with each row as soon as it exists.
void converged_comparison(const std::string& name, const ControlModel& m, const ConvergedOptions& o,
                          const std::function<void(const nlohmann::json&)>& emit);

}  // namespace pliant::smoke::bench
