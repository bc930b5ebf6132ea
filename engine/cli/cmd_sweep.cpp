// `pliant sweep SWEEP.json [--shard I/N]`: runs this shard's part of a sweep
// (sweep_plan.h) one run after another, each with the `run` protocol. Before
// each run: {"event":"run","index":k,"of":N,"take":DIR,"values":{...}}; runs
// whose take is already done are skipped ({"event":"skip",...}), so a shard
// restarted by a cluster scheduler continues where it stopped. Last line:
// {"event":"sweep","runs":..,"done":..,"skipped":..,"failed":..}.
// Exit: 0 all done, 2 invalid input (stops), 3 cancelled (stops), 1 a run failed.
#include <cstdio>
#include <memory>
#include <string>
#include <system_error>

#include "commands.h"
#include "job_kinds.h"
#include "pliant/core/error.h"
#include "pliant/core/job.h"
#include "pliant/core/scene.h"
#include "pliant/core/take.h"
#include "sweep_plan.h"

namespace pliant::cli {
namespace {

struct SweepOptions {
  std::filesystem::path sweep;
  std::string shard = "0/1";
  int threads = -1;  // -1: the sweep file's value
};

bool take_is_done(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::exists(dir / "take.json", ec)) return false;
  try {
    return TakeReader(dir).manifest().status == "done";
  } catch (const std::exception&) {
    return false;  // unreadable: run it again
  }
}

int sweep(const SweepOptions& o) {
  const Shard shard = parse_shard(o.shard);
  const SweepPlan plan = load_sweep(o.sweep);
  JobEvents events(stdout);
  const size_t count = plan.run_count();
  int done = 0, skipped = 0, failed = 0, runs = 0;
  int exit_code = kExitDone;
  for (size_t k = 0; k < count && exit_code != kExitInvalid && exit_code != kExitCancelled; ++k) {
    if (!shard.owns(k)) continue;
    ++runs;
    const std::string name = plan.run_name(k);
    RunOptions run;
    run.take = plan.out / name;
    run.scene = plan.out / "scenes" / (name + ".json");
    run.threads = o.threads >= 0 ? o.threads : plan.threads;
    nlohmann::json head = {{"index", k},
                           {"of", count},
                           {"take", run.take.string()},
                           {"values", plan.run_values(k)}};
    if (take_is_done(run.take)) {
      head["event"] = "skip";
      events.emit(head);
      ++skipped;
      continue;
    }
    // The variant scene is kept beside the takes, so each run is reproducible
    // with plain `pliant run`. Relative asset paths in it resolve from OUT/scenes.
    std::filesystem::create_directories(run.scene.parent_path());
    save_json_atomic(run.scene, plan.run_scene(k));
    head["event"] = "run";
    events.emit(head);
    const int rc = run_job(run, job_kinds(), stdout);
    if (rc == kExitDone) {
      ++done;
    } else {
      ++failed;
      if (rc == kExitInvalid || rc == kExitCancelled || exit_code == kExitDone) exit_code = rc;
    }
  }
  events.emit({{"event", "sweep"},
               {"runs", runs},
               {"done", done},
               {"skipped", skipped},
               {"failed", failed},
               {"shard", o.shard}});
  return exit_code;
}

}  // namespace

void add_sweep_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<SweepOptions>();
  CLI::App* sub = app.add_subcommand(
      "sweep", "Run one shard of a parameter sweep (SWEEP.json: scene, out, parameters with "
               "JSON pointers and values); finished takes are skipped");
  sub->add_option("sweep", opt->sweep, "Sweep JSON file")->required();
  sub->add_option("--shard", opt->shard, "This shard, I/N (runs with index % N == I)");
  sub->add_option("--threads", opt->threads, "Worker threads per run (overrides the file)")
      ->check(CLI::NonNegativeNumber);
  sub->callback([opt, &action] { action = [opt] { return sweep(*opt); }; });
}

}  // namespace pliant::cli
