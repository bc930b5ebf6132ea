// Editor hotkeys. ImGui 1.86 names only a few keys (ImGuiKey_*); S, O and the
// function keys are read by their GLFW key codes, which the GLFW backend uses
// as io.KeysDown indices (headless runs inject the same codes).
#pragma once

namespace pliant::editor {

inline constexpr int kKeyO = 'O';  // GLFW_KEY_O
inline constexpr int kKeyS = 'S';  // GLFW_KEY_S
inline constexpr int kKeyF1 = 290; // GLFW_KEY_F1; F5 = 294

// Pressed this frame (ImGui repeat off).
bool key_pressed_code(int code);
// Pressed this frame, through io.KeyMap (ImGuiKey_*).
bool key_pressed_named(int imgui_key);

}  // namespace pliant::editor
