// Input a UI script injects into ImGui's IO, applied every frame after the
// platform's new_frame so it wins over the (absent or real) device state.
// ImGui 1.86 has no input-event queue: we write io.MousePos/MouseDown/KeysDown.
#pragma once
#include <string>
#include <vector>

namespace pliant::editor {

struct InjectedInput {
  bool active = false;  // false: leave IO to the platform (windowed use)
  float mouse_x = -1, mouse_y = -1;
  bool mouse_down[3] = {false, false, false};
  float wheel = 0;             // consumed after one frame
  std::vector<int> keys_down;  // io.KeysDown indices held this frame
  bool ctrl = false, shift = false, alt = false;
  std::string chars;  // typed text, consumed after one frame

  // Writes the state into ImGui's IO (needs a current context).
  void apply();

 private:
  std::vector<int> applied_keys_;
};

// io.KeysDown index of a key name as UI scripts spell it ("S", "SPACE", "LEFT",
// "F5", "ENTER", ...); -1 if unknown. Keys ImGui 1.86 names (arrows, Enter,
// A/C/V/X/Y/Z...) go through io.KeyMap so both the GLFW and the headless key
// maps work; other keys use GLFW key codes, which are what the hotkeys read.
int key_index_from_name(const std::string& name);

}  // namespace pliant::editor
