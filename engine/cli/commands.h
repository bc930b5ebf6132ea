// The `pliant` subcommands. Each add_* registers a subcommand with its options
// on `app`; when that subcommand is parsed, `action` is set to a function that
// runs it and returns the process exit code (pliant::ExitCode).
#pragma once
#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <vector>

namespace pliant {
class PluginHost;
}

namespace pliant::cli {

using Action = std::function<int()>;

void add_run_command(CLI::App& app, Action& action);
void add_validate_command(CLI::App& app, Action& action);
void add_info_command(CLI::App& app, Action& action);
void add_export_command(CLI::App& app, Action& action);
void add_plugins_command(CLI::App& app, Action& action);
void add_sweep_command(CLI::App& app, Action& action);

// Loads the default plugin folders, then each of `extra_folders`.
void load_plugins(PluginHost& host, const std::vector<std::filesystem::path>& extra_folders);

}  // namespace pliant::cli
