// Test plugin with the right API version but no pliant_plugin_load.
#include "pliant/plugin.h"

extern "C" __attribute__((visibility("default"))) const uint32_t pliant_plugin_api_version =
    PLIANT_PLUGIN_API_VERSION;
