// The editor application: one Document, its jobs, the take being viewed and
// the panels, driven one UI frame at a time. main() and the editor tests both
// drive this class (tests in-process, headless).
//
// Frame order: platform.new_frame -> injected script input -> OpenGL3 backend
// NewFrame -> ImGui::NewFrame -> panels -> ImGui::Render -> default framebuffer,
// clear, draw data -> after-render hook (screenshots) -> present.
#pragma once
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "render/offscreen_target.h"
#include "doc/autosave.h"
#include "doc/document.h"
#include "doc/export_run.h"
#include "doc/job_process.h"
#include "doc/log_buffer.h"
#include "doc/recent_files.h"
#include "platform/platform.h"
#include "render/image.h"
#include "render/renderer.h"
#include "ui/injected_input.h"
#include "ui/keyframe_canvas.h"
#include "ui/kind_panels.h"
#include "ui/take_compare.h"
#include "ui/take_view.h"
#include "ui/ui_mark.h"

namespace pliant::editor {

struct AppOptions {
  std::filesystem::path scene;       // open at start ("" = new from the default scene)
  std::filesystem::path take;        // take to show at start
  std::filesystem::path pliant;      // `pliant` binary ("" = beside this executable)
  std::filesystem::path config_dir;  // "" = config_dir()
  int width = 1600, height = 900;
  double fixed_dt_s = 0;             // headless: 1/60 for determinism
  double autosave_s = 0;             // 0 = $PLIANT_AUTOSAVE_S or 30
  int job_threads = 0;
  bool check_recovery = true;
  bool viewport_only = false;        // screenshots show only the viewport
};

struct ViewportState {
  OrbitCamera camera;
  ViewSettings settings;
  OffscreenTarget target;
  std::string shown_dir;  // what the renderer holds now
  int shown_frame = -1, shown_count = -1;
  size_t shown_records = 0;   // record count when a preview was uploaded
  bool showing_preview = false;
  std::string preview_label;  // "preview 16x16, 3 of 5" while one is shown
  bool show_canvas = false;   // smoke 2D: the keyframe canvas instead of the result
  bool show_outlines = true;  // keyframe outlines over the result at keyframe frames
  uint64_t uploads = 0;             // bumped whenever the renderer's frame changes
  std::vector<float> drawn_state;   // what the FBO holds: redraw only when it changes
};

struct PanelVisibility {
  bool inspector = true, viewport = true, jobs = true, timeline = true, log = true;
};

// The path-entry popup that stands in for native file dialogs.
struct FileDialog {
  enum class Mode { None, Open, SaveAs, OpenTake, ExportPng, ExportMp4, ExportVdb, ExportParticles, ExportObj, ExportCsv, ImportImage } mode = Mode::None;
  bool open_requested = false;
  char path[1024] = {};
  std::string error;
};

class App {
 public:
  explicit App(AppOptions opt);
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  // Creates the ImGui context, initializes the platform, GL backend and
  // renderer, opens the start scene/take and looks for a crash to recover.
  bool init(std::unique_ptr<Platform> platform, std::string* err);
  void frame();
  // clean: removes the session lock and autosave (an unclean exit keeps them).
  // A window closed with unsaved edits keeps them too, for the recovery prompt.
  void shutdown(bool clean = true);
  bool should_quit() const;
  void request_quit() { quit_requested_ = true; }

  // Commands (menus, hotkeys and scripts call these). false + log on failure.
  void cmd_new();
  bool cmd_open(const std::filesystem::path& path);
  bool cmd_save();
  bool cmd_save_as(const std::filesystem::path& path);
  bool cmd_open_take(const std::filesystem::path& dir);
  void cmd_undo();
  void cmd_redo();
  // Starts `pliant run` on the document; take_dir "" = default_take_dir().
  bool cmd_run(const std::filesystem::path& take_dir = {}, bool resume = false);
  // Continues the newest job's take from its last checkpoint (`pliant run --resume`).
  bool cmd_resume();
  // Exports the shown take: "png" (plugin, or the viewport's rendering for kind-drawer
  // takes), "mp4" (PNGs then ffmpeg), "vdb", "particles" (PLY per frame), "obj" (plugins).
  bool cmd_export(const std::string& format, const std::filesystem::path& out);
  void poll_export();  // logs the end of an export once
  // Every frame of the shown take rendered by the viewport (camera, settings,
  // size) into DIR/frame_%05d.png; used by cmd_export for kind-drawer takes.
  bool export_rendered_frames(const std::filesystem::path& dir, std::string* err);
  void cmd_cancel(size_t job);
  void open_file_dialog(FileDialog::Mode mode);
  void handle_drops(const std::vector<std::string>& paths);
  void recover(bool accept);  // answer to the recovery prompt

  // Screenshots of the last rendered frame (call from the after-render hook).
  Image capture_window() const;
  Image capture_viewport() const;

  Platform& platform() { return *platform_; }
  bool has_gl() const { return gl_; }
  const AppOptions& options() const { return opt_; }
  // The validation error of the current scene ("" when valid); cached per revision.
  const std::string& scene_error();
  // The status line; errors show in red until the next status.
  void set_status(const std::string& s, bool error = false) {
    status_ = s;
    status_error_ = error;
  }
  const std::string& status() const { return status_; }
  bool status_is_error() const { return status_error_; }
  int job_threads = 0;  // --threads for new jobs (0 = OpenMP default)
  JobProcess* newest_job() { return jobs.empty() ? nullptr : jobs.back().get(); }
  // Numbers a job a kind panel starts itself (compare runs), in the same series as Run.
  int next_job_id() { return ++job_counter_; }
  uint64_t frame_count() const { return frames_; }

  Document doc;
  LogBuffer log;
  RecentFiles recent;
  std::unique_ptr<Autosave> autosave;
  std::optional<RecoveryCandidate> recovery;  // shown as a modal while set
  std::vector<std::unique_ptr<JobProcess>> jobs;
  std::vector<JobState> job_seen_state;  // to log state changes once
  TakeView take;
  ViewportState viewport;
  PanelVisibility panels;
  FileDialog file_dialog;
  UiMarks marks;
  InjectedInput input;
  Renderer renderer;
  KeyframeCanvasState canvas;  // smoke keyframe painting (keyframe_canvas.h)
  TakeCompare compare;         // A/B: a second take beside the shown one
  KindUiStates kind_ui;        // per-kind UI state (ui/kind_panels.h)
  std::unique_ptr<ExportRun> export_run;  // the newest export (app_export.cpp)
  // Scripts hook here: before_frame runs after platform.new_frame (to inject
  // input), after_render after the frame is drawn (screenshots).
  std::function<void(App&)> before_frame, after_render;

 private:
  void poll_jobs();
  void handle_hotkeys();
  void draw_layout();
  void update_title();

  AppOptions opt_;
  std::unique_ptr<Platform> platform_;
  bool gl_ = false, imgui_owned_ = false, gl_backend_ = false, renderer_ok_ = false;
  bool quit_requested_ = false, shut_down_ = false, status_error_ = false;
  std::string status_;
  std::string scene_error_;
  uint64_t scene_error_revision_ = ~uint64_t(0);
  std::string last_title_;
  uint64_t frames_ = 0;
  int job_counter_ = 0;
  bool export_reported_ = true;
};

}  // namespace pliant::editor
