// UI scripts: a line-based text format, one command per line, '#' comments.
// They drive the editor the way a person does: inputs are injected into ImGui's
// IO across frames (press on one frame, release on the next).
//
//   move X Y                  mouse to window pixel
//   click [left|right|middle] [X Y]
//   drag X0 Y0 X1 Y1 [frames] [left|right|middle]
//   scroll DY
//   key CTRL+SHIFT+Z          modifiers + one key (S, O, Z, Y, SPACE, LEFT, F5, ENTER...)
//   type TEXT                 the rest of the line ($TMP expands)
//   wait N                    UI frames
//   wait_job [timeout_s]      until the newest job has ended (default 60 s)
//   wait_frames N [timeout_s] until the take has N frames
//   click_item LABEL [left|right|double]   an item marked with ui_mark(LABEL)
//   drag_item LABEL DX DY [frames]         drag from an item's centre
//   drag_item_at LABEL FX0 FY0 FX1 FY1 [frames]  drag between points given as
//                             fractions of an item's rectangle (0,0 top-left)
//   click_item_at LABEL FX FY a left click at a fraction of an item's rectangle
//   export png|mp4|vdb DIR    File > Export through the path dialog
//   wait_export [timeout_s]   until the newest export has ended (default 60 s)
//   set_frame N               drags the timeline slider, then steps with arrow keys
//   screenshot PATH [viewport]
//   drop PATH...              as if files were dropped on the window
//   expect TEXT               a log line or the status text contains TEXT
//   expect_json POINTER JSON  the document's value at POINTER equals JSON
//   quit
// Paths are relative to the script's folder; $TMP expands to a per-run temp dir.
// Labels and TEXT may be "quoted".
#pragma once
#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "ui/ui_mark.h"

namespace pliant::editor {

class App;

class ScriptError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ScriptCommand {
  int line = 0;
  std::string op;
  std::vector<std::string> args;
};

struct Script {
  std::string file;            // for messages
  std::filesystem::path dir;   // relative paths resolve here
  std::vector<ScriptCommand> commands;
};

// Throws ScriptError "FILE:LINE: problem" on an unknown command or bad arguments.
Script parse_script(const std::string& text, const std::string& file_label,
                    const std::filesystem::path& dir);
Script load_script(const std::filesystem::path& path);

class ScriptRunner {
 public:
  ScriptRunner(Script script, std::filesystem::path tmp_dir);
  // Installs itself as the app's before_frame/after_render hooks.
  void attach(App& app);
  // Advances the script by one UI frame (called from before_frame).
  void step(App& app);
  void after_render(App& app);

  bool finished() const { return pc_ >= script_.commands.size() || failed_ || quit_; }
  bool failed() const { return failed_; }
  bool quit_requested() const { return quit_; }
  const std::string& error() const { return error_; }
  // Screenshots written so far.
  const std::vector<std::string>& screenshots() const { return shots_; }

 private:
  std::string resolve(const std::string& path) const;
  void fail(const ScriptCommand& c, const std::string& msg);
  void next();
  bool run_command(App& app, const ScriptCommand& c);  // true when the command is complete

  Script script_;
  std::filesystem::path tmp_;
  size_t pc_ = 0;
  int phase_ = 0;  // frames spent in the current command
  std::chrono::steady_clock::time_point started_;
  bool failed_ = false, quit_ = false;
  std::string error_;
  // Drag/click plans.
  float x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0;
  int frames_ = 0, button_ = 0, y_base_ = 0;  // y_base_: frame the item was found
  UiRect last_;  // item rectangle seen on the previous frame
  bool have_last_ = false;
  std::string pending_shot_;
  bool pending_viewport_ = false;
  std::vector<std::string> shots_;
};

}  // namespace pliant::editor
