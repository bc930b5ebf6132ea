// Plugin loading with dlopen and exporting takes through plugin exporters.
#include "pliant/core/plugin_host.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <system_error>

#include "pliant/core/error.h"
#include "pliant/core/log.h"
#include "pliant/core/progress.h"
#include "pliant/core/take.h"
#include "pliant/core/version.h"

namespace pliant {
namespace fs = std::filesystem;

namespace {

// The C log callback handed to plugins (PliantHost::log).
void host_log(const char* level, const char* message) {
  const std::string lv = level ? level : "info";
  const LogLevel l = lv == "error" ? LogLevel::Error : lv == "warn" ? LogLevel::Warn : LogLevel::Info;
  log(l, std::string("plugin: ") + (message ? message : ""));
}

const PliantHost kHostApi = {PLIANT_PLUGIN_API_VERSION, kEngineVersion, &host_log};

fs::path canonical_or_self(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(p, ec);
  return ec ? fs::absolute(p) : c;
}

std::string dl_error() {
  const char* e = dlerror();
  return e ? e : "unknown dlopen error";
}

}  // namespace

PluginHost::~PluginHost() {
  exporters_.clear();  // their function pointers live in the libraries
  for (auto it = libraries_.rbegin(); it != libraries_.rend(); ++it) {
    if (it->handle) dlclose(it->handle);
  }
}

std::vector<fs::path> PluginHost::default_folders() {
  std::vector<fs::path> out;
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back(exe.parent_path() / "plugins");
  if (const char* env = std::getenv("PLIANT_PLUGIN_PATH")) {
    std::string s = env;
    size_t start = 0;
    while (start <= s.size()) {
      size_t end = s.find(':', start);
      if (end == std::string::npos) end = s.size();
      if (end > start) out.emplace_back(s.substr(start, end - start));
      start = end + 1;
    }
  }
  return out;
}

void PluginHost::load_default_folders() {
  std::set<fs::path> seen;
  for (const fs::path& folder : default_folders()) {
    if (seen.insert(canonical_or_self(folder)).second) load_folder(folder);
  }
}

void PluginHost::load_folder(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return;
  std::vector<fs::path> files;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& p = it->path();
    if (p.extension() == ".so" && !fs::is_directory(p)) files.push_back(p);
  }
  if (ec) fail(folder, "plugin folder " + folder.string() + ": cannot list: " + ec.message());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) load_file(f);
}

void PluginHost::fail(const fs::path& path, std::string reason) {
  failures_.push_back({path, std::move(reason)});
}

bool PluginHost::load_file(const fs::path& file) {
  const fs::path canonical = canonical_or_self(file);
  for (const auto& lib : libraries_) {
    if (lib.canonical == canonical) return true;
  }
  for (const auto& f : failures_) {
    if (canonical_or_self(f.path) == canonical) return false;
  }
  const std::string name = file.string();
  // dlopen searches the library path unless the name has a '/'.
  const fs::path abs = fs::absolute(file);
  dlerror();
  void* handle = dlopen(abs.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    fail(file, "plugin " + name + ": cannot load: " + dl_error());
    return false;
  }
  auto refuse = [&](std::string reason) {
    dlclose(handle);
    fail(file, std::move(reason));
    return false;
  };
  const auto* version = static_cast<const uint32_t*>(dlsym(handle, "pliant_plugin_api_version"));
  if (!version) {
    return refuse("plugin " + name +
                  ": not a Pliant plugin (no pliant_plugin_api_version symbol)");
  }
  if (*version != PLIANT_PLUGIN_API_VERSION) {
    return refuse("plugin " + name + ": built for plugin API " + std::to_string(*version) +
                  ", this Pliant has API " + std::to_string(PLIANT_PLUGIN_API_VERSION) +
                  "; rebuild it");
  }
  auto load = reinterpret_cast<PliantPluginLoadFn>(dlsym(handle, "pliant_plugin_load"));
  if (!load) return refuse("plugin " + name + ": has no pliant_plugin_load function");

  PliantRegistry registry{PLIANT_PLUGIN_API_VERSION, this, &PluginHost::register_exporter_cb};
  loading_ = &file;
  loading_names_.clear();
  const size_t exporters_before = exporters_.size();
  int rc = 0;
  std::string thrown;
  try {
    rc = load(&kHostApi, &registry);
  } catch (const std::exception& e) {  // a C++ plugin leaking an exception
    rc = -1;
    thrown = e.what();
  } catch (...) {
    rc = -1;
    thrown = "unknown exception";
  }
  loading_ = nullptr;
  if (rc != 0) {
    exporters_.resize(exporters_before);  // drop what it registered before failing
    return refuse("plugin " + name + ": pliant_plugin_load " +
                  (thrown.empty() ? "returned " + std::to_string(rc) : "threw: " + thrown));
  }
  libraries_.push_back({file, canonical, handle});
  plugins_.push_back({file, loading_names_});
  return true;
}

int PluginHost::register_exporter_cb(void* host_data, const PliantExporter* e) {
  auto* self = static_cast<PluginHost*>(host_data);
  if (!self || !self->loading_) return -1;  // only valid during pliant_plugin_load
  const std::string who = self->loading_->string();
  if (!e || !e->name || !*e->name || !e->frame) {
    log_error("plugin " + who + ": register_exporter needs a name and a frame function");
    return -1;
  }
  if (const Exporter* other = self->find_exporter(e->name)) {
    log_warn("plugin " + who + ": exporter \"" + e->name + "\" is already provided by " +
             other->plugin.string() + "; ignored");
    return -1;
  }
  auto ex = std::make_unique<Exporter>();
  ex->name = e->name;
  ex->description = e->description ? e->description : "";
  ex->extension = e->extension ? e->extension : "";
  ex->plugin = *self->loading_;
  ex->api = *e;
  ex->api.name = ex->name.c_str();
  ex->api.description = ex->description.c_str();
  ex->api.extension = ex->extension.c_str();
  self->loading_names_.push_back(ex->name);
  self->exporters_.push_back(std::move(ex));
  return 0;
}

std::vector<const Exporter*> PluginHost::exporters() const {
  std::vector<const Exporter*> out;
  for (const auto& e : exporters_) out.push_back(e.get());
  return out;
}

const Exporter* PluginHost::find_exporter(std::string_view name) const {
  for (const auto& e : exporters_) {
    if (e->name == name) return e.get();
  }
  return nullptr;
}

namespace {

// Calls an exporter's begin/end, turning nonzero into ExportError.
std::string call_message(const char* err, int rc) {
  return err[0] ? std::string(err) : "returned " + std::to_string(rc);
}

}  // namespace

int export_take(TakeReader& take, const Exporter& exporter, const fs::path& out_dir,
                Progress* progress) {
  const PliantExporter& api = exporter.api;
  const std::string label = "exporter \"" + exporter.name + "\"";
  const size_t count = take.frame_count();
  char err[1024] = {0};
  if (api.begin) {
    int rc = api.begin(api.user, out_dir.c_str(), take.dir().c_str(), uint32_t(count), err,
                       sizeof err);
    if (rc != 0) throw ExportError(label + ": " + call_message(err, rc));
  }
  // end() must run whatever happens after a successful begin().
  auto end_quietly = [&] {
    char ignored[256] = {0};
    if (api.end) api.end(api.user, ignored, sizeof ignored);
  };
  if (progress) progress->stage("export", int(count));
  std::vector<PliantField> views;
  for (size_t n = 0; n < count; ++n) {
    if (progress && progress->cancelled()) {
      end_quietly();
      throw CancelledError();
    }
    Record rec;
    try {
      rec = take.read_frame_at(n);
    } catch (...) {
      end_quietly();
      throw;
    }
    views.clear();
    for (const Field& f : rec.fields) {
      views.push_back({f.name.c_str(), f.shape.data(), uint32_t(f.shape.size()), f.data.data()});
    }
    PliantFrame frame{rec.index, rec.time_s, views.data(), uint32_t(views.size())};
    err[0] = 0;
    int rc = api.frame(api.user, &frame, err, sizeof err);
    if (rc != 0) {
      end_quietly();
      throw ExportError(label + ": frame " + std::to_string(rec.index) + ": " +
                        call_message(err, rc));
    }
    if (progress) progress->report(int(n + 1));
  }
  if (api.end) {
    err[0] = 0;
    int rc = api.end(api.user, err, sizeof err);
    if (rc != 0) throw ExportError(label + ": " + call_message(err, rc));
  }
  return int(count);
}

}  // namespace pliant
