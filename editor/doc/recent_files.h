// Recently opened scenes, newest first, persisted as recent.json in the config dir.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace pliant::editor {

class RecentFiles {
 public:
  static constexpr size_t kMax = 10;
  explicit RecentFiles(std::filesystem::path file) : file_(std::move(file)) {}
  // Missing or malformed file: empty list (recent files are a convenience).
  void load();
  void save() const;
  // Moves (or inserts) the absolute path to the front and saves.
  void add(const std::filesystem::path& scene);
  void remove(const std::string& path);
  const std::vector<std::string>& items() const { return items_; }

 private:
  std::filesystem::path file_;
  std::vector<std::string> items_;
};

}  // namespace pliant::editor
