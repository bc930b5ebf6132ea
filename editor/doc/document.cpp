#include "doc/document.h"

#include <atomic>

namespace pliant::editor {

Document::Document() : scene_(nlohmann::json::object()), saved_(scene_) {
  static std::atomic<uint64_t> next_id{1};
  id_ = next_id++;
}

std::string Document::title() const {
  std::string name = scene_.is_object() ? scene_.value("name", std::string()) : std::string();
  std::string file = path_.empty() ? "untitled" : path_.filename().string();
  std::string t = name.empty() ? file : name + " - " + file;
  return dirty() ? t + "*" : t;
}

void Document::edit(const std::string& label, nlohmann::json new_scene, uint64_t merge_key) {
  if (new_scene == scene_) return;
  history_.push(label, scene_, new_scene, merge_key);
  scene_ = std::move(new_scene);
  ++revision_;
}

void Document::set(const std::string& pointer, const nlohmann::json& value, uint64_t merge_key) {
  nlohmann::json next = scene_;
  next[nlohmann::json::json_pointer(pointer)] = value;
  edit("Set " + pointer, std::move(next), merge_key);
}

bool Document::undo() {
  if (!history_.can_undo()) return false;
  scene_ = history_.undo();
  ++revision_;
  return true;
}

bool Document::redo() {
  if (!history_.can_redo()) return false;
  scene_ = history_.redo();
  ++revision_;
  return true;
}

void Document::reset(nlohmann::json scene, std::filesystem::path path,
                     const nlohmann::json* saved_scene) {
  scene_ = std::move(scene);
  saved_ = saved_scene ? *saved_scene : scene_;
  path_ = std::move(path);
  history_.clear();
  selection.clear();
  ++revision_;
}

void Document::mark_saved(const std::filesystem::path& path) {
  path_ = path;
  saved_ = scene_;
}

}  // namespace pliant::editor
