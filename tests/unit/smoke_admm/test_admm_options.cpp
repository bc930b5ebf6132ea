// ADMM options of the ninth session: residual balancing of the penalty (Boyd et al. 2011,
// Sec. 3.4.1), over-relaxation (Sec. 3.4.3), the adaptive switch to the polish, and the
// checkpoint format that carries the balanced penalty (version 5; version 4 still loads).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <utility>
#include <stdexcept>
#include <string>
#include <vector>

#include "admm_solver.h"
#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/control.h"

namespace pliant::smoke {
namespace {

// A shipped scene at 16^2 (circle to square x 20 frames, about 0.03 s per ADMM iteration;
// circle to the letter P x 40 frames, 0.04 s), with `admm_fields` added to its "admm" object
// (the scene format's compile path).
ControlModel admmopt_small(const std::string& admm_fields = "", bool letter = false) {
  std::ifstream in(std::string(PLIANT_ASSETS_DIR) + "/scenes/" +
                   (letter ? "smoke_circle_to_letter.json" : "smoke_circle_to_square.json"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto replace = [&](const std::string& a, const std::string& b) {
    const size_t p = text.find(a);
    if (p == std::string::npos) throw std::runtime_error("scene text lacks " + a);
    text.replace(p, a.size(), b);
  };
  replace(letter ? "[64, 64]" : "[32, 32]", "[16, 16]");
  replace(letter ? "0.015625" : "0.03125", "0.0625");
  const std::string polish = "\"polish_iterations\": 40";  // both scenes have it
  if (!admm_fields.empty()) replace(polish, polish + ", " + admm_fields);
  ControlModel m = control_compile(parse_scene(text, "admmopt_small.json"));
  m.progressive_preview = false;
  m.polish_iterations = 0;
  return m;
}

ControlState admmopt_run(const ControlModel& m, std::vector<AdmmIterationStats>* stats = nullptr,
                         std::vector<std::vector<uint8_t>>* checkpoints = nullptr) {
  ControlState s = control_init(m);
  Progress progress;
  ControlCallbacks cb;
  if (checkpoints) cb.on_iteration = [&](const ControlState& st) { checkpoints->push_back(control_state_serialize(st)); };
  admm_run(m, s, progress, cb, stats);
  return s;
}

double admmopt_best(const ControlState& s) {
  return *std::min_element(s.objective_history.begin(), s.objective_history.end());
}

TEST(AdmmOptions, SceneFieldsCompileAndBadValuesNameTheField) {
  const ControlModel m = admmopt_small(R"("balance_mu": 10, "balance_tau": 3, "relaxation": 1.6, "switch_progress": 0.02)");
  EXPECT_EQ(m.admm_balance_mu, 10);
  EXPECT_EQ(m.admm_balance_tau, 3);
  EXPECT_EQ(m.admm_relaxation, 1.6);
  EXPECT_EQ(m.admm_switch_progress, 0.02);
  for (const char* bad : {R"("balance_mu": 0.5)", R"("balance_tau": 1)", R"("relaxation": 2.5)", R"("switch_progress": -1)"}) {
    try {
      admmopt_small(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      const std::string field = std::string(bad).substr(1, std::string(bad).find('"', 1) - 1);
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

// Residual balancing keeps ADMM decreasing and ends at least as low as the continuation
// schedule on the same iterations (16^2 x 40 letter, mu 3: 7.76 against 8.06; on the 16^2
// square the two tie, 5.95 / 5.99); its penalty really moves (state, not a function of k).
TEST(AdmmOptions, ResidualBalancingDecreasesAndEndsAtLeastAsLowAsTheSchedule) {
  ControlModel m = admmopt_small("", true);
  m.max_iterations = 10;
  const ControlState schedule = admmopt_run(m);
  m.admm_balance_mu = 3;
  std::vector<AdmmIterationStats> st;
  const ControlState balanced = admmopt_run(m, &st);
  ASSERT_GE(st.size(), 9u);
  const double e0 = control_objective(m, FaceSeries(m.sim.frames, std::vector<float>(balanced.force[0].size(), 0.0f)), nullptr);
  const auto& h = balanced.objective_history;
  EXPECT_LT(admmopt_best(balanced), 0.3 * e0);
  // Each 3-iteration window's best beats everything before it (ADMM is not monotone step by step).
  for (size_t w = 3; w + 3 <= h.size(); w += 3)
    EXPECT_LT(*std::min_element(h.begin() + w, h.begin() + w + 3), *std::min_element(h.begin(), h.begin() + w)) << w;
  EXPECT_LE(admmopt_best(balanced), admmopt_best(schedule));
  bool moved = false;
  for (size_t k = 1; k < st.size(); ++k) moved |= st[k].beta != st[k - 1].beta;
  EXPECT_TRUE(moved);
  EXPECT_EQ(st[0].beta, admm_penalty_at(m, 0));
  EXPECT_GT(balanced.admm_beta, 0);
  EXPECT_EQ(schedule.admm_beta, 0);
}

// alpha = 1 is the plain update bit for bit; another alpha takes another path that still
// decreases the objective.
TEST(AdmmOptions, RelaxationOneIsBitIdenticalToPlainAdmm) {
  ControlModel m = admmopt_small();
  m.max_iterations = 5;
  const ControlState plain = admmopt_run(m);
  m.admm_relaxation = 1.0;
  const ControlState one = admmopt_run(m);
  EXPECT_TRUE(one.force == plain.force);
  EXPECT_TRUE(one.split == plain.split && one.dual == plain.dual && one.velocity == plain.velocity);
  EXPECT_TRUE(one.objective_history == plain.objective_history);
  m.admm_relaxation = 1.6;
  const ControlState relaxed = admmopt_run(m);
  EXPECT_FALSE(relaxed.split == plain.split);
  EXPECT_LT(admmopt_best(relaxed), 0.5 * relaxed.objective_history.front());
}

TEST(AdmmOptions, SwitchStopsWhenTheLastIterationGainedTooLittle) {
  EXPECT_FALSE(admm_progress_below({10, 5}, 0.05));            // too short to judge
  EXPECT_FALSE(admm_progress_below({10, 9, 8}, 0.05));         // 11% better
  EXPECT_TRUE(admm_progress_below({10, 9, 8.8}, 0.05));        // 2.2% better
  EXPECT_TRUE(admm_progress_below({10, 9, 9.5}, 0.05));        // worse than the best
  EXPECT_FALSE(admm_progress_below({10, 9, 8.8}, 0.0));        // off
  ControlModel m = admmopt_small();
  m.max_iterations = 30;
  m.admm_switch_progress = 0.05;
  const ControlState s = admmopt_run(m);
  ASSERT_LT(s.iteration, 30);
  ASSERT_GE(s.objective_history.size(), 3u);
  EXPECT_TRUE(admm_progress_below(s.objective_history, 0.05));
  std::vector<double> before(s.objective_history.begin(), s.objective_history.end() - 1);
  EXPECT_FALSE(admm_progress_below(before, 0.05));
}

// A run with all three options, killed after any iteration (its checkpoint), resumes to the
// uninterrupted run's objective and forces: the balanced beta travels in the checkpoint.
TEST(AdmmOptions, CheckpointsWithTheNewOptionsResumeToTheSameResult) {
  ControlModel m = admmopt_small();
  m.max_iterations = 8;
  m.admm_balance_mu = 3;
  m.admm_relaxation = 1.6;
  m.admm_switch_progress = 1e-3;
  std::vector<std::vector<uint8_t>> cps;
  const ControlState a = admmopt_run(m, nullptr, &cps);
  ASSERT_GE(cps.size(), 5u);
  for (size_t k : {size_t(1), size_t(3)}) {
    ControlState c = control_state_deserialize(cps[k]);
    ASSERT_GT(c.admm_beta, 0);
    Progress progress;
    admm_run(m, c, progress, {}, nullptr);
    ASSERT_EQ(c.iteration, a.iteration) << k;
    EXPECT_EQ(c.objective_history.back(), a.objective_history.back()) << k;
    EXPECT_TRUE(c.force == a.force) << k;
    EXPECT_EQ(c.admm_beta, a.admm_beta) << k;
  }
  // Without the stored beta (as a version-4 checkpoint would load) the run takes another path.
  ControlState lost = control_state_deserialize(cps[3]);
  lost.admm_beta = 0;
  Progress progress;
  admm_run(m, lost, progress, {}, nullptr);
  EXPECT_FALSE(lost.force == a.force);
}

// A version-4 checkpoint (before the ADMM penalty field) still loads, with admm_beta 0
// (the continuation schedule's beta) and every other field as written.
TEST(AdmmOptions, Version4CheckpointsStillLoad) {
  ControlModel m = admmopt_small();
  m.max_iterations = 2;
  const ControlState s = admmopt_run(m);
  std::vector<uint8_t> v5 = control_state_serialize(s);
  uint32_t version = 0;
  std::memcpy(&version, v5.data() + 4, 4);
  ASSERT_EQ(version, 5u);
  std::vector<uint8_t> v4(v5.begin(), v5.end() - sizeof(double));
  version = 4;
  std::memcpy(v4.data() + 4, &version, 4);
  const ControlState r = control_state_deserialize(v4);
  EXPECT_EQ(r.admm_beta, 0);
  EXPECT_EQ(r.iteration, s.iteration);
  EXPECT_TRUE(r.force == s.force && r.split == s.split && r.dual == s.dual);
  EXPECT_TRUE(r.objective_history == s.objective_history);
  EXPECT_EQ(control_state_serialize(r), v5);  // admm_beta 0 written back: the same bytes
  // A version-5 checkpoint cut before its last field is truncated, not silently old.
  std::vector<uint8_t> cut(v5.begin(), v5.end() - 4);
  EXPECT_THROW(control_state_deserialize(cut), std::runtime_error);
}

// coarse_polish_iterations caps the polish of the coarse levels only (the fine level keeps
// polish_iterations): a 64^2 x 6 square, one coarse ADMM iteration, polish 1 coarse / 3 fine.
TEST(AdmmOptions, CoarsePolishIterationsCapOnlyTheCoarseLevels) {
  std::ifstream in(std::string(PLIANT_ASSETS_DIR) + "/scenes/smoke_circle_to_square.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& [a, b] : std::vector<std::pair<std::string, std::string>>{
           {"[32, 32]", "[64, 64]"}, {"0.03125", "0.015625"}, {"\"frames\": 20", "\"frames\": 6"},
           {"\"frame\": 20", "\"frame\": 6"}, {"\"polish_iterations\": 40", "\"polish_iterations\": 3, \"coarse_polish_iterations\": 1"}})
    text.replace(text.find(a), a.size(), b);
  ControlModel m = control_compile(parse_scene(text, "admmopt_coarse_polish.json"));
  ASSERT_EQ(m.coarse_polish_iterations, 1);
  m.max_iterations = 0;
  m.coarse_iterations = 1;
  m.tolerance = 1e-12;  // the polish runs to its cap
  ControlState s = control_init(m);
  Progress progress;
  std::map<int, int> last_polish;  // level -> last polish iteration number
  ControlCallbacks cb;
  cb.on_iteration = [&](const ControlState& st) {
    if (st.phase == 1) last_polish[st.level] = st.iteration;
  };
  control_solve_admm(m, s, progress, cb);
  ASSERT_EQ(last_polish.count(1), 1u);
  EXPECT_EQ(last_polish[1], 1 + 1);  // numbered after the level's 1 ADMM iteration
  EXPECT_EQ(last_polish[0], 0 + 3);
}

}  // namespace
}  // namespace pliant::smoke
