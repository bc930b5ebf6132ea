// A path-entry popup instead of native dialogs (works headless and in scripts).
#include <imgui.h>

#include <algorithm>

#include "ui/app.h"
#include "ui/panel_window.h"
#include "ui/panels.h"

namespace pliant::editor {

void draw_file_dialog(App& app) {
  FileDialog& d = app.file_dialog;
  const char* id = "File##dialog";
  if (d.open_requested) {
    ImGui::OpenPopup(id);
    d.open_requested = false;
  }
  ImVec2 ds = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(ds.x * 0.5f, ds.y * 0.4f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(std::min(640.0f, ds.x - 40), 0), ImGuiCond_Always);
  if (!ImGui::BeginPopupModal(id, nullptr, ImGuiWindowFlags_NoMove)) return;
  using M = FileDialog::Mode;
  const char* what = d.mode == M::Open          ? "Open scene (.json)"
                     : d.mode == M::SaveAs      ? "Save scene as (.json)"
                     : d.mode == M::ExportPng   ? "Export PNG sequence to folder"
                     : d.mode == M::ExportMp4   ? "Export MP4 (take.mp4 and frames/) to folder"
                     : d.mode == M::ExportVdb   ? "Export OpenVDB density (3D) to folder"
                     : d.mode == M::ExportParticles ? "Export particle positions (PLY per frame) to folder"
                     : d.mode == M::ExportObj   ? "Export surface meshes (OBJ per frame) to folder"
                     : d.mode == M::ExportCsv   ? "Export every frame's small fields (frames.csv) to folder"
                     : d.mode == M::ImportImage ? "Import image as a new keyframe at the current frame"
                                                : "Open take folder";
  ImGui::TextUnformatted(what);
  if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
  ImGui::SetNextItemWidth(-1);
  bool enter = ImGui::InputText("##path", d.path, sizeof d.path, ImGuiInputTextFlags_EnterReturnsTrue);
  ui_mark("dialog_path");
  if (!d.error.empty()) ImGui::TextColored(kErrorColor, "%s", d.error.c_str());
  bool ok = ImGui::Button("OK") || enter;
  ui_mark("dialog_ok");
  ImGui::SameLine();
  bool cancel = ImGui::Button("Cancel");
  ui_mark("dialog_cancel");
  if (ok && d.path[0]) {
    bool done = false;
    if (d.mode == FileDialog::Mode::Open) done = app.cmd_open(d.path);
    else if (d.mode == FileDialog::Mode::SaveAs) done = app.cmd_save_as(d.path);
    else if (d.mode == M::ExportPng) done = app.cmd_export("png", d.path);
    else if (d.mode == M::ExportMp4) done = app.cmd_export("mp4", d.path);
    else if (d.mode == M::ExportVdb) done = app.cmd_export("vdb", d.path);
    else if (d.mode == M::ExportParticles) done = app.cmd_export("particles", d.path);
    else if (d.mode == M::ExportObj) done = app.cmd_export("obj", d.path);
    else if (d.mode == M::ExportCsv) done = app.cmd_export("csv", d.path);
    else if (d.mode == M::ImportImage) done = import_image_keyframe(app, d.path, true);
    else done = app.cmd_open_take(d.path);
    if (done) {
      d.mode = FileDialog::Mode::None;
      ImGui::CloseCurrentPopup();
    } else {
      d.error = app.status();
    }
  }
  if (cancel) {
    d.mode = FileDialog::Mode::None;
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

}  // namespace pliant::editor
