// `pliant export TAKE --format NAME --out DIR [--plugins DIR]...`: feeds every
// frame of a take to a plugin exporter. Progress as JSON lines on stdout (same
// events as `run`); SIGINT/SIGTERM stop between frames with exit 3.
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "pliant/core/error.h"
#include "pliant/core/job.h"
#include "pliant/core/log.h"
#include "pliant/core/plugin_host.h"
#include "pliant/core/progress.h"
#include "pliant/core/take.h"

namespace pliant::cli {
namespace {

struct ExportOptions {
  std::filesystem::path take, out;
  std::string format;
  std::vector<std::filesystem::path> folders;
};

Progress* g_export_progress = nullptr;  // for the signal handler
extern "C" void on_export_signal(int) {
  if (g_export_progress) g_export_progress->cancel();  // async-signal-safe
}

int run_export(const ExportOptions& o) {
  PluginHost host;
  load_plugins(host, o.folders);
  for (const PluginFailure& f : host.failures()) std::fprintf(stderr, "warning: %s\n", f.reason.c_str());
  const Exporter* exporter = host.find_exporter(o.format);
  if (!exporter) {
    std::string names;
    for (const Exporter* e : host.exporters()) names += (names.empty() ? "" : ", ") + e->name;
    std::fprintf(stderr, "pliant export: no exporter \"%s\" (available: %s); see `pliant plugins`\n",
                 o.format.c_str(), names.empty() ? "none" : names.c_str());
    return kExitInvalid;
  }
  TakeReader take(o.take);  // InputError -> exit 2 in main
  JobEvents events(stdout);
  Progress progress([&events](const ProgressReport& r) { events.progress(r); });
  g_export_progress = &progress;
  struct sigaction sa {};
  sa.sa_handler = &on_export_signal;
  sigemptyset(&sa.sa_mask);
  struct sigaction old_int {}, old_term {};
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);
  // Plugin and engine log lines become {"event":"log",...} lines while exporting.
  LogSink old_sink = set_log_sink(
      [&events](LogLevel level, const std::string& m) { events.log(log_level_name(level), m); });
  auto restore = [&] {
    set_log_sink(std::move(old_sink));
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
    g_export_progress = nullptr;
  };
  events.emit({{"event", "start"},
               {"exporter", exporter->name},
               {"take", o.take.string()},
               {"out", o.out.string()},
               {"frames", take.frame_count()}});
  try {
    const int n = export_take(take, *exporter, o.out, &progress);
    restore();
    events.done({{"frames", n}, {"out", o.out.string()}, {"format", exporter->name}});
    return kExitDone;
  } catch (const CancelledError&) {
    restore();
    events.emit({{"event", "cancelled"}});
    return kExitCancelled;
  } catch (const std::exception& e) {
    restore();
    events.error(e.what());
    std::fprintf(stderr, "pliant export: %s\n", e.what());
    return kExitInternal;
  }
}

}  // namespace

void add_export_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<ExportOptions>();
  CLI::App* sub = app.add_subcommand(
      "export", "Export a take's frames with a plugin exporter (see `pliant plugins`)");
  sub->add_option("take", opt->take, "Take directory")->required();
  sub->add_option("--format", opt->format, "Exporter name, e.g. png")->required();
  sub->add_option("--out", opt->out, "Output directory (created)")->required();
  sub->add_option("--plugins", opt->folders, "Extra plugin folder (repeatable)");
  sub->callback([opt, &action] { action = [opt] { return run_export(*opt); }; });
}

}  // namespace pliant::cli
