// soft_compile's `optimizer` section, the pure L-BFGS variant keys (2026-12-01):
// lbfgs_line_search, lbfgs_memory, lbfgs_initial_step (0 = the raw-gradient first
// step), lbfgs_restarts reach OptimizerSettings, keep their defaults when absent, and a
// bad value is an InputError at its JSON pointer that says what is allowed. (The
// shipped worm that pins L-BFGS with them crawls: test_soft_job_shipped.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"

using namespace pliant;
using pliant::soft::OptimizerSettings;

namespace {
// A small worm; only the optimizer section varies (nothing is optimized here).
Scene optimizer_worm_with(const std::string& optimizer) {
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "worm.obj", "resolution": 4, "modes": 4},
    "environment": {"type": "ground", "friction": 0.6},
    "simulation": {"dt_s": 0.04, "frames": 5},
    "controller": {"modes": 2, "kernels": 2, "period_s": 0.4},
    "objectives": {"velocity": {"target_m_per_s": [0.05, 0, 0], "weight": 100}},
    "optimizer": )" + optimizer + "}";
  return parse_scene(text, "opt.json", std::string(PLIANT_ASSETS_DIR) + "/characters");
}

struct OptimizerFailure {
  std::string pointer, problem;
};

OptimizerFailure optimizer_failure_of(const std::string& optimizer) {
  try {
    soft::soft_compile(optimizer_worm_with(optimizer));
  } catch (const InputError& e) {
    return {e.pointer(), e.problem()};
  }
  return {"no error", ""};
}
}  // namespace

TEST(SoftCompileOptimizer, LbfgsKeysDefaultToTheSettingsBefore) {
  const OptimizerSettings def;
  const soft::SoftModel m = soft::soft_compile(optimizer_worm_with(R"({"method": "lbfgs", "iterations": 0})"));
  EXPECT_EQ(m.optimizer.lbfgs_line_search, def.lbfgs_line_search);
  EXPECT_EQ(m.optimizer.lbfgs_line_search, OptimizerSettings::LineSearch::Armijo);
  EXPECT_EQ(m.optimizer.lbfgs_memory, def.lbfgs_memory);
  EXPECT_EQ(m.optimizer.lbfgs_initial_step, def.lbfgs_initial_step);
  EXPECT_EQ(m.optimizer.lbfgs_restarts, def.lbfgs_restarts);
}

TEST(SoftCompileOptimizer, LbfgsKeysReachTheSettings) {
  const soft::SoftModel m = soft::soft_compile(optimizer_worm_with(
      R"({"method": "lbfgs", "iterations": 0, "lbfgs_line_search": "wolfe", "lbfgs_memory": 4,
          "lbfgs_initial_step": 0, "lbfgs_restarts": 3})"));
  EXPECT_EQ(m.optimizer.kind, soft::OptimizerKind::LBFGS);
  EXPECT_EQ(m.optimizer.lbfgs_line_search, OptimizerSettings::LineSearch::Wolfe);
  EXPECT_EQ(m.optimizer.lbfgs_memory, 4);
  EXPECT_EQ(m.optimizer.lbfgs_initial_step, 0.0);  // the raw-gradient first step
  EXPECT_EQ(m.optimizer.lbfgs_restarts, 3);
  // Every name the optimizer parses is accepted, and means that search.
  for (const char* name : {"armijo", "wolfe", "strong_wolfe", "bracketing", "nocedal_wright"}) {
    const soft::SoftModel k = soft::soft_compile(
        optimizer_worm_with(std::string(R"({"iterations": 0, "lbfgs_line_search": ")") + name + "\"}"));
    EXPECT_EQ(k.optimizer.lbfgs_line_search, soft::parse_line_search(name)) << name;
    EXPECT_STREQ(soft::line_search_name(k.optimizer.lbfgs_line_search), name);
  }
  // The hybrid's own L-BFGS phase search stays its own key.
  EXPECT_EQ(m.optimizer.hybrid_lbfgs_line_search, OptimizerSettings::LineSearch::Armijo);
}

TEST(SoftCompileOptimizer, BadLbfgsValuesAreInputErrorsAtTheirPointers) {
  const auto expect = [](const std::string& optimizer, const std::string& pointer, const std::string& allowed) {
    const OptimizerFailure f = optimizer_failure_of(optimizer);
    EXPECT_EQ(f.pointer, pointer) << optimizer;
    EXPECT_NE(f.problem.find(allowed), std::string::npos) << optimizer << ": " << f.problem;
  };
  expect(R"({"lbfgs_line_search": "more_thuente"})", "/optimizer/lbfgs_line_search", "nocedal_wright");
  expect(R"({"lbfgs_line_search": "Wolfe"})", "/optimizer/lbfgs_line_search", "strong_wolfe");
  expect(R"({"lbfgs_line_search": 1})", "/optimizer/lbfgs_line_search", "armijo");
  expect(R"({"lbfgs_memory": 0})", "/optimizer/lbfgs_memory", "positive integer");
  expect(R"({"lbfgs_memory": 2.5})", "/optimizer/lbfgs_memory", "integer");
  expect(R"({"lbfgs_memory": 100000})", "/optimizer/lbfgs_memory", "1000");
  expect(R"({"lbfgs_initial_step": -1})", "/optimizer/lbfgs_initial_step", "[0,");
  expect(R"({"lbfgs_initial_step": "raw"})", "/optimizer/lbfgs_initial_step", "number");
  expect(R"({"lbfgs_restarts": -1})", "/optimizer/lbfgs_restarts", "non-negative integer");
  expect(R"({"lbfgs_restarts": true})", "/optimizer/lbfgs_restarts", "integer");
  expect(R"({"lbfgs_restrats": 2})", "/optimizer/lbfgs_restrats", "lbfgs_restarts");
}
