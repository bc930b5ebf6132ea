// Best-so-far objective trace (ControlState::objective_trace): issue 3's time to an
// intermediate objective. One TraceClock per solver segment (an ADMM run, an L-BFGS run
// on one level) adds its seconds on top of the state's trace_s, so coarse levels, phases
// and resumed runs continue one clock. Recording only: no solver decision reads it.
#pragma once
#include <chrono>

#include "pliant/smoke/control.h"

namespace pliant::smoke::control_detail {

class TraceClock {
 public:
  TraceClock(ControlState& s, const ControlCallbacks& cb) : s_(s), clock_(cb.clock), t0_(now()), base_(s.trace_s) {}
  TraceClock(const TraceClock&) = delete;
  TraceClock& operator=(const TraceClock&) = delete;
  ~TraceClock() { sync(); }
  double elapsed() const { return base_ + (now() - t0_); }
  // Before a checkpoint (and at the end): the state carries the time spent so far.
  void sync() { s_.trace_s = elapsed(); }
  // An evaluated objective: a point when it lowers the trace (so the trace is monotone).
  void add(double E) {
    auto& t = s_.objective_trace;
    if (t.empty() || E < t.back()[1]) t.push_back({elapsed(), E});
  }

 private:
  double now() const {
    return clock_ ? clock_()
                  : std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  }
  ControlState& s_;
  std::function<double()> clock_;
  double t0_, base_;
};

// At most max_points of a trace (>= 2): evenly spaced by index, the first and last kept
// (the take's metrics: a long polish has thousands of points).
inline std::vector<std::array<double, 2>> decimate_trace(const std::vector<std::array<double, 2>>& t,
                                                         size_t max_points) {
  if (t.size() <= max_points || max_points < 2) return t;
  std::vector<std::array<double, 2>> out;
  out.reserve(max_points);
  for (size_t k = 0; k < max_points; ++k) out.push_back(t[k * (t.size() - 1) / (max_points - 1)]);
  return out;
}

}  // namespace pliant::smoke::control_detail
