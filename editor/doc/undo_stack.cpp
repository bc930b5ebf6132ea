#include "doc/undo_stack.h"

namespace pliant::editor {

void UndoStack::push(const std::string& label, const nlohmann::json& before,
                     const nlohmann::json& after, uint64_t merge_key) {
  if (merge_key != 0 && merge_open_ && cursor_ == steps_.size() && cursor_ > 0 &&
      steps_.back().merge_key == merge_key) {
    steps_.back().after = after;
    return;
  }
  steps_.erase(steps_.begin() + static_cast<std::ptrdiff_t>(cursor_), steps_.end());
  steps_.push_back(Step{label, before, after, merge_key});
  while (steps_.size() > max_steps_) steps_.pop_front();
  cursor_ = steps_.size();
  merge_open_ = merge_key != 0;
}

const nlohmann::json& UndoStack::undo() {
  merge_open_ = false;
  --cursor_;
  return steps_[cursor_].before;
}

const nlohmann::json& UndoStack::redo() {
  merge_open_ = false;
  ++cursor_;
  return steps_[cursor_ - 1].after;
}

void UndoStack::clear() {
  steps_.clear();
  cursor_ = 0;
  merge_open_ = false;
}

}  // namespace pliant::editor
