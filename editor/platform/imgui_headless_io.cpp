#include "platform/imgui_headless_io.h"

#include <imgui.h>

#include <algorithm>

namespace pliant::editor {

void HeadlessImGuiClock::new_frame(int width, int height, double fixed_dt_s) {
  if (ImGui::GetCurrentContext() == nullptr) return;
  ImGuiIO& io = ImGui::GetIO();
  if (!keymap_set_) {
    // Identity key map: scripts press ImGuiKey_X by setting io.KeysDown[ImGuiKey_X].
    for (int k = 0; k < ImGuiKey_COUNT; ++k) io.KeyMap[k] = k;
    if (io.BackendPlatformName == nullptr) io.BackendPlatformName = "pliant_headless";
    keymap_set_ = true;
  }
  io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
  io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
  auto now = std::chrono::steady_clock::now();
  double dt = fixed_dt_s;
  if (dt <= 0) dt = started_ ? std::chrono::duration<double>(now - last_).count() : 1.0 / 60.0;
  io.DeltaTime = static_cast<float>(std::max(dt, 1e-4));
  last_ = now;
  started_ = true;
}

}  // namespace pliant::editor
