// The job protocol (ARCHITECTURE.md): `pliant run SCENE --take DIR` writes JSON
// lines to stdout:
//   {"event":"start","kind":"smoke","take":"DIR","frames":120}
//   {"event":"progress","stage":"simulate","iter":3,"of":20,"objective":1.2e-2,"eta_s":41}
//   {"event":"frame","index":17}
//   {"event":"log","level":"info","message":"..."}
//   {"event":"done","metrics":{...}}   or   {"event":"error","message":"..."}
// and exits 0 done, 2 invalid input, 3 cancelled, 1 internal failure.
#pragma once
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>

#include "pliant/core/progress.h"
#include "pliant/core/scene.h"
#include "pliant/core/take.h"

namespace pliant {

// Thread-safe JSON-lines emitter; flushes after every line.
class JobEvents {
 public:
  explicit JobEvents(std::FILE* out) : out_(out) {}
  void start(const std::string& kind, const std::string& take_dir, int frames);
  void progress(const ProgressReport& r);
  void frame(int index);
  void log(const std::string& level, const std::string& message);
  void done(const nlohmann::json& metrics);
  void error(const std::string& message);
  void emit(const nlohmann::json& event);  // any event object

 private:
  std::FILE* out_;
  std::mutex mu_;
};

// What a job kind's entry point receives.
struct JobContext {
  const Scene& scene;
  TakeWriter& take;
  Progress& progress;
  JobEvents& events;
  int threads = 0;      // 0 = OpenMP default
  bool resume = false;  // continue from the take's last checkpoint
};

// A job kind: compiles the scene (throws InputError), runs, appends records,
// emits frame events, checks progress.check_cancelled() at safe points and
// returns metrics. Must not print to stdout.
using JobFn = nlohmann::json (*)(JobContext&);
// Returns the job's frame count for the manifest; throws InputError.
using JobFramesFn = int (*)(const Scene&);

// Compiles the scene and returns what `pliant validate` prints: at least
// "frames"; "dim" and "resolution" (array) where the kind has a grid.
using JobSummaryFn = nlohmann::json (*)(const Scene&);

struct JobKind {
  std::string kind;
  JobFn run;
  JobFramesFn frames;
  JobSummaryFn summary = nullptr;  // nullptr: {"frames": frames(scene)}
};

struct RunOptions {
  std::filesystem::path scene;
  std::filesystem::path take;
  int threads = 0;
  bool resume = false;
};

// The whole protocol: loads the scene, creates (or reopens) the take, installs
// SIGINT/SIGTERM handlers that cancel at the next safe point, runs the kind,
// finishes the take with done/cancelled/failed and returns the exit code.
int run_job(const RunOptions& opt, const std::vector<JobKind>& kinds, std::FILE* out);

}  // namespace pliant
