// Undo/redo of document edits as (before, after) JSON snapshots with labels.
// Scenes are small (kilobytes), so whole snapshots are simpler and safer than
// patches. Continuous edits (dragging a slider) merge into one step while the
// same merge key stays open; the app closes merging when no widget is active.
#pragma once
#include <cstddef>
#include <cstdint>
#include <deque>
#include <nlohmann/json.hpp>
#include <string>

namespace pliant::editor {

class UndoStack {
 public:
  struct Step {
    std::string label;
    nlohmann::json before, after;
    uint64_t merge_key = 0;  // 0: never merges
  };

  explicit UndoStack(size_t max_steps = 200) : max_steps_(max_steps) {}

  // Records an edit. Merges into the newest step when merge_key != 0 equals its
  // key and merging is still open. Clears the redo side.
  void push(const std::string& label, const nlohmann::json& before, const nlohmann::json& after,
            uint64_t merge_key = 0);
  // Ends the current merge run (a widget was released).
  void close_merge() { merge_open_ = false; }

  bool can_undo() const { return cursor_ > 0; }
  bool can_redo() const { return cursor_ < steps_.size(); }
  // Return the snapshot to restore; call only when can_undo()/can_redo().
  const nlohmann::json& undo();
  const nlohmann::json& redo();
  std::string undo_label() const { return can_undo() ? steps_[cursor_ - 1].label : ""; }
  std::string redo_label() const { return can_redo() ? steps_[cursor_].label : ""; }

  void clear();
  size_t size() const { return steps_.size(); }
  size_t cursor() const { return cursor_; }  // steps_[0..cursor) are applied
  size_t max_steps() const { return max_steps_; }

 private:
  std::deque<Step> steps_;
  size_t cursor_ = 0;
  size_t max_steps_;
  bool merge_open_ = false;
};

}  // namespace pliant::editor
