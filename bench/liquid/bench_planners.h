// Planner cases of bench_liquid: held-out problems of the fixed-seed
// generator, each planned and then validated by the full simulator.
//   success_at_5: share of problems with under 5% spilled (validated)
//   mean_transfer: mean fraction in the target (validated)
//   plan_s: mean planning time per problem (validation excluded)
#pragma once
#include <omp.h>

#include <cstdio>
#include <string>
#include <nlohmann/json.hpp>
#include <vector>

#include "planners.h"
#include "pliant/core/progress.h"
#include "pliant/liquid/feedback.h"
#include "pliant/liquid/problem_generator.h"

// Case names: planner_<mode>_2d (TRANSFER+ZERO) or planner_<mode>_follow_2d
// (TRANSFER+FOLLOW: the same held-out ids with a moving target).
inline std::string planner_case(const char* mode, pliant::liquid::Family family) {
  return std::string("planner_") + mode + (family == pliant::liquid::Family::Follow ? "_follow" : "") + "_2d";
}

inline std::vector<nlohmann::json> bench_planners(bool quick, int count_override = 0,
                                                  pliant::liquid::Family family = pliant::liquid::Family::Zero) {
  using namespace pliant::liquid;
  const int count = count_override > 0 ? count_override : quick ? 3 : 20;
  const auto problems = held_out_problems(count, 2026, 2, family);
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
    out.push_back({{"case", planner_case(planner == Planner::Simplified ? "simplified" : "correction", family)},
                   {"family", family_name(family)},
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

// The feedback planner on held-out problems with the shipped network: the
// closed loop (MPC decisions + full simulator) is the validation run.
//   mpc_step_ms: mean time of one MPC decision (the networks over all
//   candidates and the horizon); the simulator's frames are not included.
inline nlohmann::json bench_feedback(int count, pliant::liquid::Family family = pliant::liquid::Family::Zero) {
  using namespace pliant::liquid;
  const FeedbackPredictor net = FeedbackPredictor::load(default_feedback_network());
  const auto problems = held_out_problems(count, 2026, 2, family);
  int success = 0;
  double transfer = 0, wall = 0, step_ms = 0, step_cpu_ms = 0, step_max = 0, plan_s = 0;
  nlohmann::json per = nlohmann::json::array();
  for (const auto& p : problems) {
    const double t0 = omp_get_wtime();
    const FeedbackRun run = run_feedback(p.model, net, MpcSettings{}, liquid_init(p.model), {}, nullptr);
    wall += omp_get_wtime() - t0;
    LiquidModel m = p.model;
    m.source_path = run.path;
    const auto fr = liquid_fractions(m, run.final_state);
    transfer += fr[0];
    success += fr[1] < 0.05;
    step_ms += run.mpc_step_ms_mean;
    step_cpu_ms += run.mpc_step_cpu_ms_mean;
    plan_s += run.mpc_step_ms_mean * run.mpc_steps * 1e-3;  // all decisions of the pour
    step_max = std::max(step_max, run.mpc_step_ms_max);
    per.push_back({{"id", p.id}, {"in_target", fr[0]}, {"spilled", fr[1]}, {"in_source", fr[2]},
                   {"mpc_step_ms", run.mpc_step_ms_mean}});
    std::fprintf(stderr, "  feedback problem %d: in target %.3f spilled %.3f left %.3f\n", p.id, fr[0], fr[1], fr[2]);
  }
  return {{"case", planner_case("feedback", family)},
          {"family", family_name(family)},
          {"problems", count},
          {"split", "held_out (generator seed 2026)"},
          {"training_samples", net.samples},
          {"success_at_5", double(success) / count},
          {"mean_transfer", transfer / count},
          {"plan_s", plan_s / count},
          {"mpc_step_ms", step_ms / count},
          {"mpc_step_ms_max", step_max},
          {"mpc_step_cpu_ms", step_cpu_ms / count},
          {"closed_loop_wall_s", wall / count},
          {"threads", omp_get_max_threads()},
          {"per_problem", per}};
}
