// Each planner on three fixed 2D problems; every plan is validated by the full
// simulator. Slow (tens of seconds): label "slow" in CMakeLists.
#include <gtest/gtest.h>

#include <filesystem>

#include "planners.h"
#include "pliant/core/progress.h"
#include "pliant/liquid/feedback.h"
#include "pliant/liquid/liquid.h"

namespace pliant::liquid {
namespace {

LiquidModel problem(int which) {
  nlohmann::json d = {
      {"pliant", 1}, {"kind", "liquid"}, {"dim", 2},
      {"domain", {{"min_m", {-0.15, 0}}, {"max_m", {0.4, 0.4}}, {"cell_size_m", 0.006}}},
      {"time", {{"dt_s", 0.02}, {"frames", 130}}},
      {"liquid", {{"viscosity_pa_s", 0.01}, {"fill_fraction", 0.6}}},
      {"source", {{"container", {{"shape", "cylinder"}, {"radius_m", 0.04}, {"height_m", 0.12}, {"wall_m", 0.012}}},
                  {"position_m", {0, 0.2}}}},
      {"target", {{"container", {{"shape", "cylinder"}, {"radius_m", 0.07}, {"height_m", 0.08}, {"wall_m", 0.012}}},
                  {"position_m", {0.22, 0}}}},
      {"planner", {{"pour_time_s", 2.0}, {"iterations", 4}}}};
  if (which == 1) {  // viscous liquid in a box, farther target
    d["liquid"]["viscosity_pa_s"] = 0.5;
    d["source"]["container"]["shape"] = "box";
    d["target"]["position_m"] = {0.26, 0};
  } else if (which == 2) {  // less liquid, nearer and smaller target
    d["liquid"]["fill_fraction"] = 0.4;
    d["target"]["position_m"] = {0.18, 0};
    d["target"]["container"]["radius_m"] = 0.06;
  }
  return liquid_compile(parse_scene(d.dump(), "problem" + std::to_string(which) + ".json"));
}

void expect_transfer(Planner planner) {
  for (int which = 0; which < 3; ++which) {
    LiquidModel m = problem(which);
    Progress progress;
    m.source_path = planner == Planner::Simplified ? plan_simplified(m, progress, nullptr)
                                                   : plan_correction(m, progress, nullptr);
    const auto fr = simulate_fractions(m);
    EXPECT_GE(fr[0], 0.9) << "problem " << which << ": spilled " << fr[1] << ", left " << fr[2];
  }
}

// The feedback planner with the network shipped in assets/: the closed loop
// (MPC + full simulator) is itself the validation run.
TEST(Planners, FeedbackTransfersNinetyPercent) {
  const FeedbackPredictor net =
      FeedbackPredictor::load(std::filesystem::path(PLIANT_ASSETS_DIR) / "sweeps/liquid_dataset_net.json");
  for (int which = 0; which < 3; ++which) {
    const LiquidModel m = problem(which);
    const FeedbackRun run = run_feedback(m, net, MpcSettings{}, liquid_init(m), {}, nullptr);
    LiquidModel validated = m;
    validated.source_path = run.path;
    const auto fr = liquid_fractions(validated, run.final_state);
    EXPECT_GE(fr[0], 0.9) << "problem " << which << ": spilled " << fr[1] << ", left " << fr[2];
  }
}

// TRANSFER+FOLLOW: problem 0 with the target moving away from the source at
// 3 cm/s (7.8 cm over the run); every planner must follow it.
TEST(Planners, FollowTargetEachPlannerTransfersNinetyPercent) {
  LiquidModel m = problem(0);
  m.target_velocity_mps = {0.03, 0, 0};
  const FeedbackPredictor net =
      FeedbackPredictor::load(std::filesystem::path(PLIANT_ASSETS_DIR) / "sweeps/liquid_dataset_net.json");
  const FeedbackRun run = run_feedback(m, net, MpcSettings{}, liquid_init(m), {}, nullptr);
  LiquidModel fb = m;
  fb.source_path = run.path;
  const auto f0 = liquid_fractions(fb, run.final_state);
  EXPECT_GE(f0[0], 0.9) << "feedback: spilled " << f0[1] << ", left " << f0[2];
  for (Planner planner : {Planner::Correction, Planner::Simplified}) {
    LiquidModel p = m;
    Progress progress;
    p.source_path = planner == Planner::Simplified ? plan_simplified(p, progress, nullptr)
                                                   : plan_correction(p, progress, nullptr);
    const auto fr = simulate_fractions(p);
    EXPECT_GE(fr[0], 0.9) << (planner == Planner::Simplified ? "simplified" : "correction") << ": spilled "
                          << fr[1] << ", left " << fr[2];
  }
}

TEST(Planners, CorrectionTransfersNinetyPercent) { expect_transfer(Planner::Correction); }
TEST(Planners, SimplifiedTransfersNinetyPercent) { expect_transfer(Planner::Simplified); }

}  // namespace
}  // namespace pliant::liquid
