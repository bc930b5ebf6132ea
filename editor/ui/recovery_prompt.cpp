// After a crash: offer the newest autosave of a dead session (Recover / Discard).
#include <imgui.h>

#include "ui/app.h"
#include "ui/panels.h"

namespace pliant::editor {

void draw_recovery_prompt(App& app) {
  const char* id = "Recover unsaved work?";
  if (!app.recovery) return;
  if (!ImGui::IsPopupOpen(id)) ImGui::OpenPopup(id);
  ImVec2 ds = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(ds.x * 0.5f, ds.y * 0.4f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  if (!ImGui::BeginPopupModal(id, nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove))
    return;
  const RecoveryCandidate& c = *app.recovery;
  ImGui::Text("The editor (pid %d) did not exit cleanly.", c.pid);
  ImGui::Text("An autosave of %s exists.",
              c.file.empty() ? "an unsaved scene" : c.file.string().c_str());
  ImGui::Text("Recover it? Discard deletes the autosave.");
  ui_mark("recovery_prompt");
  bool accept = ImGui::Button("Recover");
  ui_mark("Recover");
  ImGui::SameLine();
  bool discard = ImGui::Button("Discard");
  ui_mark("Discard");
  if (accept || discard) {
    app.recover(accept);
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

}  // namespace pliant::editor
