// Log lines from the editor and the jobs, with a level filter, Clear and
// auto-scroll to the newest line.
#include <imgui.h>

#include "ui/app.h"
#include "ui/panel_window.h"

namespace pliant::editor {

namespace {
struct LogView {
  int min_level = 1;  // info
  bool auto_scroll = true;
  uint64_t seen = 0;
};
}  // namespace

void draw_log_panel(App& app, const PanelRect& r) {
  static LogView view;  // panel-local view state, not document data
  if (!begin_panel("Log", r)) {
    ImGui::End();
    return;
  }
  if (ImGui::Button("Clear")) app.log.clear();
  ui_mark("Clear log");
  ImGui::SameLine();
  ImGui::Checkbox("auto-scroll", &view.auto_scroll);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(80);
  ImGui::Combo("##level", &view.min_level, "debug\0info\0warning\0error\0");
  ImGui::Separator();
  ImGui::BeginChild("log_lines", ImVec2(0, 0), false, ImGuiWindowFlags_HorizontalScrollbar);
  for (const auto& l : app.log.lines()) {
    if (static_cast<int>(l.level) < view.min_level) continue;
    ImVec4 c = l.level == LogLevel::Error     ? kErrorColor
               : l.level == LogLevel::Warning ? kWarnColor
               : l.level == LogLevel::Debug   ? kDimColor
                                              : ImVec4(0.9f, 0.9f, 0.92f, 1);
    ImGui::TextColored(c, "[%s] %s", l.source.c_str(), l.message.c_str());
  }
  if (view.auto_scroll && view.seen != app.log.added()) ImGui::SetScrollHereY(1.0f);
  view.seen = app.log.added();
  ImGui::EndChild();
  ImGui::End();
}

}  // namespace pliant::editor
