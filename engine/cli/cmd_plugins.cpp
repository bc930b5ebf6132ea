// `pliant plugins [--plugins DIR]... [--json]`: which plugins loaded, what they
// provide, and which were refused (wrong API version, not a plugin, load failed).
#include <cstdio>
#include <memory>
#include <system_error>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "pliant/core/plugin_host.h"

namespace pliant::cli {
namespace {

struct PluginsOptions {
  std::vector<std::filesystem::path> folders;
  bool json = false;
};

int list_plugins(const PluginsOptions& o) {
  PluginHost host;
  load_plugins(host, o.folders);
  if (o.json) {
    nlohmann::json j = {{"folders", nlohmann::json::array()},
                        {"plugins", nlohmann::json::array()},
                        {"failures", nlohmann::json::array()}};
    for (const auto& f : PluginHost::default_folders()) j["folders"].push_back(f.string());
    for (const auto& f : o.folders) j["folders"].push_back(f.string());
    for (const LoadedPlugin& p : host.plugins()) {
      nlohmann::json ex = nlohmann::json::array();
      for (const std::string& name : p.exporters) {
        const Exporter* e = host.find_exporter(name);
        ex.push_back({{"name", name},
                      {"description", e ? e->description : ""},
                      {"extension", e ? e->extension : ""}});
      }
      j["plugins"].push_back({{"path", p.path.string()}, {"exporters", ex}});
    }
    for (const PluginFailure& f : host.failures()) {
      j["failures"].push_back({{"path", f.path.string()}, {"reason", f.reason}});
    }
    std::printf("%s\n", j.dump().c_str());
    return 0;
  }
  std::printf("plugin folders:\n");
  for (const auto& f : PluginHost::default_folders()) std::printf("  %s\n", f.c_str());
  for (const auto& f : o.folders) std::printf("  %s\n", f.c_str());
  std::printf("loaded plugins: %zu\n", host.plugins().size());
  for (const LoadedPlugin& p : host.plugins()) {
    std::printf("  %s\n", p.path.c_str());
    for (const std::string& name : p.exporters) {
      const Exporter* e = host.find_exporter(name);
      std::printf("    exporter %-10s %s (%s)\n", name.c_str(), e ? e->description.c_str() : "",
                  e ? e->extension.c_str() : "");
    }
  }
  std::printf("refused or failed: %zu\n", host.failures().size());
  for (const PluginFailure& f : host.failures()) std::printf("  %s\n", f.reason.c_str());
  return 0;
}

}  // namespace

void load_plugins(PluginHost& host, const std::vector<std::filesystem::path>& extra_folders) {
  host.load_default_folders();
  for (const auto& folder : extra_folders) {
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec)) {
      std::fprintf(stderr, "warning: plugin folder %s does not exist\n", folder.c_str());
    }
    host.load_folder(folder);
  }
}

void add_plugins_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<PluginsOptions>();
  CLI::App* sub = app.add_subcommand(
      "plugins", "List plugins (plugins/ beside the binary, $PLIANT_PLUGIN_PATH, --plugins), "
                 "their exporters, and refused or failed ones with the reason");
  sub->add_option("--plugins", opt->folders, "Extra plugin folder (repeatable)");
  sub->add_flag("--json", opt->json, "One JSON object on stdout instead of text");
  sub->callback([opt, &action] { action = [opt] { return list_plugins(*opt); }; });
}

}  // namespace pliant::cli
