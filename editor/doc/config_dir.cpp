#include "doc/config_dir.h"

#include <cstdlib>

namespace pliant::editor {

std::filesystem::path config_dir() {
  if (const char* d = std::getenv("PLIANT_CONFIG_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x)
    return std::filesystem::path(x) / "pliant";
  if (const char* h = std::getenv("HOME"); h && *h)
    return std::filesystem::path(h) / ".config" / "pliant";
  return std::filesystem::temp_directory_path() / "pliant-config";
}

std::filesystem::path ensure_config_dir() {
  auto d = config_dir();
  std::error_code ec;
  std::filesystem::create_directories(d, ec);
  return d;
}

}  // namespace pliant::editor
