#include "platform/imgui_headless_io.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes only: headless keys use GLFW's numbering
#include <imgui.h>

#include <algorithm>

namespace pliant::editor {

void HeadlessImGuiClock::new_frame(int width, int height, double fixed_dt_s) {
  if (ImGui::GetCurrentContext() == nullptr) return;
  ImGuiIO& io = ImGui::GetIO();
  static const char* const kName = "pliant_headless";
  // Every frame, so a context created after init() gets it too; never over
  // another backend's map.
  if (io.BackendPlatformName == nullptr || io.BackendPlatformName == kName) {
    // The key map ImGui's GLFW backend installs, so scripts and hotkeys use the
    // same io.KeysDown indices (GLFW key codes, ASCII for letters) in both.
    static const int kGlfwKeys[ImGuiKey_COUNT] = {
        GLFW_KEY_TAB,    GLFW_KEY_LEFT,      GLFW_KEY_RIGHT,    GLFW_KEY_UP,        GLFW_KEY_DOWN,
        GLFW_KEY_PAGE_UP, GLFW_KEY_PAGE_DOWN, GLFW_KEY_HOME,    GLFW_KEY_END,       GLFW_KEY_INSERT,
        GLFW_KEY_DELETE, GLFW_KEY_BACKSPACE, GLFW_KEY_SPACE,    GLFW_KEY_ENTER,     GLFW_KEY_ESCAPE,
        GLFW_KEY_KP_ENTER, GLFW_KEY_A,       GLFW_KEY_C,        GLFW_KEY_V,         GLFW_KEY_X,
        GLFW_KEY_Y,      GLFW_KEY_Z};
    static_assert(ImGuiKey_COUNT == 22, "ImGui 1.86 key list");
    for (int k = 0; k < ImGuiKey_COUNT; ++k) io.KeyMap[k] = kGlfwKeys[k];
    io.BackendPlatformName = kName;
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
