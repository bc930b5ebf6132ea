// run_job: the whole job protocol around a JobKind (job.h, ARCHITECTURE.md).
#include <omp.h>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>

#include "pliant/core/error.h"
#include "pliant/core/job.h"
#include "pliant/core/log.h"
#include "pliant/core/version.h"

namespace pliant {
namespace {

// The signal handler may only touch this pointer and Progress::cancel(),
// both async-signal-safe (lock-free atomics).
std::atomic<Progress*> g_cancel_target{nullptr};
static_assert(std::atomic<Progress*>::is_always_lock_free);

extern "C" void cancel_on_signal(int) {
  if (Progress* p = g_cancel_target.load()) p->cancel();
}

// Installs the handlers for the lifetime of the object and restores the old ones.
class SignalGuard {
 public:
  explicit SignalGuard(Progress* p) : previous_target_(g_cancel_target.exchange(p)) {
    struct sigaction sa {};
    sa.sa_handler = cancel_on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~SignalGuard() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    g_cancel_target.store(previous_target_);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  Progress* previous_target_;
  struct sigaction old_int_ {}, old_term_ {};
};

// Routes engine logs into the job's event stream while the job runs.
class LogGuard {
 public:
  explicit LogGuard(JobEvents& ev)
      : old_(set_log_sink([&ev](LogLevel level, const std::string& m) { ev.log(log_level_name(level), m); })) {}
  ~LogGuard() { set_log_sink(std::move(old_)); }

 private:
  LogSink old_;
};

nlohmann::json progress_json(const ProgressReport& r) {
  nlohmann::json j{{"stage", r.stage}, {"iter", r.iter}, {"of", r.of}, {"elapsed_s", r.elapsed_s}};
  if (std::isfinite(r.objective)) j["objective"] = r.objective;
  if (std::isfinite(r.eta_s) && r.eta_s >= 0) j["eta_s"] = r.eta_s;
  return j;
}

std::string available_kinds(const std::vector<JobKind>& kinds) {
  std::string s;
  for (const auto& k : kinds) s += (s.empty() ? "" : ", ") + ("\"" + k.kind + "\"");
  return s.empty() ? "none" : s;
}

}  // namespace

int run_job(const RunOptions& opt, const std::vector<JobKind>& kinds, std::FILE* out) {
  JobEvents events(out);
  LogGuard log_guard(events);

  // 1. Scene, kind and frame count: failures here leave no take behind.
  Scene scene;
  const JobKind* kind = nullptr;
  int frames = 0;
  try {
    scene = load_scene(opt.scene);
    for (const auto& k : kinds)
      if (k.kind == scene.kind && k.run) kind = &k;
    if (!kind)
      throw InputError(scene.file, "/kind",
                       "no job for scene kind \"" + scene.kind + "\" in this build (available: " +
                           available_kinds(kinds) + ")");
    frames = kind->frames ? kind->frames(scene) : 0;
  } catch (const InputError& e) {
    events.error(e.what());
    return kExitInvalid;
  } catch (const std::exception& e) {
    events.error(e.what());
    return kExitInternal;
  }

  // 2. The take.
  std::optional<TakeWriter> take;
  try {
    if (opt.resume && std::filesystem::exists(opt.take / "take.json")) {
      take.emplace(TakeWriter::reopen(opt.take));
      take->manifest().frames_expected = frames;
    } else {
      Manifest m;
      m.kind = scene.kind;
      m.scene_file = opt.scene.string();
      m.scene = scene.doc;
      m.engine_version = kEngineVersion;
      m.frames_expected = frames;
      take.emplace(TakeWriter::create(opt.take, std::move(m)));
    }
  } catch (const InputError& e) {
    events.error(e.what());
    return kExitInvalid;
  } catch (const std::exception& e) {
    events.error(e.what());
    return kExitInternal;
  }
  events.start(scene.kind, opt.take.string(), frames);

  // 3. Progress: every report goes to stdout; the manifest gets one per second.
  auto last_manifest = std::chrono::steady_clock::now() - std::chrono::seconds(2);
  TakeWriter& writer = *take;
  Progress progress([&](const ProgressReport& r) {
    events.progress(r);
    const auto now = std::chrono::steady_clock::now();
    if (now - last_manifest < std::chrono::seconds(1)) return;
    last_manifest = now;
    writer.manifest().progress = progress_json(r);
    try {
      writer.write_manifest();
    } catch (const std::exception& e) {
      log_warn(e.what());  // a missed progress update is not worth failing the job
    }
  });
  SignalGuard signals(&progress);
  if (opt.threads > 0) omp_set_num_threads(opt.threads);

  // 4. Run and finish the take.
  JobContext ctx{scene, writer, progress, events, opt.threads, opt.resume};
  try {
    try {
      nlohmann::json metrics = kind->run(ctx);
      if (metrics.is_null()) metrics = nlohmann::json::object();
      writer.manifest().metrics = metrics;
      writer.manifest().progress = progress_json(progress.last());
      writer.finish("done");
      events.done(metrics);
      return kExitDone;
    } catch (const CancelledError&) {
      writer.manifest().progress = progress_json(progress.last());
      writer.finish("cancelled");
      events.emit({{"event", "cancelled"}});
      return kExitCancelled;
    } catch (const InputError& e) {
      writer.finish("failed", e.what());
      events.error(e.what());
      return kExitInvalid;
    } catch (const std::exception& e) {
      writer.finish("failed", e.what());
      events.error(e.what());
      return kExitInternal;
    }
  } catch (const std::exception& e) {
    // finish() itself failed (e.g. disk full while writing the manifest).
    events.error(e.what());
    return kExitInternal;
  }
}

}  // namespace pliant
