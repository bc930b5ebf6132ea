// Test plugin whose load registers an exporter and then fails (returns 7):
// the host must drop the exporter and record the failure.
#include "pliant/plugin.h"

namespace {
int noop_frame(void*, const PliantFrame*, char*, size_t) { return 0; }
}  // namespace

extern "C" __attribute__((visibility("default"))) const uint32_t pliant_plugin_api_version =
    PLIANT_PLUGIN_API_VERSION;

extern "C" __attribute__((visibility("default"))) int pliant_plugin_load(
    const PliantHost* host, PliantRegistry* registry) {
  PliantExporter e{};
  e.name = "half_loaded";
  e.frame = &noop_frame;
  registry->register_exporter(registry->host_data, &e);
  host->log("warn", "failing_plugin: giving up on purpose");
  return 7;
}
