#include "doc/recent_files.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "pliant/core/scene.h"

namespace pliant::editor {

void RecentFiles::load() {
  items_.clear();
  std::ifstream in(file_);
  if (!in) return;
  auto j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object() || !j.contains("recent") || !j["recent"].is_array()) return;
  for (const auto& e : j["recent"])
    if (e.is_string() && items_.size() < kMax) items_.push_back(e.get<std::string>());
}

void RecentFiles::save() const {
  std::error_code ec;
  std::filesystem::create_directories(file_.parent_path(), ec);
  try {
    save_json_atomic(file_, nlohmann::json{{"recent", items_}});
  } catch (const std::exception&) {
    // A read-only config dir must not stop the editor.
  }
}

void RecentFiles::add(const std::filesystem::path& scene) {
  std::error_code ec;
  auto abs = std::filesystem::absolute(scene, ec).lexically_normal().string();
  remove(abs);
  items_.insert(items_.begin(), abs);
  if (items_.size() > kMax) items_.resize(kMax);
  save();
}

void RecentFiles::remove(const std::string& path) {
  items_.erase(std::remove(items_.begin(), items_.end(), path), items_.end());
}

}  // namespace pliant::editor
