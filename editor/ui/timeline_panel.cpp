// Frame slider over the current take, play/pause/loop, fps and frame steps.
// While the take is running the view follows the newest frame until scrubbed.
#include <imgui.h>

#include <string>

#include "ui/app.h"
#include "doc/smoke_keyframes.h"
#include "ui/panel_window.h"
#include "ui/kind_panels.h"
#include "ui/smoke_panels.h"

namespace pliant::editor {

void draw_timeline_panel(App& app, const PanelRect& r) {
  if (!begin_panel("Timeline", r)) {
    ImGui::End();
    return;
  }
  TakeView& t = app.take;
  int n = t.frame_count();
  if (ImGui::Button(t.playing ? "Pause" : "Play")) t.playing = !t.playing;
  ui_mark("Play");
  ImGui::SameLine();
  if (ImGui::ArrowButton("prev", ImGuiDir_Left)) t.step(-1);
  ui_mark("prev_frame");
  ImGui::SameLine();
  if (ImGui::ArrowButton("next", ImGuiDir_Right)) t.step(+1);
  ui_mark("next_frame");
  ImGui::SameLine();
  ImGui::Checkbox("loop", &t.loop);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90);
  ImGui::DragFloat("fps", &t.fps, 0.25f, 1.0f, 120.0f, "%.0f fps");
  ImGui::SameLine();
  if (t.user_scrubbed && t.status() == "running") {
    if (ImGui::SmallButton("Follow")) t.user_scrubbed = false;
    ImGui::SameLine();
  }
  std::string status = t.dir().empty() ? "no take" : t.is_open() ? t.status() : "waiting";
  ImGui::TextDisabled("%s | %d frames | %s", status.c_str(), n,
                      t.dir().empty() ? "" : t.dir().filename().string().c_str());
  ui_mark("take_status");
  if (!t.error().empty()) ImGui::TextColored(kErrorColor, "%s", t.error().c_str());

  ImGui::SetNextItemWidth(-1);
  int f = t.frame;
  if (n == 0) ImGui::BeginDisabled();
  if (ImGui::SliderInt("##frame", &f, 0, n > 0 ? n - 1 : 0, "frame %d")) t.set_frame(f);
  if (n == 0) ImGui::EndDisabled();
  ui_mark("frame_slider");
  // Scene kinds with keyframes draw their markers under the slider.
  if (has_control(app.doc.scene()) || is_smoke_2d(app.doc.scene())) draw_keyframe_markers(app);
  else if (const KindPanels* kp = kind_panels(scene_kind(app)); kp && kp->timeline) kp->timeline(app);
  ImGui::End();
}

}  // namespace pliant::editor
