// The open document: the scene JSON, its file, dirty state, current take and
// selection. Every change of the scene goes through edit() so it can be undone;
// the UI reads scene() and never keeps its own copy of document data.
#pragma once
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "doc/undo_stack.h"

namespace pliant::editor {

class Document {
 public:
  Document();

  const nlohmann::json& scene() const { return scene_; }
  const std::filesystem::path& path() const { return path_; }  // empty: never saved
  bool has_path() const { return !path_.empty(); }
  // Differs from what was last loaded or saved (undoing back to it is clean).
  bool dirty() const { return scene_ != saved_; }
  std::string title() const;  // "name - file*"

  // An undoable edit: replaces the scene. merge_key != 0 merges continuous edits.
  void edit(const std::string& label, nlohmann::json new_scene, uint64_t merge_key = 0);
  // Sets the value at a JSON pointer (creating parents); one undo step.
  void set(const std::string& pointer, const nlohmann::json& value, uint64_t merge_key = 0);
  bool undo();
  bool redo();
  UndoStack& history() { return history_; }
  const UndoStack& history() const { return history_; }

  // Replaces everything (new/open/recover): clears history. saved_scene is what
  // the file on disk holds (dirty() compares against it).
  void reset(nlohmann::json scene, std::filesystem::path path,
             const nlohmann::json* saved_scene = nullptr);
  void mark_saved(const std::filesystem::path& path);

  // Edits since open; used by autosave to notice changes cheaply.
  uint64_t revision() const { return revision_; }
  // Unique per Document object in this process (caches keyed on revision need it:
  // revisions restart at 0 in every Document).
  uint64_t id() const { return id_; }

  std::filesystem::path take_dir;  // take shown in the viewport/timeline
  std::string selection;           // JSON pointer of the selected item

 private:
  nlohmann::json scene_, saved_;
  std::filesystem::path path_;
  UndoStack history_;
  uint64_t revision_ = 0;
  uint64_t id_ = 0;
};

}  // namespace pliant::editor
