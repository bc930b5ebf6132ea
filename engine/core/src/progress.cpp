// Progress: stage/iteration/objective reporting with a throttled sink.
#include "pliant/core/progress.h"

#include "pliant/core/error.h"

namespace pliant {
namespace {
double seconds(std::chrono::steady_clock::duration d) { return std::chrono::duration<double>(d).count(); }
}  // namespace

Progress::Progress(Sink sink) : sink_(std::move(sink)) {
  t0_ = stage_t0_ = last_emit_ = std::chrono::steady_clock::now();
}

void Progress::stage(const std::string& name, int of) {
  const auto now = std::chrono::steady_clock::now();
  stage_t0_ = now;
  last_.stage = name;
  last_.iter = 0;
  last_.of = of;
  last_.objective = std::numeric_limits<double>::quiet_NaN();
  last_.eta_s = -1;
  last_.elapsed_s = seconds(now - t0_);
  // A new stage is always shown once; the first report() after it is too.
  emitted_ = false;
  if (sink_) {
    sink_(last_);
    last_emit_ = now;
  }
}

void Progress::report(int iter, double objective) {
  const auto now = std::chrono::steady_clock::now();
  last_.iter = iter;
  last_.objective = objective;
  last_.elapsed_s = seconds(now - t0_);
  const double in_stage = seconds(now - stage_t0_);
  last_.eta_s = (iter > 0 && last_.of > 0) ? in_stage / iter * (last_.of - iter) : -1;
  if (last_.of > 0 && iter >= last_.of) last_.eta_s = 0;  // done (or overshot)
  if (!sink_) return;
  const bool due = !emitted_ || iter == last_.of || seconds(now - last_emit_) >= min_interval_s;
  if (!due) return;
  emitted_ = true;
  last_emit_ = now;
  sink_(last_);
}

void Progress::check_cancelled() const {
  if (cancelled()) throw CancelledError();
}

}  // namespace pliant
