// Test plugin declaring a future plugin API version; the host must refuse it
// without calling pliant_plugin_load.
#include <cstdlib>

#include "pliant/plugin.h"

extern "C" __attribute__((visibility("default"))) const uint32_t pliant_plugin_api_version = 99;

extern "C" __attribute__((visibility("default"))) int pliant_plugin_load(const PliantHost*,
                                                                         PliantRegistry*) {
  std::abort();  // must never be called
}
