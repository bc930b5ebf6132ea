#include "ui/injected_input.h"

#include <imgui.h>

#include <algorithm>
#include <cctype>

#include "ui/hotkeys.h"

namespace pliant::editor {

void InjectedInput::apply() {
  if (!active) return;
  ImGuiIO& io = ImGui::GetIO();
  io.MousePos = ImVec2(mouse_x, mouse_y);
  for (int b = 0; b < 3; ++b) io.MouseDown[b] = mouse_down[b];
  io.MouseWheel = wheel;
  wheel = 0;
  for (int k : applied_keys_) io.KeysDown[k] = false;
  for (int k : keys_down)
    if (k >= 0 && k < 512) io.KeysDown[k] = true;
  applied_keys_ = keys_down;
  io.KeyCtrl = ctrl;
  io.KeyShift = shift;
  io.KeyAlt = alt;
  io.KeySuper = false;
  if (!chars.empty()) io.AddInputCharactersUTF8(chars.c_str());
  chars.clear();
}

int key_index_from_name(const std::string& raw) {
  std::string n = raw;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::toupper(c); });
  const ImGuiIO& io = ImGui::GetIO();
  struct Named {
    const char* name;
    ImGuiKey key;
  };
  static const Named kNamed[] = {
      {"TAB", ImGuiKey_Tab},           {"LEFT", ImGuiKey_LeftArrow},
      {"RIGHT", ImGuiKey_RightArrow},  {"UP", ImGuiKey_UpArrow},
      {"DOWN", ImGuiKey_DownArrow},    {"PAGEUP", ImGuiKey_PageUp},
      {"PAGEDOWN", ImGuiKey_PageDown}, {"HOME", ImGuiKey_Home},
      {"END", ImGuiKey_End},           {"INSERT", ImGuiKey_Insert},
      {"DELETE", ImGuiKey_Delete},     {"BACKSPACE", ImGuiKey_Backspace},
      {"SPACE", ImGuiKey_Space},       {"ENTER", ImGuiKey_Enter},
      {"ESCAPE", ImGuiKey_Escape},     {"KEYPADENTER", ImGuiKey_KeyPadEnter},
      {"A", ImGuiKey_A},               {"C", ImGuiKey_C},
      {"V", ImGuiKey_V},               {"X", ImGuiKey_X},
      {"Y", ImGuiKey_Y},               {"Z", ImGuiKey_Z},
  };
  for (const auto& k : kNamed)
    if (n == k.name) return io.KeyMap[k.key];
  if (n.size() == 1 && std::isalnum(static_cast<unsigned char>(n[0]))) return n[0];  // GLFW: ASCII
  if (n.size() >= 2 && n[0] == 'F' && std::isdigit(static_cast<unsigned char>(n[1]))) {
    int f = std::stoi(n.substr(1));
    if (f >= 1 && f <= 12) return kKeyF1 + f - 1;
  }
  return -1;
}

}  // namespace pliant::editor
