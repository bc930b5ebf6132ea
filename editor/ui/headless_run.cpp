#include "ui/headless_run.h"

#include <unistd.h>

#include "render/screenshot.h"
#include "ui/ui_script.h"

namespace pliant::editor {

namespace fs = std::filesystem;

std::string run_headless(App& app, const HeadlessRunOptions& opt) {
  std::unique_ptr<ScriptRunner> runner;
  fs::path tmp;
  if (!opt.script.empty()) {
    Script s;
    try {
      s = load_script(opt.script);
    } catch (const ScriptError& e) {
      return e.what();
    }
    fs::path script_tmp = opt.tmp_dir;
    if (script_tmp.empty()) {
      tmp = fs::temp_directory_path() / ("pliant-editor-" + std::to_string(::getpid()));
      script_tmp = tmp;
    }
    std::error_code ec;
    fs::create_directories(script_tmp, ec);
    runner = std::make_unique<ScriptRunner>(std::move(s), script_tmp);
    runner->attach(app);
  }
  std::string err;
  int frames = 0;
  for (;;) {
    app.frame();
    ++frames;
    if (runner) {
      if (runner->failed()) {
        err = runner->error();
        break;
      }
      if (runner->finished()) break;
    } else if (frames >= opt.frames) {
      break;
    }
    if (app.should_quit()) break;
    if (frames >= opt.max_frames) {
      err = "stopped after " + std::to_string(frames) + " frames";
      break;
    }
  }
  if (err.empty() && !opt.screenshot.empty()) {
    // One more frame so the final state is what the screenshot shows.
    app.before_frame = nullptr;
    app.after_render = [&](App& a) {
      Image img = opt.viewport_only ? a.capture_viewport() : a.capture_window();
      if (img.empty()) {
        err = "screenshot: nothing to capture";
        return;
      }
      std::error_code ec;
      if (opt.screenshot.has_parent_path()) fs::create_directories(opt.screenshot.parent_path(), ec);
      std::string werr;
      if (!write_png(opt.screenshot.string(), img, &werr)) err = werr;
    };
    app.frame();
  }
  app.before_frame = nullptr;
  app.after_render = nullptr;
  if (!tmp.empty()) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
  }
  return err;
}

}  // namespace pliant::editor
