// `pliant`: the command-line front end of the engine (ARCHITECTURE.md).
// stdout carries only machine-readable output (JSON lines for run/export) or
// the requested report; diagnostics go to stderr.
#include <cstdio>
#include <exception>
#include <string>

#include "commands.h"
#include "pliant/core/error.h"
#include "pliant/core/version.h"
#include "pliant/plugin.h"

int main(int argc, char** argv) {
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
