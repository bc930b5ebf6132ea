// Keyframe markers of a smoke scene under the timeline slider: click selects a
// keyframe (and shows its frame), drag moves it to another frame (one undo step
// on release), a click between markers sets the current frame; "+ Key" adds an
// empty painted keyframe at the current frame, "Delete key" removes the selected.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "doc/smoke_keyframes.h"
#include "ui/app.h"
#include "ui/keyframe_canvas.h"
#include "ui/panel_window.h"
#include "ui/smoke_panels.h"

namespace pliant::editor {

namespace {

// Marker x of frame k of T: 1% margins so the ends are grabbable; scripts use the
// same fractions (0.01 + 0.98 k / T).
float frame_x(float x0, float w, int k, int T) { return x0 + w * (0.01f + 0.98f * float(k) / float(T)); }
int frame_at(float x0, float w, float mx, int T) {
  return std::clamp(int(std::lround(((mx - x0) / w - 0.01f) / 0.98f * T)), 0, T);
}

void set_current_frame(App& app, int f) {
  if (app.take.frame_count() > 0) app.take.set_frame(f);
  app.canvas.edit_frame = f;
}

struct MarkerDrag {
  int index = -1, from = 0, to = 0;
};

}  // namespace

void draw_keyframe_markers(App& app) {
  const nlohmann::json& scene = app.doc.scene();
  const int T = smoke_frames(scene);
  if (T <= 0) return;
  static MarkerDrag drag;
  KeyframeCanvasState& c = app.canvas;
  const int cur = canvas_current_frame(app);

  if (ImGui::Button("+ Key")) {
    int idx = 0;
    nlohmann::json next = with_keyframe_added(scene, std::max(1, cur), &idx);
    if (next != scene) {
      app.doc.edit("Add keyframe " + std::to_string(std::clamp(cur, 1, T)), std::move(next));
      app.set_status("Added keyframe at frame " + std::to_string(std::clamp(cur, 1, T)));
    }
    c.slot = idx;
  }
  ui_mark("add_key");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("add an empty painted keyframe at the current frame");
  ImGui::SameLine();
  const bool can_delete = c.slot >= 0;
  if (!can_delete) ImGui::BeginDisabled();
  if (ImGui::Button("Delete key")) {
    app.doc.edit("Delete keyframe", with_keyframe_removed(scene, c.slot));
    c.slot = kInitialDensitySlot;
  }
  if (!can_delete) ImGui::EndDisabled();
  ui_mark("delete_key");
  ImGui::SameLine();
  ImGui::Text("frame %d / %d", cur, T);
  ui_mark("frame_counter");
  ImGui::SameLine();
  ImGui::TextDisabled("%zu keyframes", list_keyframes(scene).size());

  const float w = std::max(50.0f, ImGui::GetContentRegionAvail().x), h = 22.0f;
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("keyframe_strip", ImVec2(w, h));
  ui_mark("keyframe_strip");
  const ImGuiIO& io = ImGui::GetIO();
  const auto keys = list_keyframes(scene);
  if (ImGui::IsItemActivated()) {
    drag.index = -1;
    for (const auto& k : keys)
      if (std::abs(io.MousePos.x - frame_x(p0.x, w, k.frame, T)) <= 6.0f) {
        drag = {k.index, k.frame, k.frame};
        c.slot = k.index;
        set_current_frame(app, k.frame);
      }
    if (drag.index < 0) set_current_frame(app, frame_at(p0.x, w, io.MousePos.x, T));
  } else if (ImGui::IsItemActive()) {
    const int f = frame_at(p0.x, w, io.MousePos.x, T);
    if (drag.index >= 0) drag.to = std::max(1, f);
    else set_current_frame(app, f);
  }
  if (ImGui::IsItemDeactivated() && drag.index >= 0) {
    if (drag.to != drag.from) {
      int where = drag.index;
      nlohmann::json next = with_keyframe_moved(scene, drag.index, drag.to, &where);
      if (next != scene) {
        app.doc.edit("Move keyframe " + std::to_string(drag.from) + " to " + std::to_string(drag.to),
                     std::move(next));
        c.slot = where;
        set_current_frame(app, drag.to);
      } else {
        app.set_status("Frame " + std::to_string(drag.to) + " already has a keyframe", true);
      }
    }
    drag.index = -1;
  }

  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(p0, ImVec2(p0.x + w, p0.y + h), IM_COL32(30, 32, 38, 255));
  const int tick = T <= 50 ? 5 : T <= 200 ? 10 : 50;
  for (int k = 0; k <= T; k += tick)
    dl->AddLine(ImVec2(frame_x(p0.x, w, k, T), p0.y + h - 5), ImVec2(frame_x(p0.x, w, k, T), p0.y + h),
                IM_COL32(120, 120, 130, 255));
  const float cx = frame_x(p0.x, w, std::clamp(cur, 0, T), T);
  dl->AddLine(ImVec2(cx, p0.y), ImVec2(cx, p0.y + h), IM_COL32(255, 90, 80, 255), 2.0f);
  for (const auto& k : keys) {
    const int f = drag.index == k.index ? drag.to : k.frame;
    const float x = frame_x(p0.x, w, f, T), y = p0.y + 0.5f * h, r = 6.0f;
    const ImU32 col = k.index == c.slot ? IM_COL32(255, 210, 60, 255) : IM_COL32(120, 190, 255, 255);
    dl->AddQuadFilled(ImVec2(x, y - r), ImVec2(x + r, y), ImVec2(x, y + r), ImVec2(x - r, y), col);
    ui_mark_rect("key_" + std::to_string(k.frame), x - r, y - r, x + r, y + r);
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("click: select a keyframe or set the frame; drag a keyframe to move it");
}

}  // namespace pliant::editor
