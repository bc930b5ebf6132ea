// Progress of a long loop: stage, iteration, objective, ETA, cancellation.
// Solvers take a Progress& and call report() each iteration and
// check_cancelled() at every safe point; they never print by themselves.
#pragma once
#include <atomic>
#include <chrono>
#include <functional>
#include <limits>
#include <string>

namespace pliant {

struct ProgressReport {
  std::string stage;
  int iter = 0;
  int of = 0;  // 0 when unknown
  double objective = std::numeric_limits<double>::quiet_NaN();  // NaN when none
  double eta_s = -1;   // -1 when unknown
  double elapsed_s = 0;
};

class Progress {
 public:
  using Sink = std::function<void(const ProgressReport&)>;
  explicit Progress(Sink sink = {});

  // Begins a stage with `of` iterations expected (0 = unknown); resets the ETA clock.
  void stage(const std::string& name, int of = 0);
  // Reports iteration `iter` (1-based count of completed ones) of the current stage.
  // ETA = elapsed-in-stage / iter * (of - iter). Calls the sink at most every
  // `min_interval_s` unless iter == of.
  void report(int iter, double objective = std::numeric_limits<double>::quiet_NaN());
  const ProgressReport& last() const { return last_; }

  // Async-signal-safe: may be called from a signal handler or another thread.
  void cancel() { cancelled_.store(true, std::memory_order_relaxed); }
  bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }
  // Throws CancelledError if cancel() was called.
  void check_cancelled() const;

  double min_interval_s = 0.1;

 private:
  Sink sink_;
  ProgressReport last_;
  std::chrono::steady_clock::time_point t0_, stage_t0_, last_emit_;
  bool emitted_ = false;
  std::atomic<bool> cancelled_{false};
};

}  // namespace pliant
