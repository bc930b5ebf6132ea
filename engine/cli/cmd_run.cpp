// `pliant run SCENE --take DIR [--threads N] [--resume]`: the job protocol
// (JSON lines on stdout, exit 0/1/2/3) is implemented by pliant::run_job.
#include <cstdio>
#include <memory>

#include "commands.h"
#include "job_kinds.h"
#include "pliant/core/job.h"

namespace pliant::cli {

void add_run_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<RunOptions>();
  CLI::App* sub = app.add_subcommand(
      "run", "Run a scene to completion into a take; JSON lines on stdout, exit 0 done, "
             "1 internal failure, 2 invalid input, 3 cancelled (SIGINT/SIGTERM)");
  sub->add_option("scene", opt->scene, "Scene JSON file")->required();
  sub->add_option("--take", opt->take, "Take directory to write")->required();
  sub->add_option("--threads", opt->threads, "Worker threads (0 = OpenMP default)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--resume", opt->resume,
                "Continue the take in DIR from its last good record / checkpoint");
  sub->callback([opt, &action] {
    action = [opt] { return run_job(*opt, job_kinds(), stdout); };
  });
}

}  // namespace pliant::cli
