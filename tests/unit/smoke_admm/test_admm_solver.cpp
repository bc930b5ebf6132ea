// ADMM keyframe control end to end on the shipped circle-to-square scene (32^2 x 20),
// and the pieces it is built from against the control model's own operators.
#include <gtest/gtest.h>


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "admm_solver.h"
#include "ao_solver.h"
#include "control_coarse_to_fine.h"
#include "control_forward_model.h"
#include "nso_advection_stencil.h"
#include "nso_solver.h"
#include "control_test_util.h"
#include "pliant/core/scene.h"

namespace pliant::smoke {
namespace {

using control_detail::Vec;

ControlModel circle_to_square() {
  return control_compile(load_scene(std::string(PLIANT_ASSETS_DIR) + "/scenes/smoke_circle_to_square.json"));
}

TEST(AdmmPieces, PicardStencilReproducesTheForwardSelfAdvection) {
  const ControlModel m = circle_to_square();
  control_detail::ForwardOps ops(m, 1e-10);
  const auto z = test::random_velocity_series(ops, 1, 0.3, 5);
  const SpacetimeGrid sg(ops.grid(), 1);
  SlStencil s;
  build_sl_stencil(sg, z[0].data(), ops.dt(), s);
  Vec a(ops.faces()), b(ops.faces());
  sl_apply(sg, s, z[0].data(), a.data());
  ops.advect_velocity(z[0], b);
  // Weights are stored as float: agreement to float precision.
  for (size_t f = 0; f < a.size(); ++f) ASSERT_NEAR(a[f], b[f], 1e-6 * 0.3 * 5) << "face " << f;
}

TEST(AdmmPieces, AoGradientMatchesFiniteDifferences) {
  const ControlModel m = circle_to_square();
  control_detail::ForwardOps ops(m, 1e-10);
  const int T = m.sim.frames;
  auto u = test::random_velocity_series(ops, T, 0.05, 1), c = test::random_velocity_series(ops, T, 0.05, 2);
  AoSolver ao(m, ops);
  ao.div_penalty = 0.3;  // include the optional divergence term in the check
  std::vector<Vec> g(T, Vec(ops.faces()));
  ao.evaluate(u, c, 0.7, &g);
  std::mt19937 rng(3);
  for (int probe = 0; probe < 6; ++probe) {
    const int t = int(rng() % T);
    size_t f = rng() % ops.faces();
    while (std::abs(g[t][f]) < 1e-6) f = rng() % ops.faces();
    const double h = 1e-6, u0 = u[t][f];
    u[t][f] = u0 + h;
    const double jp = ao.evaluate(u, c, 0.7, nullptr);
    u[t][f] = u0 - h;
    const double jm = ao.evaluate(u, c, 0.7, nullptr);
    u[t][f] = u0;
    const double fd = (jp - jm) / (2 * h);
    EXPECT_NEAR(g[t][f], fd, 1e-5 * std::max(1.0, std::abs(fd))) << "frame " << t << " face " << f;
  }
}

TEST(AdmmPieces, NsoLevenbergMarquardtDecreasesItsEnergy) {
  ControlModel m = circle_to_square();
  m.r = 1e-2;  // strong coupling in time
  control_detail::ForwardOps ops(m, 1e-10);
  const int T = m.sim.frames;
  auto d = test::random_velocity_series(ops, T, 0.1, 9);
  std::vector<Vec> z(T, Vec(ops.faces(), 0.0));
  NsoSolver nso(m, ops);
  const NsoStats st = nso.solve(z, d, 1.0, 4, 2);
  EXPECT_LT(st.e_after, st.e_before);
  ASSERT_FALSE(st.vcycle_factors.empty());
  double reduction = 1;
  for (double f : st.vcycle_factors) reduction *= f;
  EXPECT_LT(reduction, 0.05);
  // z is divergence-free to the multigrid's accuracy.
  double dmax = 0, umax = 0;
  for (const auto& zt : z) {
    dmax = std::max(dmax, ops.max_divergence(zt));
    for (double v : zt) umax = std::max(umax, std::abs(v));
  }
  EXPECT_LT(dmax * ops.grid().h, 1e-2 * umax);
}

// Circle to square, 32^2 x 20 (the shipped scene, diagonal move). Measured (20
// iterations): the objective falls ~7x and the re-simulated IoU reaches ~0.65-0.7; the
// first-order upwind density smears the square's corners on this long diagonal move (see
// AdmmQualitySlow below for the 0.9 bar on a sideways move).
TEST(Admm, DecreasesTheObjectiveOnCircleToSquare) {
  ControlModel m = circle_to_square();
  m.progressive_preview = false;
  m.max_iterations = 20;
  ControlState s = control_init(m);
  Progress progress;
  std::vector<AdmmIterationStats> stats;
  admm_run(m, s, progress, {}, &stats);
  ASSERT_EQ(stats.size(), 20u);
  const double e0 = control_objective(m, FaceSeries(m.sim.frames, std::vector<float>(s.force[0].size(), 0.0f)), nullptr);
  EXPECT_LT(s.objective_history.back(), 0.2 * e0);
  // Decrease over iterations (ADMM is not monotone step by step): every 5-iteration
  // window's best beats the previous window's best until the plateau.
  EXPECT_LT(*std::min_element(s.objective_history.begin() + 10, s.objective_history.end()),
            *std::min_element(s.objective_history.begin(), s.objective_history.begin() + 5));
  // The state's forces are the best iteration's, and they re-simulate to its objective.
  const ControlMetrics cm = control_evaluate(m, s.force);
  const double best = *std::min_element(s.objective_history.begin(), s.objective_history.end());
  EXPECT_NEAR(cm.objective, best, 1e-3 * cm.objective);
  EXPECT_GE(cm.iou_min, 0.6);
  EXPECT_LT(cm.max_divergence, 1e-6);
}

// The shipped scene's text with replacements (grid size, geometry) applied.
ControlModel circle_to_square_variant(const std::vector<std::pair<std::string, std::string>>& edits) {
  std::ifstream in(std::string(PLIANT_ASSETS_DIR) + "/scenes/smoke_circle_to_square.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& [a, b] : edits) {
    const size_t p = text.find(a);
    if (p == std::string::npos) throw std::runtime_error("scene text lacks " + a);
    text.replace(p, a.size(), b);
  }
  return control_compile(parse_scene(text, "circle_to_square_variant.json"));
}

// Every checkpoint (ADMM iterations, the switch to the polish, L-BFGS chunks) resumes
// to exactly the uninterrupted run's forces and objective: the state holds everything
// the solver carries between outer iterations (NSO damping, phase; AO and L-BFGS
// memories restart per solve / chunk), and the running solver continues from the
// checkpoint's float values.
TEST(Admm, EveryCheckpointResumesToTheUninterruptedResult) {
  ControlModel m = circle_to_square_variant({{"[32, 32]", "[16, 16]"}, {"0.03125", "0.0625"}});
  m.max_iterations = 5;
  m.polish_iterations = 30;  // two L-BFGS chunks
  ControlState a = control_init(m);
  Progress progress;
  std::vector<std::vector<uint8_t>> checkpoints;
  ControlCallbacks cb;
  cb.on_iteration = [&](const ControlState& st) { checkpoints.push_back(control_state_serialize(st)); };
  control_solve_admm(m, a, progress, cb);
  ASSERT_GE(checkpoints.size(), 7u);  // 5 ADMM + switch + >= 1 chunk
  EXPECT_EQ(a.phase, 1);
  EXPECT_GT(a.iteration, m.max_iterations);
  // Resume from an ADMM iteration, from the switch to the polish and from the first
  // polish chunk (each resume is a full solve: three keep the test short).
  std::vector<size_t> picks{1};
  for (size_t k = 0; k + 1 < checkpoints.size() && picks.size() < 3; ++k)
    if (control_state_deserialize(checkpoints[k]).phase == 1) picks.push_back(k);
  bool resumed_admm = false, resumed_polish = false;
  for (size_t k : picks) {
    ControlState c = control_state_deserialize(checkpoints[k]);
    (c.phase == 0 ? resumed_admm : resumed_polish) = true;
    control_solve_admm(m, c, progress);
    ASSERT_EQ(c.iteration, a.iteration) << "checkpoint " << k;
    EXPECT_DOUBLE_EQ(c.objective_history.back(), a.objective_history.back()) << "checkpoint " << k;
    EXPECT_TRUE(c.force == a.force) << "checkpoint " << k;
  }
  EXPECT_TRUE(resumed_admm && resumed_polish);
}

// Coarse-to-fine levels checkpoint as well (ControlState::level): a run killed during
// the 32^2 level of a 64^2 problem resumes there and ends bit-identically where the
// uninterrupted run ends, for ADMM (from an ADMM iteration and from the polish) and
// for the L-BFGS baseline (which uses the same levels).
TEST(Admm, CoarseLevelCheckpointsResumeToTheUninterruptedResult) {
  ControlModel m = circle_to_square_variant(
      {{"[32, 32]", "[64, 64]"}, {"0.03125", "0.015625"}, {"\"frames\": 20", "\"frames\": 6"}, {"\"frame\": 20", "\"frame\": 6"}});
  m.progressive_preview = true;
  m.max_iterations = 2;
  m.polish_iterations = 4;
  Progress progress;
  for (const ControlMethod method : {ControlMethod::Admm, ControlMethod::Lbfgs}) {
    m.method = method;
    auto solve = [&](ControlState& st, const ControlCallbacks& cb) {
      if (method == ControlMethod::Admm) control_solve_admm(m, st, progress, cb);
      else control_solve_lbfgs(m, st, progress, cb);
    };
    ControlState a = control_init(m);
    std::vector<std::vector<uint8_t>> coarse;
    int fine = 0;
    ControlCallbacks cb;
    cb.on_iteration = [&](const ControlState& st) {
      if (st.level == 0) return void(++fine);
      EXPECT_EQ(st.level, 1);
      EXPECT_TRUE(control_state_fits(m, st));
      coarse.push_back(control_state_serialize(st));
    };
    solve(a, cb);
    EXPECT_EQ(a.level, 0);
    ASSERT_GE(coarse.size(), method == ControlMethod::Admm ? 4u : 1u);  // ADMM: 2 + switch + polish chunk
    EXPECT_GE(fine, 1);
    // The first coarse checkpoint, and for ADMM the polish switch as well.
    std::vector<size_t> picks{0};
    if (method == ControlMethod::Admm)
      for (size_t k = 1; k < coarse.size(); ++k)
        if (control_state_deserialize(coarse[k]).phase == 1) {
          picks.push_back(k);
          break;
        }
    for (size_t k : picks) {
      ControlState c = control_state_deserialize(coarse[k]);
      ASSERT_EQ(c.level, 1);
      solve(c, {});
      EXPECT_EQ(c.level, 0);
      const char* name = method == ControlMethod::Admm ? "admm" : "lbfgs";
      ASSERT_EQ(c.iteration, a.iteration) << name << " coarse checkpoint " << k;
      EXPECT_DOUBLE_EQ(c.objective_history.back(), a.objective_history.back()) << name << " coarse checkpoint " << k;
      EXPECT_TRUE(c.force == a.force) << name << " coarse checkpoint " << k;
    }
  }
  // A state of a level the model does not have is refused.
  ControlState bad = control_init(m);
  bad.level = 2;
  EXPECT_FALSE(control_state_fits(m, bad));
}

// The shipped FLUID / letter schedule: ADMM on the coarse level only (max_iterations 0,
// coarse_iterations N), the L-BFGS polish on every level in chunks of lbfgs_chunk. The
// callbacks count N ADMM iterations on the 32^2 level, none on 64^2, and one polish
// checkpoint per chunk; changing coarse_iterations, lbfgs_chunk or coarse_admm_levels
// changes those counts.
TEST(Admm, CoarseOnlyScheduleRunsAdmmOnTheCoarseLevelsOnly) {
  ControlModel m = circle_to_square_variant(
      {{"[32, 32]", "[64, 64]"}, {"0.03125", "0.015625"}, {"\"frames\": 20", "\"frames\": 6"}, {"\"frame\": 20", "\"frame\": 6"}});
  m.progressive_preview = true;
  m.max_iterations = 0;
  m.polish_iterations = 6;
  auto counts = [&](int coarse_iterations, int chunk) {
    m.coarse_iterations = coarse_iterations;
    m.lbfgs_chunk = chunk;
    std::map<std::pair<int, int>, int> n;  // (level, phase) -> checkpoints
    ControlCallbacks cb;
    cb.on_iteration = [&](const ControlState& st) { ++n[{st.level, st.phase}]; };
    ControlState s = control_init(m);
    Progress progress;
    control_solve_admm(m, s, progress, cb);
    EXPECT_EQ(s.level, 0);
    EXPECT_EQ(s.phase, 1);
    return n;
  };
  auto a = counts(3, 100);
  EXPECT_EQ(a[std::make_pair(1, 0)], 3);  // ADMM on 32^2 (the stall rule needs 6)
  EXPECT_EQ(a[std::make_pair(0, 0)], 0);  // none on 64^2
  EXPECT_EQ(a[std::make_pair(1, 1)], 2);  // the switch + one polish chunk of <= 6
  EXPECT_EQ(a[std::make_pair(0, 1)], 2);
  auto b = counts(2, 2);
  EXPECT_EQ(b[std::make_pair(1, 0)], 2);
  EXPECT_EQ(b[std::make_pair(0, 0)], 0);
  EXPECT_GT(b[std::make_pair(0, 1)], a[std::make_pair(0, 1)]);  // chunks of 2: more polish checkpoints (unless it stops early)
  // coarse_admm_levels 0: no level runs ADMM (1 would be the 32^2 level, as above).
  m.coarse_admm_levels = 0;
  auto c = counts(3, 100);
  EXPECT_EQ(c[std::make_pair(1, 0)], 0);
  // The switch + the polish from rest: a failed first line search (disjoint target, flat
  // objective at rest) restarts it once; the old one-iteration stop ended it at once.
  EXPECT_GE(c[std::make_pair(1, 1)], 2);
  m.coarse_admm_levels = 1;
  EXPECT_EQ(counts(3, 100)[std::make_pair(1, 0)], 3);
}

TEST(Admm, StopsWhenTheObjectiveStalls) {
  EXPECT_FALSE(admm_stalled({10, 9, 8, 7, 6}));           // too short to judge
  EXPECT_FALSE(admm_stalled({10, 9, 8, 7, 6, 5.9}));      // still improving
  EXPECT_TRUE(admm_stalled({10, 9, 8, 7, 7.5, 7.2, 7.1}));     // last 3 not below 7
  EXPECT_TRUE(admm_stalled({10, 9, 8, 7, 7, 6.9999, 7}));      // under 0.1% better
  EXPECT_FALSE(admm_stalled({10, 12, 13, 14, 9.9, 20}));  // a new best among the last 3
}

TEST(Admm, ResumesFromItsStateAndCallsBack) {
  ControlModel m = circle_to_square();
  m.progressive_preview = false;
  m.max_iterations = 4;
  m.polish_iterations = 0;
  ControlState a = control_init(m);
  Progress progress;
  int calls = 0;
  ControlCallbacks cb;
  cb.on_iteration = [&](const ControlState& st) {
    ++calls;
    EXPECT_EQ(int(st.objective_history.size()), st.iteration);
  };
  control_solve_admm(m, a, progress, cb);
  EXPECT_EQ(calls, 4);
  // Stop after 2, serialise, resume to 4: same result as the uninterrupted run.
  m.max_iterations = 2;
  ControlState b = control_init(m);
  control_solve_admm(m, b, progress);
  ControlState c = control_state_deserialize(control_state_serialize(b));
  m.max_iterations = 4;
  control_solve_admm(m, c, progress);
  ASSERT_EQ(c.iteration, 4);
  EXPECT_DOUBLE_EQ(c.objective_history.back(), a.objective_history.back());
}

// Progressive preview: a 64^2 problem is first solved at 32^2; the preview shows that
// coarse trajectory (T+1 frames, mass conserved by the upwind operator) before the
// fine iterations start from its prolonged forces (control_coarse_to_fine.h).
TEST(Admm, ProgressivePreviewShowsTheCoarseSolutionFirst) {
  std::ifstream in(std::string(PLIANT_ASSETS_DIR) + "/scenes/smoke_circle_to_square.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto replace = [&](const std::string& a, const std::string& b) {
    const size_t p = text.find(a);
    ASSERT_NE(p, std::string::npos) << a;
    text.replace(p, a.size(), b);
  };
  replace("[32, 32]", "[64, 64]");
  replace("0.03125", "0.015625");
  ControlModel m = control_compile(parse_scene(text, "circle_to_square_64.json"));
  m.max_iterations = 2;
  m.polish_iterations = 0;
  m.progressive_preview = true;
  ControlState s = control_init(m);
  Progress progress;
  int previews = 0, iterations = 0;
  ControlCallbacks cb;
  cb.on_preview = [&](const GridDims& d, const std::vector<std::vector<float>>& density) {
    ++previews;
    EXPECT_EQ(iterations, 0) << "preview must come before the fine iterations";
    EXPECT_EQ(d.n[0], 32);
    EXPECT_EQ(d.n[1], 32);
    ASSERT_EQ(int(density.size()), m.sim.frames + 1);
    double m0 = 0, mT = 0;
    for (float v : density.front()) m0 += v;
    for (float v : density.back()) mT += v;
    EXPECT_NEAR(mT, m0, 1e-4 * m0);
  };
  cb.on_iteration = [&](const ControlState& st) { iterations += st.level == 0; };  // coarse ones checkpoint too
  control_solve_admm(m, s, progress, cb);
  // One 32^2 level of 2 iterations: previews after its iterations 1 and 2 (powers of
  // two, so the editor sees the first within one coarse iteration) and at its end.
  EXPECT_EQ(previews, 3);
  EXPECT_EQ(iterations, 2);
  // The fine run starts from the prolonged coarse solution, not from rest.
  const double e0 = control_objective(m, FaceSeries(m.sim.frames, std::vector<float>(s.force[0].size(), 0.0f)), nullptr);
  EXPECT_LT(s.objective_history.front(), e0);
}

// Issue 3's quality bar: a 32^2 x 20 circle-to-square problem re-simulates at IoU >= 0.9.
// Here the circle moves sideways by 0.3 of the box (the shipped scene moves it along the
// diagonal, 0.45, where first-order upwind smearing caps every solver found so far at
// IoU ~0.78, see engine/smoke/README.md). ADMM alone: IoU 0.89 at 30 iterations;
// with the L-BFGS polish from its forces 0.93 (measured). Release only (label slow):
// ~4 s here, several times that under ASan.
TEST(AdmmQualitySlow, CircleToSquare32x20ReachesIoU09) {
  ControlModel m = circle_to_square_variant({{"[0.3, 0.3]", "[0.35, 0.5]"}, {"[0.62, 0.62]", "[0.65, 0.5]"}});
  m.max_iterations = 15;
  m.nso_vcycles = 2;
  m.polish_iterations = 40;
  ControlState s = control_init(m);
  Progress progress;
  control_solve_admm(m, s, progress);
  const ControlMetrics cm = control_evaluate(m, s.force);
  EXPECT_GE(cm.iou_min, 0.9) << "relative L2 " << cm.keyframes[0].relative_l2;
  EXPECT_LT(cm.max_divergence, 1e-6);
}

}  // namespace
}  // namespace pliant::smoke
