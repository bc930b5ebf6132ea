// OptimizerState's checkpoint form (optimizer_state.cpp): a state serialized after
// iteration k and restored continues bit for bit as the run that was never stopped
// (LM with Broyden reuse, L-BFGS with its curvature pairs, restarts and a Wolfe
// search, the hybrid in and out of its L-BFGS phase, fused trials with the trust
// region); every truncation and a damaged byte are errors, never a crash.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <string>
#include <vector>

#include "optimizer_test_problems.h"
#include "pliant/core/crc32.h"
#include "pliant/soft/optimizer.h"

using namespace pliant::soft;

namespace {

bool state_bits_equal(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (std::bit_cast<uint64_t>(a[i]) != std::bit_cast<uint64_t>(b[i])) return false;
  return true;
}

bool state_bits_equal(const std::vector<double>& a, const std::vector<double>& b) {
  return state_bits_equal(Eigen::Map<const Eigen::VectorXd>(a.data(), Eigen::Index(a.size())),
                   Eigen::Map<const Eigen::VectorXd>(b.data(), Eigen::Index(b.size())));
}

const ResidualFn kStateRf = [](const Eigen::VectorXd& x) { return test::rosenbrock_residuals(x); };
const JacobianFn kStateJf = [](const Eigen::VectorXd& x, const Eigen::VectorXd&) {
  return test::rosenbrock_jacobian(x);
};
const ResidualJacobianFn kStateFf = [](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
  r = test::rosenbrock_residuals(x);
  return test::rosenbrock_jacobian(x);
};

OptimizerState state_start(double x0 = -1.2) {
  OptimizerState st;
  st.theta = Eigen::VectorXd::Constant(6, x0);
  st.theta[1] = 1.0;
  return st;
}

// The uninterrupted run, and a run stopped after iteration k (its state serialized
// there, as the job's checkpoint does), restored and continued.
struct ResumePair {
  OptimizerState whole, resumed;
  std::vector<uint8_t> bytes;
  OptimizerState at_k;  // the deserialized checkpoint
};

ResumePair stop_and_resume(const OptimizerSettings& s, int k, const JacobianFn& jf = kStateJf, double x0 = -1.2) {
  ResumePair p;
  p.whole = state_start(x0);
  optimize(kStateRf, s, p.whole, {}, jf, kStateFf);
  OptimizerState first = state_start(x0);
  optimize(
      kStateRf, s, first,
      [&](const OptimizerState& st) {
        if (st.iteration < k) return true;
        p.bytes = optimizer_state_serialize(st, 7);
        return false;  // "killed" right after the checkpoint
      },
      jf, kStateFf);
  EXPECT_FALSE(p.bytes.empty());
  uint32_t tag = 0;
  p.at_k = optimizer_state_deserialize(p.bytes, &tag);
  EXPECT_EQ(tag, 7u);
  p.resumed = p.at_k;
  optimize(kStateRf, s, p.resumed, {}, jf, kStateFf);
  return p;
}

void expect_same_run(const OptimizerState& a, const OptimizerState& b) {
  EXPECT_TRUE(state_bits_equal(a.theta, b.theta));
  EXPECT_TRUE(state_bits_equal(a.history, b.history)) << a.history.size() << " vs " << b.history.size();
  EXPECT_EQ(a.step_kinds, b.step_kinds);
  EXPECT_EQ(a.iteration, b.iteration);
  EXPECT_EQ(a.evaluations, b.evaluations);
  EXPECT_EQ(std::bit_cast<uint64_t>(a.lambda), std::bit_cast<uint64_t>(b.lambda));
  EXPECT_EQ(a.in_lbfgs, b.in_lbfgs);
  EXPECT_EQ(a.lbfgs_restarts_used, b.lbfgs_restarts_used);
}

OptimizerSettings state_settings(OptimizerKind k, int iterations) {
  OptimizerSettings s;
  s.kind = k;
  s.max_iterations = iterations;
  s.tolerance = 1e-14;
  return s;
}

size_t kinds_count(const std::vector<std::string>& v, const std::string& x, size_t from = 0) {
  return size_t(std::count(v.begin() + std::ptrdiff_t(from), v.end(), x));
}

}  // namespace

TEST(OptimizerState, LmWithBroydenReuseResumesExactly) {
  // Finite-difference Jacobians: the Broyden-updated J is what the next step uses.
  const ResumePair p = stop_and_resume(state_settings(OptimizerKind::LM, 14), 5, {});
  expect_same_run(p.whole, p.resumed);
  EXPECT_GT(p.at_k.memory.J.size(), 0);
  EXPECT_GT(kinds_count(p.whole.step_kinds, "lm-broyden", 5), 0u);
}

TEST(OptimizerState, LbfgsWithItsCurvaturePairsResumesExactly) {
  const ResumePair p = stop_and_resume(state_settings(OptimizerKind::LBFGS, 30), 12);
  expect_same_run(p.whole, p.resumed);
  EXPECT_GE(p.at_k.memory.S.size(), 4u);
  // Restarts and an LBFGS++ Wolfe search with fused evaluations (J_at carried).
  OptimizerSettings s = state_settings(OptimizerKind::LBFGS, 30);
  s.lbfgs_restarts = 3;
  s.lbfgs_line_search = OptimizerSettings::LineSearch::StrongWolfe;
  s.fused_trials = true;
  const ResumePair w = stop_and_resume(s, 10);
  expect_same_run(w.whole, w.resumed);
  EXPECT_GT(w.at_k.memory.J_at.size(), 0);
}

TEST(OptimizerState, HybridInItsLbfgsPhaseResumesExactly) {
  // A stall threshold of 90% from x = -3: LM hands over to L-BFGS after 3 iterations
  // (on this problem LM at the default 5% rarely stalls).
  OptimizerSettings s = state_settings(OptimizerKind::Hybrid, 40);
  s.stall = 0.9;
  // Find an iteration inside an L-BFGS phase that has a curvature pair, and stop there.
  OptimizerState probe = state_start(-3.0);
  int k = -1;
  optimize(
      kStateRf, s, probe,
      [&](const OptimizerState& st) {
        if (k < 0 && st.in_lbfgs && st.memory.S.size() >= 1) k = st.iteration;
        return true;
      },
      kStateJf);
  ASSERT_GT(k, 0) << "the hybrid never reached its L-BFGS phase";
  const ResumePair p = stop_and_resume(s, k, kStateJf, -3.0);
  expect_same_run(p.whole, p.resumed);
  EXPECT_TRUE(p.at_k.in_lbfgs);
  EXPECT_EQ(p.resumed.step_kinds[size_t(k)], "lbfgs");
  EXPECT_GT(kinds_count(p.whole.step_kinds, "lm", size_t(k)), 0u);  // and back to LM later
}

TEST(OptimizerState, HybridWithFusedTrialsAndTrustRegionResumesExactly) {
  OptimizerSettings s = state_settings(OptimizerKind::Hybrid, 30);
  s.fused_trials = true;
  s.lm_damping = OptimizerSettings::Damping::TrustRegion;
  for (int k : {2, 6, 11}) {
    SCOPED_TRACE(k);
    const ResumePair p = stop_and_resume(s, k);
    expect_same_run(p.whole, p.resumed);
    if (!p.at_k.in_lbfgs) {
      EXPECT_GT(p.at_k.memory.radius, 0);
    }
  }
}

TEST(OptimizerState, RoundTripKeepsEveryField) {
  OptimizerSettings s = state_settings(OptimizerKind::Hybrid, 9);
  OptimizerState st = state_start();
  optimize(kStateRf, s, st, {}, kStateJf);
  st.memory.S.push_back(Eigen::VectorXd::LinSpaced(6, -1, 1));
  st.memory.Y.push_back(Eigen::VectorXd::Constant(6, 0.25));
  st.memory.J_at = Eigen::MatrixXd::Identity(7, 6);
  const OptimizerState b = optimizer_state_deserialize(optimizer_state_serialize(st));
  expect_same_run(st, b);
  EXPECT_EQ(std::bit_cast<uint64_t>(st.objective), std::bit_cast<uint64_t>(b.objective));
  const OptimizerMemory &x = st.memory, &y = b.memory;
  EXPECT_TRUE(state_bits_equal(x.theta, y.theta) && state_bits_equal(x.r, y.r));
  auto same_matrix = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() && a == b;
  };
  EXPECT_TRUE(same_matrix(x.J, y.J) && same_matrix(x.J_at, y.J_at));
  EXPECT_EQ(x.reused, y.reused);
  EXPECT_EQ(x.lm_stalls, y.lm_stalls);
  EXPECT_EQ(x.last_lm_step, y.last_lm_step);
  EXPECT_EQ(x.last_lbfgs_step, y.last_lbfgs_step);
  EXPECT_EQ(x.radius, y.radius);
  ASSERT_EQ(x.S.size(), y.S.size());
  for (size_t i = 0; i < x.S.size(); ++i)
    EXPECT_TRUE(state_bits_equal(x.S[i], y.S[i]) && state_bits_equal(x.Y[i], y.Y[i]));
  EXPECT_TRUE(state_bits_equal(x.g_prev, y.g_prev) && state_bits_equal(x.theta_prev, y.theta_prev));
}

TEST(OptimizerState, TruncatedOrDamagedBytesAreErrors) {
  OptimizerState st = state_start();
  optimize(kStateRf, state_settings(OptimizerKind::LBFGS, 6), st, {}, kStateJf);
  const std::vector<uint8_t> good = optimizer_state_serialize(st);
  auto error_of = [](const std::vector<uint8_t>& b) -> std::string {
    try {
      optimizer_state_deserialize(b);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_of(good), "");
  std::vector<uint8_t> padded = good;
  padded.resize(good.size() + 3, 0);  // a take field's padding
  EXPECT_EQ(error_of(padded), "");
  // Every prefix fails (and none reads past its end: ASan runs these tests too).
  for (size_t n = 0; n < good.size(); n += (n < 64 ? 1 : 7)) {
    const std::string e = error_of(std::vector<uint8_t>(good.begin(), good.begin() + std::ptrdiff_t(n)));
    EXPECT_NE(e.find("soft optimizer checkpoint"), std::string::npos) << n << ": " << e;
  }
  EXPECT_NE(error_of(std::vector<uint8_t>(good.begin(), good.end() - 8)).find("truncated"), std::string::npos);
  std::vector<uint8_t> bad = good;
  bad[bad.size() / 2] ^= 0x10;
  EXPECT_NE(error_of(bad).find("CRC mismatch"), std::string::npos) << error_of(bad);
  bad = good;
  bad[0] ^= 1;
  EXPECT_NE(error_of(bad).find("bad magic"), std::string::npos);
  bad = good;
  bad[4] = 9;
  EXPECT_NE(error_of(bad).find("unsupported version 9"), std::string::npos);
  bad = good;
  bad.push_back(1);
  EXPECT_NE(error_of(bad).find("trailing bytes"), std::string::npos);
  // A body cut anywhere but sealed again (length and CRC fixed up) reaches the field
  // parser: every cut is an error, none reads out of bounds; so is a huge theta size.
  auto sealed = [](std::vector<uint8_t> b, size_t body) {
    b.resize(24 + body);
    const uint64_t n = body;
    const uint32_t crc = pliant::crc32(b.data() + 24, body);
    std::memcpy(b.data() + 8, &n, 8);
    std::memcpy(b.data() + 16, &crc, 4);
    return b;
  };
  for (size_t body = 0; body + 24 < good.size(); body += (body < 200 ? 1 : 5)) {
    const std::string e = error_of(sealed(good, body));
    EXPECT_NE(e.find("soft optimizer checkpoint"), std::string::npos) << body << ": " << e;
  }
  bad = good;
  const uint64_t huge = uint64_t(1) << 60;
  std::memcpy(bad.data() + 24 + 29, &huge, 8);  // theta's length, after 29 bytes of scalars
  EXPECT_NE(error_of(sealed(bad, bad.size() - 24)).find("theta of"), std::string::npos)
      << error_of(sealed(bad, bad.size() - 24));
}
