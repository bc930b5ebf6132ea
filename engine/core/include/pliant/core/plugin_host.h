// The plugin host: loads shared libraries that speak the C ABI of
// plugins/include/pliant/plugin.h (ARCHITECTURE.md, Plugins) and exports takes
// through their exporters. Used by the `pliant` CLI and the editor; no GL.
//
// Each library is dlopen()ed with RTLD_NOW | RTLD_LOCAL, so a missing symbol is
// found at load time and two plugins cannot clash on symbol names. A library
// that is not a plugin, was built for another API version, or whose
// pliant_plugin_load fails is recorded in failures() and the host keeps going.
// Plugins' PliantHost::log lines go to pliant::log (log.h) as "plugin: ...".
#pragma once
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pliant/plugin.h"

namespace pliant {

class Progress;
class TakeReader;

// An exporter registered by a plugin; the strings are owned by the host.
struct Exporter {
  std::string name, description, extension;
  std::filesystem::path plugin;  // library it came from
  PliantExporter api{};          // api.name etc. point into the strings above
};

struct LoadedPlugin {
  std::filesystem::path path;
  std::vector<std::string> exporters;  // names it registered
};

struct PluginFailure {
  std::filesystem::path path;
  std::string reason;  // one line, names the file
};

// An exporter returned nonzero (message from the plugin) or a frame could not be read.
class ExportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class PluginHost {
 public:
  PluginHost() = default;
  ~PluginHost();  // drops the exporters, then dlclose()s in reverse load order
  PluginHost(const PluginHost&) = delete;
  PluginHost& operator=(const PluginHost&) = delete;

  // plugins/ beside the running executable (/proc/self/exe), then each
  // non-empty entry of $PLIANT_PLUGIN_PATH (':'-separated).
  static std::vector<std::filesystem::path> default_folders();

  // Loads every *.so in `folder` in name order (a missing folder is not an error).
  void load_folder(const std::filesystem::path& folder);
  void load_default_folders();
  // Loads one library; false (and a failure recorded) when it was refused.
  // A library already loaded (same canonical path) is skipped and returns true.
  bool load_file(const std::filesystem::path& file);

  const std::vector<LoadedPlugin>& plugins() const { return plugins_; }
  const std::vector<PluginFailure>& failures() const { return failures_; }
  std::vector<const Exporter*> exporters() const;
  const Exporter* find_exporter(std::string_view name) const;  // nullptr if none

 private:
  struct Library {
    std::filesystem::path path, canonical;  // canonical: for de-duplication
    void* handle = nullptr;                 // from dlopen
  };
  static int register_exporter_cb(void* host_data, const PliantExporter* exporter);
  void fail(const std::filesystem::path& path, std::string reason);

  std::vector<Library> libraries_;  // load order
  std::vector<std::unique_ptr<Exporter>> exporters_;  // stable addresses
  std::vector<LoadedPlugin> plugins_;
  std::vector<PluginFailure> failures_;
  // While a plugin's pliant_plugin_load runs: its path and exporters so far.
  const std::filesystem::path* loading_ = nullptr;
  std::vector<std::string> loading_names_;
};

// Feeds every frame of `take` (in TakeReader::read_frame_at order) to
// `exporter`: begin(out_dir, take_dir, frame_count), frame() per frame, end().
// Reports stage "export" on `progress` and checks cancellation between frames
// (throws CancelledError after calling end()). Throws ExportError naming the
// exporter and the frame when the plugin fails. Returns the frames written.
int export_take(TakeReader& take, const Exporter& exporter, const std::filesystem::path& out_dir,
                Progress* progress = nullptr);

}  // namespace pliant
