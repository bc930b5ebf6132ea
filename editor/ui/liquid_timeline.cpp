// Key poses of the hand-drawn source trajectory (/source/trajectory) on a strip
// under the frame slider: x = time / run length. Click a marker to select it
// (and show that frame), drag it to retime it, "+ Key" adds a key at the shown
// frame (pose interpolated), "Delete key" removes the selected one; the
// selected key's position and tilt are edited below. One undo step each.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "doc/liquid_scene_edit.h"
#include "ui/app.h"
#include "ui/json_widgets.h"
#include "ui/liquid_ui.h"

namespace pliant::editor {

using nlohmann::json;

namespace {
constexpr float kStripH = 22.0f;
constexpr float kMarkerHalfW = 5.0f;
}  // namespace

void liquid_timeline(App& app) {
  Document& doc = app.doc;
  LiquidUiState& ui = liquid_ui(app);
  const json& scene = doc.scene();
  if (!scene.contains("source") || !scene["source"].is_object()) return;
  const double duration = std::max(1e-6, liquid_duration_s(scene));
  const double dt = scene.value("time", json::object()).value("dt_s", 0.02);
  const std::vector<double> times = liquid_key_times(scene);
  if (ui.selected_key >= int(times.size())) ui.selected_key = -1;

  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  const float w = std::max(32.0f, ImGui::GetContentRegionAvail().x);
  ImGui::InvisibleButton("liquid_key_strip", ImVec2(w, kStripH));
  ui_mark("liquid_key_strip");
  const bool hovered = ImGui::IsItemHovered();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(p0, ImVec2(p0.x + w, p0.y + kStripH), IM_COL32(40, 42, 48, 255));
  auto x_of = [&](double t) { return p0.x + float(std::clamp(t / duration, 0.0, 1.0)) * (w - 1); };
  // The shown frame.
  const float fx = x_of(app.take.frame * dt);
  dl->AddLine(ImVec2(fx, p0.y), ImVec2(fx, p0.y + kStripH), IM_COL32(200, 200, 210, 160));
  for (size_t i = 0; i < times.size(); ++i) {
    const float x = x_of(times[i]);
    const bool sel = int(i) == ui.selected_key;
    dl->AddRectFilled(ImVec2(x - kMarkerHalfW, p0.y + 3), ImVec2(x + kMarkerHalfW, p0.y + kStripH - 3),
                      sel ? IM_COL32(255, 210, 90, 255) : IM_COL32(235, 160, 60, 255));
    ui_mark_rect("liquid_key_" + std::to_string(i), x - kMarkerHalfW, p0.y + 3, x + kMarkerHalfW, p0.y + kStripH - 3);
  }
  const ImGuiIO& io = ImGui::GetIO();
  const double mouse_t = std::clamp((io.MousePos.x - p0.x) / double(w - 1), 0.0, 1.0) * duration;
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    ui.selected_key = -1;
    for (size_t i = 0; i < times.size(); ++i)
      if (std::abs(io.MousePos.x - x_of(times[i])) <= kMarkerHalfW + 2) ui.selected_key = int(i);
    if (ui.selected_key >= 0) {
      ui.dragging_key = ui.selected_key;
      ui.key_drag_scene = scene;
      ui.key_drag_key = liquid_next_merge_key();
      if (app.take.frame_count() > 0) app.take.set_frame(int(std::lround(times[ui.selected_key] / dt)));
    } else if (app.take.frame_count() > 0) {
      app.take.set_frame(int(std::lround(mouse_t / dt)));
    }
  }
  if (ui.dragging_key >= 0) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left) && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 1.0f)) {
      // Snap to frames: key times the user can scrub to.
      const double t = std::round(mouse_t / dt) * dt;
      json next = liquid_move_key(ui.key_drag_scene, ui.dragging_key, t);
      if (next != doc.scene()) doc.edit("Move key pose", std::move(next), ui.key_drag_key);
    }
    if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) ui.dragging_key = -1;
  }

  if (ImGui::SmallButton("+ Key")) {
    int index = -1;
    json next = liquid_add_key(scene, app.take.frame * dt, &index);
    if (index >= 0) {
      doc.edit("Add key pose", std::move(next));
      ui.selected_key = index;
    }
  }
  ui_mark("liquid_add_key");
  ImGui::SameLine();
  if (ui.selected_key < 0) ImGui::BeginDisabled();
  if (ImGui::SmallButton("Delete key")) {
    doc.edit("Delete key pose", liquid_delete_key(scene, ui.selected_key));
    ui.selected_key = -1;
  }
  if (ui.selected_key < 0) ImGui::EndDisabled();
  ui_mark("liquid_delete_key");
  ImGui::SameLine();
  const std::string mode = scene.value("planner", json::object()).value("mode", std::string("none"));
  ImGui::TextDisabled("%zu key poses%s", times.size(), mode != "none" ? " (the planner replaces them)" : "");
  if (ui.selected_key >= 0 && ui.selected_key < int(liquid_key_times(doc.scene()).size())) {
    const std::string p = "/source/trajectory/" + std::to_string(ui.selected_key);
    ImGui::PushID(ui.selected_key);
    ImGui::SetNextItemWidth(180);
    json_vec(doc, "position (m)", p + "/position_m", liquid_dim(scene), 0.002f);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(90);
    json_double(doc, "tilt (deg)", p + "/tilt_deg", 0, 0.5f, -180, 180, "%.1f");
    ImGui::PopID();
  }
}

}  // namespace pliant::editor
