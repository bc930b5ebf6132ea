// Planner cases of bench_liquid: held-out problems of the fixed-seed
// generator, each planned and then validated by the full simulator.
//   success_at_5: share of problems with under 5% spilled (validated)
//   mean_transfer: mean fraction in the target (validated)
//   plan_s: mean planning time per problem (validation excluded)
#pragma once
#include <omp.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <vector>

#include "planners.h"
#include "pliant/core/progress.h"
#include "pliant/liquid/problem_generator.h"

inline std::vector<nlohmann::json> bench_planners(bool quick) {
  using namespace pliant::liquid;
  const int count = quick ? 3 : 20;
  const auto problems = held_out_problems(count, 2026);
  std::vector<nlohmann::json> out;
  for (Planner planner : {Planner::Simplified, Planner::Correction}) {
    int success = 0;
    double transfer = 0, plan_s = 0, validate_s = 0;
    nlohmann::json per = nlohmann::json::array();
    for (const auto& p : problems) {
      LiquidModel m = p.model;
      pliant::Progress progress;
      const double t0 = omp_get_wtime();
      m.source_path = planner == Planner::Simplified ? plan_simplified(m, progress, nullptr)
                                                     : plan_correction(m, progress, nullptr);
      const double t1 = omp_get_wtime();
      const auto fr = simulate_fractions(m);
      validate_s += omp_get_wtime() - t1;
      plan_s += t1 - t0;
      transfer += fr[0];
      success += fr[1] < 0.05;
      per.push_back({{"id", p.id}, {"in_target", fr[0]}, {"spilled", fr[1]}, {"in_source", fr[2]}, {"plan_s", t1 - t0}});
      std::fprintf(stderr, "  problem %d: in target %.3f spilled %.3f\n", p.id, fr[0], fr[1]);
    }
    out.push_back({{"case", std::string("planner_") + (planner == Planner::Simplified ? "simplified" : "correction") + "_2d"},
                   {"problems", count},
                   {"split", "held_out (generator seed 2026)"},
                   {"success_at_5", double(success) / count},
                   {"mean_transfer", transfer / count},
                   {"plan_s", plan_s / count},
                   {"validate_s", validate_s / count},
                   {"threads", omp_get_max_threads()},
                   {"per_problem", per}});
  }
  return out;
}
