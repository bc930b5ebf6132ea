#include "ui/hotkeys.h"

#include <imgui.h>

namespace pliant::editor {

bool key_pressed_code(int code) { return code >= 0 && code < 512 && ImGui::IsKeyPressed(code, false); }

bool key_pressed_named(int imgui_key) {
  return key_pressed_code(ImGui::GetIO().KeyMap[imgui_key]);
}

}  // namespace pliant::editor
