#include <imgui.h>

#include "ui/app.h"
#include "ui/kind_panels.h"
#include "ui/panels.h"

namespace pliant::editor {

void draw_menu_bar(App& app) {
  if (!ImGui::BeginMainMenuBar()) return;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("New")) app.cmd_new();
    if (ImGui::MenuItem("Open...", "Ctrl+O")) app.open_file_dialog(FileDialog::Mode::Open);
    if (ImGui::BeginMenu("Open Recent", !app.recent.items().empty())) {
      std::string chosen;
      for (const auto& p : app.recent.items())
        if (ImGui::MenuItem(p.c_str())) chosen = p;
      ImGui::EndMenu();
      if (!chosen.empty()) app.cmd_open(chosen);
    }
    if (ImGui::MenuItem("Save", "Ctrl+S")) app.cmd_save();
    if (ImGui::MenuItem("Save As...", "Ctrl+Shift+S")) app.open_file_dialog(FileDialog::Mode::SaveAs);
    ImGui::Separator();
    if (ImGui::MenuItem("Open Take...")) app.open_file_dialog(FileDialog::Mode::OpenTake);
    ImGui::Separator();
    // Kind-specific items appear only where they apply (a smoke keyframe image, a
    // liquid's particles, a soft body's meshes, the small per-frame fields).
    const std::string kind = scene_kind(app);
    const bool smoke = kind == "smoke" || kind.empty();
    if (smoke) {
      if (ImGui::MenuItem("Import Image as Keyframe...")) app.open_file_dialog(FileDialog::Mode::ImportImage);
      ui_mark("Import Image");
    }
    const bool has_frames = app.take.frame_count() > 0;
    if (ImGui::MenuItem("Export PNG Sequence...", nullptr, false, has_frames))
      app.open_file_dialog(FileDialog::Mode::ExportPng);
    ui_mark("Export PNG");
    if (ImGui::MenuItem("Export MP4...", nullptr, false, has_frames && !find_ffmpeg().empty()))
      app.open_file_dialog(FileDialog::Mode::ExportMp4);
    ui_mark("Export MP4");
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled) && find_ffmpeg().empty())
      ImGui::SetTooltip("needs ffmpeg (apt-get install ffmpeg)");
    if (smoke) {
      if (ImGui::MenuItem("Export OpenVDB (3D)...", nullptr, false, has_frames))
        app.open_file_dialog(FileDialog::Mode::ExportVdb);
      ui_mark("Export VDB");
    }
    if (kind == "liquid") {
      if (ImGui::MenuItem("Export Particles (PLY per frame)...", nullptr, false, has_frames))
        app.open_file_dialog(FileDialog::Mode::ExportParticles);
      ui_mark("Export Particles");
    }
    if (kind == "soft") {
      if (ImGui::MenuItem("Export OBJ Sequence...", nullptr, false, has_frames))
        app.open_file_dialog(FileDialog::Mode::ExportObj);
      ui_mark("Export OBJ");
    }
    if (kind == "articulated" || kind == "soft" || kind == "liquid") {
      if (ImGui::MenuItem("Export Table (CSV)...", nullptr, false, has_frames))
        app.open_file_dialog(FileDialog::Mode::ExportCsv);
      ui_mark("Export CSV");
    }
    ImGui::Separator();
    if (ImGui::MenuItem("Quit")) app.request_quit();
    ImGui::EndMenu();
  }
  ui_mark("File");
  if (ImGui::BeginMenu("Edit")) {
    std::string u = "Undo " + app.doc.history().undo_label();
    std::string r = "Redo " + app.doc.history().redo_label();
    if (ImGui::MenuItem(u.c_str(), "Ctrl+Z", false, app.doc.history().can_undo())) app.cmd_undo();
    ui_mark("Undo");
    if (ImGui::MenuItem(r.c_str(), "Ctrl+Shift+Z", false, app.doc.history().can_redo()))
      app.cmd_redo();
    ui_mark("Redo");
    ImGui::EndMenu();
  }
  ui_mark("Edit");
  if (ImGui::BeginMenu("View")) {
    ImGui::MenuItem("Inspector", nullptr, &app.panels.inspector);
    ImGui::MenuItem("Viewport", nullptr, &app.panels.viewport);
    ImGui::MenuItem("Timeline", nullptr, &app.panels.timeline);
    ImGui::MenuItem("Jobs", nullptr, &app.panels.jobs);
    ImGui::MenuItem("Log", nullptr, &app.panels.log);
    ImGui::EndMenu();
  }
  ui_mark("View");
  ImGui::TextDisabled("  %s", app.doc.title().c_str());
  if (app.status_is_error()) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "   %s", app.status().c_str());
  }
  ImGui::EndMainMenuBar();
}

}  // namespace pliant::editor
