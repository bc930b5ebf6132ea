// Placement view of liquid scenes (KindPanels::viewport_editor): before the
// first frame of a take (or with "Place" ticked) the viewport shows the
// document's own initial state instead of a result: the engine compiles the
// scene and seeds the liquid (liquid_initial_frame), and the liquid drawer
// draws that record like a take frame (containers from the engine's wall
// SDFs at their t = 0 poses, the initial liquid region as particles, the
// source's key-pose path). The gizmos work on it as on a result, so
// containers and key poses are placed before anything runs. It draws into the
// viewport's own OffscreenTarget, so screenshots of the viewport show it.
#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>
#include <cstdint>

#include "ui/app.h"
#include "ui/liquid_scene_geometry.h"
#include "ui/liquid_ui.h"
#include "ui/panel_window.h"

namespace pliant::editor {

namespace {

// Rebuilds the initial-state record when the document changed.
void update_record(App& app, LiquidUiState& ui) {
  if (ui.place_doc == app.doc.id() && ui.place_revision == app.doc.revision()) return;
  if (ui.place_doc != app.doc.id()) ui.place_reframe = true;
  ui.place_doc = app.doc.id();
  ui.place_revision = app.doc.revision();
  liquid_update_scene_dirs(app);
  Record r;
  std::string err;
  ui.place_ok = liquid_initial_frame(app.doc.scene(), &r, &err);
  ui.place_error = err;
  if (ui.place_ok) {
    ui.place_record = std::move(r);
    ui.place_dirty = true;
  }
}

}  // namespace

bool liquid_placement_view(App& app) {
  LiquidUiState& ui = liquid_ui(app);
  const bool has_result = app.take.frame_count() > 0;
  if (has_result && !ui.place_mode) return false;
  ViewportState& v = app.viewport;

  if (has_result) {
    if (ImGui::Button("Result")) {
      ui.place_mode = false;
      v.drawn_state.clear();  // the result view redraws the shared target
    }
    ui_mark("liquid_result");
    ImGui::SameLine();
  }
  if (ImGui::Button("Reset view")) {
    v.camera.reset();
    ui.place_reframe = ui.place_dirty = true;
  }
  ui_mark("Reset view");
  ImGui::SameLine();
  liquid_viewport_toolbar(app);
  update_record(app, ui);

  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const int w = std::max(16, int(avail.x)), h = std::max(16, int(avail.y));
  const ImVec2 pos = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("viewport_canvas", ImVec2(float(w), float(h)),
                         ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight |
                             ImGuiButtonFlags_MouseButtonMiddle);
  ui_mark("viewport");
  const ImGuiIO& io = ImGui::GetIO();
  // A gizmo drag holds the camera (liquid_gizmos starts it on the same click).
  if (ImGui::IsItemActive() && ui.drag == LiquidUiState::Handle::None) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) v.camera.orbit(io.MouseDelta.x, io.MouseDelta.y);
    else if (ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle))
      v.camera.pan(io.MouseDelta.x, io.MouseDelta.y, h);
  }
  if (ImGui::IsItemHovered() && io.MouseWheel != 0) v.camera.zoom(io.MouseWheel);

  ImDrawList* dl = ImGui::GetWindowDrawList();
  if (app.has_gl()) {
    if (!ui.place_ready) {
      std::string err;
      ui.place_ready = ui.place_renderer.init(&err);
      if (!ui.place_ready) {
        ui.place_ok = false;
        ui.place_error = "placement view: " + err;
      }
    }
    if (ui.place_ready && ui.place_ok && ui.place_dirty) {
      if (ui.place_reframe) ui.place_renderer.reset_framing();
      ui.place_renderer.set_frame(ui.place_record, &app.doc.scene());
      ui.place_reframe = ui.place_dirty = false;
      ++ui.place_uploads;
    }
    // The result view drew into the shared target since our last draw.
    if (!v.drawn_state.empty()) ui.place_drawn.clear();
    const OrbitCamera& cam = v.camera;
    std::vector<float> state = {float(ui.place_uploads), cam.yaw_deg, cam.pitch_deg, cam.distance, cam.fov_deg,
                                cam.target[0], cam.target[1], cam.target[2], cam.zoom2d, cam.pan2d[0],
                                cam.pan2d[1], float(w), float(h), float(ui.place_ok)};
    if (v.target.ensure(w, h) || state != ui.place_drawn) {
      GLint prev_fb = 0;
      glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev_fb);
      v.target.bind();
      const auto& bg = v.settings.background;
      glClearColor(bg[0], bg[1], bg[2], 1.0f);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      if (ui.place_ok && ui.place_renderer.has_frame()) {
        ui.place_renderer.render(v.camera, v.settings, w, h);
        ui.place_view = liquid_last_view();
      } else {
        ui.place_view.valid = false;
      }
      glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(prev_fb));
      ui.place_drawn = std::move(state);
      v.drawn_state.clear();
      ++ui.place_redraws;
    }
    dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(v.target.color_tex)), pos,
                 ImVec2(pos.x + w, pos.y + h), ImVec2(0, 1), ImVec2(1, 0));
    if (ui.place_ok) liquid_gizmos(app, ui.place_view, pos.x, pos.y, w, h);
  }
  if (!ui.place_ok) {
    const std::string msg = "Cannot place: " + ui.place_error;
    dl->AddText(nullptr, 0.0f, ImVec2(pos.x + 12, pos.y + 12), IM_COL32(255, 120, 110, 255), msg.c_str(), nullptr,
                float(w) - 24.0f);
  } else {
    const char* msg = has_result            ? "Placement: the scene's start (not the shown take)"
                      : app.take.is_open()  ? "Placement (waiting for the first frame)"
                                            : "Placement: the scene's start; press Plan / Simulate (F5)";
    dl->AddText(ImVec2(pos.x + 12, pos.y + 12), IM_COL32(200, 200, 210, 255), msg);
  }
  return true;
}

}  // namespace pliant::editor
