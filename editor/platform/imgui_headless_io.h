// ImGui platform-side helpers shared by the headless platforms (EGL, mock).
// ImGui 1.86 has no AddMousePosEvent/AddKeyEvent queue: UI scripts write
// io.MousePos / io.MouseDown / io.KeysDown directly, so these helpers set only
// display size and time and never touch input state.
#pragma once
#include <chrono>

namespace pliant::editor {

class HeadlessImGuiClock {
 public:
  // Sets io.DisplaySize (framebuffer scale 1) and io.DeltaTime: fixed_dt_s when
  // > 0 (deterministic runs), else real elapsed time, never below 1e-4 s
  // (ImGui asserts DeltaTime > 0). Also sets io.KeyMap as ImGui's GLFW backend
  // does (GLFW key codes), so a script presses Enter with
  // io.KeysDown[io.KeyMap[ImGuiKey_Enter]] = true, the same as in a window.
  // No-op without a current ImGui context.
  void new_frame(int width, int height, double fixed_dt_s);

 private:
  bool started_ = false;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace pliant::editor
