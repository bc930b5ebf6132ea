// Where the editor keeps recent files, autosaves and session locks:
// $PLIANT_CONFIG_DIR (tests), else $XDG_CONFIG_HOME/pliant, else ~/.config/pliant.
#pragma once
#include <filesystem>

namespace pliant::editor {

std::filesystem::path config_dir();
// Creates the folder if needed; returns it.
std::filesystem::path ensure_config_dir();

}  // namespace pliant::editor
