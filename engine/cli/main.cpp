// `pliant`: the command-line front end of the engine (ARCHITECTURE.md).
// stdout carries only machine-readable output (JSON lines for run/export) or
// the requested report; diagnostics go to stderr.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "commands.h"
#include "pliant/core/error.h"
#include "pliant/core/version.h"
#include "pliant/plugin.h"

namespace {

// OpenMP's default (active) waiting spins at every barrier. On shared or busy
// machines that made 2 threads 5-20x slower than 1 (bench_smoke_sim, editor
// jobs), so jobs wait passively unless the user set OMP_WAIT_POLICY. libgomp
// reads the variable before main(), hence the re-exec.
void prefer_passive_openmp_waiting(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  ::setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
  ::execv("/proc/self/exe", argv);  // returns only on failure: run as we are
}

}  // namespace

int main(int argc, char** argv) {
  prefer_passive_openmp_waiting(argv);
  CLI::App app{"Pliant: plan the motion of deformable things (scenes -> jobs -> takes)", "pliant"};
  app.set_version_flag("--version", std::string("pliant ") + pliant::kEngineVersion +
                                        " (plugin API " +
                                        std::to_string(PLIANT_PLUGIN_API_VERSION) + ")");
  app.require_subcommand(1);
  pliant::cli::Action action;
  pliant::cli::add_run_command(app, action);
  pliant::cli::add_validate_command(app, action);
  pliant::cli::add_info_command(app, action);
  pliant::cli::add_export_command(app, action);
  pliant::cli::add_plugins_command(app, action);
  pliant::cli::add_sweep_command(app, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);  // prints help/version (0) or the usage error
    return rc == 0 ? pliant::kExitDone : pliant::kExitInvalid;
  }
  if (!action) return pliant::kExitInvalid;
  try {
    return action();
  } catch (const pliant::InputError& e) {
    std::fprintf(stderr, "pliant: %s\n", e.what());
    return pliant::kExitInvalid;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pliant: internal error: %s\n", e.what());
    return pliant::kExitInternal;
  }
}
