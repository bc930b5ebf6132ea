// The headless session: run a UI script (or N plain frames), write the
// screenshot, report the first failure. Shared by main() and the editor tests.
#pragma once
#include <filesystem>
#include <string>

#include "ui/app.h"

namespace pliant::editor {

struct HeadlessRunOptions {
  std::filesystem::path script;      // "" = just render `frames` frames
  std::filesystem::path screenshot;  // written after the last frame ("" = none)
  bool viewport_only = false;
  int frames = 2;
  int max_frames = 100000;
  std::filesystem::path tmp_dir;     // $TMP of the script ("" = a fresh folder, removed after)           // safety net against a script that never ends
};

// Returns "" on success, else the error (a script error names file and line).
std::string run_headless(App& app, const HeadlessRunOptions& opt);

}  // namespace pliant::editor
