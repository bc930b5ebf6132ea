// A fixed panel window at a layout rectangle (no move, resize or collapse).
#pragma once
#include <imgui.h>

#include "ui/panels.h"

namespace pliant::editor {

inline bool begin_panel(const char* title, const PanelRect& r, ImGuiWindowFlags extra = 0) {
  ImGui::SetNextWindowPos(ImVec2(r.x, r.y), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(r.w, r.h), ImGuiCond_Always);
  return ImGui::Begin(title, nullptr,
                      ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                          ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoBringToFrontOnFocus |
                          extra);
}

inline const ImVec4 kErrorColor(1.0f, 0.35f, 0.3f, 1.0f);
inline const ImVec4 kWarnColor(1.0f, 0.8f, 0.3f, 1.0f);
inline const ImVec4 kDimColor(0.6f, 0.6f, 0.65f, 1.0f);

}  // namespace pliant::editor
