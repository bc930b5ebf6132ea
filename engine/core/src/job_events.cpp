// JSON-lines emitter of the job protocol (job.h). One object per line,
// flushed, never with NaN/Inf (which JSON cannot spell).
#include <cmath>

#include "pliant/core/job.h"

namespace pliant {

void JobEvents::emit(const nlohmann::json& event) {
  // replace: a message quoting invalid UTF-8 (a file name) must not throw.
  const std::string line = event.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::lock_guard<std::mutex> lock(mu_);
  std::fputs(line.c_str(), out_);
  std::fputc('\n', out_);
  std::fflush(out_);
}

void JobEvents::start(const std::string& kind, const std::string& take_dir, int frames) {
  emit({{"event", "start"}, {"kind", kind}, {"take", take_dir}, {"frames", frames}});
}

void JobEvents::progress(const ProgressReport& r) {
  nlohmann::json e{{"event", "progress"}, {"stage", r.stage}, {"iter", r.iter}, {"of", r.of}};
  if (std::isfinite(r.objective)) e["objective"] = r.objective;
  if (std::isfinite(r.eta_s) && r.eta_s >= 0) e["eta_s"] = r.eta_s;
  e["elapsed_s"] = r.elapsed_s;
  emit(e);
}

void JobEvents::frame(int index) { emit({{"event", "frame"}, {"index", index}}); }

void JobEvents::log(const std::string& level, const std::string& message) {
  emit({{"event", "log"}, {"level", level}, {"message", message}});
}

void JobEvents::done(const nlohmann::json& metrics) { emit({{"event", "done"}, {"metrics", metrics}}); }

void JobEvents::error(const std::string& message) { emit({{"event", "error"}, {"message", message}}); }

}  // namespace pliant
