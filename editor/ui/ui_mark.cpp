#include "ui/ui_mark.h"

#include <imgui.h>

namespace pliant::editor {

namespace {
UiMarks* g_marks = nullptr;
}

void UiMarks::begin_frame() {
  previous_.swap(current_);
  current_.clear();
}

const UiRect* UiMarks::find(const std::string& label) const {
  auto it = previous_.find(label);
  return it == previous_.end() ? nullptr : &it->second;
}

void set_ui_marks(UiMarks* marks) { g_marks = marks; }

void ui_mark(const std::string& label) {
  if (!g_marks) return;
  ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  g_marks->add(label, UiRect{a.x, a.y, b.x, b.y});
}

void ui_mark_field(const std::string& label) {
  if (!g_marks) return;
  ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  float w = ImGui::CalcItemWidth();
  if (w > 0 && a.x + w < b.x) b.x = a.x + w;
  g_marks->add(label, UiRect{a.x, a.y, b.x, b.y});
}

void ui_mark_rect(const std::string& label, float x0, float y0, float x1, float y1) {
  if (g_marks) g_marks->add(label, UiRect{x0, y0, x1, y1});
}

}  // namespace pliant::editor
