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
  std::filesystem::path tmp_dir;     // $TMP of the script ("" = a fresh folder, removed after)
  // The main job without a display: start the document's job (into run_take,
  // "" = the default take folder), keep the UI running until it ends, then
  // render every frame of the take into render_frames/frame_NNNNN.png.
  bool run = false;
  std::filesystem::path run_take;
  std::filesystem::path render_frames;
};

// Returns "" on success, else the error (a script error names file and line).
std::string run_headless(App& app, const HeadlessRunOptions& opt);
// Runs the document's job to its end with the UI live (part of run_headless).
std::string run_job_headless(App& app, const std::filesystem::path& take_dir);
// Renders every frame of the app's current take through the viewport to PNGs.
// Returns "" on success; *written receives the number of files.
std::string render_take_frames(App& app, const std::filesystem::path& out_dir, int* written);

}  // namespace pliant::editor
