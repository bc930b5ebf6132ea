// A registry of item rectangles for UI scripts: panels call ui_mark(label) right
// after an important widget, so a script can `click_item Run` without pixel
// coordinates. Marks of the last complete frame are what scripts look up.
#pragma once
#include <map>
#include <string>

namespace pliant::editor {

struct UiRect {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  float cx() const { return 0.5f * (x0 + x1); }
  float cy() const { return 0.5f * (y0 + y1); }
};

class UiMarks {
 public:
  void begin_frame();  // current -> previous
  void add(const std::string& label, const UiRect& r) { current_[label] = r; }
  // From the last complete frame.
  const UiRect* find(const std::string& label) const;
  const std::map<std::string, UiRect>& last_frame() const { return previous_; }

 private:
  std::map<std::string, UiRect> current_, previous_;
};

// The registry ui_mark() writes to (set by the App each frame; may be null).
void set_ui_marks(UiMarks* marks);
// Records the last ImGui item's rectangle under `label`.
void ui_mark(const std::string& label);
// For labelled fields (drags, inputs, combos): only the input frame, whose
// width is the current item width, so a click lands on the field, not its label.
void ui_mark_field(const std::string& label);
// A rectangle that is not an ImGui item (a marker drawn on a strip).
void ui_mark_rect(const std::string& label, float x0, float y0, float x1, float y1);

}  // namespace pliant::editor
