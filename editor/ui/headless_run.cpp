#include "ui/headless_run.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "render/screenshot.h"
#include "ui/ui_script.h"

namespace pliant::editor {

namespace fs = std::filesystem;

std::string run_job_headless(App& app, const fs::path& take_dir) {
  if (!app.cmd_run(take_dir)) return app.status();
  JobProcess* job = app.newest_job();
  // The UI keeps drawing (frames arrive in the viewport as the job writes
  // them), at about 60 Hz so the editor does not compete with the job for CPU.
  while (!job->snapshot().ended()) {
    app.frame();
    std::this_thread::sleep_for(std::chrono::milliseconds(16));
  }
  app.frame();  // pick up the last frames and the final status
  const JobStatus st = job->snapshot();
  if (st.state != JobState::Done) {
    return std::string("job ") + job_state_name(st.state) + ": " +
           (st.error.empty() ? st.last_message : st.error);
  }
  return "";
}

std::string render_take_frames(App& app, const fs::path& out_dir, int* written) {
  *written = 0;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) return out_dir.string() + ": cannot create folder: " + ec.message();
  app.frame();  // refresh the take view
  const int n = app.take.frame_count();
  if (n == 0) return "render: the take has no frames";
  std::string err;
  for (int i = 0; i < n && err.empty(); ++i) {
    app.take.playing = false;
    app.take.set_frame(i);
    app.after_render = [&](App& a) {
      Image img = a.capture_viewport();
      if (img.empty()) {
        err = "render: nothing to capture";
        return;
      }
      char name[32];
      std::snprintf(name, sizeof name, "frame_%05d.png", i);
      if (!write_png((out_dir / name).string(), img, &err)) return;
      ++*written;
    };
    app.frame();
  }
  app.after_render = nullptr;
  return err;
}

std::string run_headless(App& app, const HeadlessRunOptions& opt) {
  if (opt.run) {
    if (std::string e = run_job_headless(app, opt.run_take); !e.empty()) return e;
  }
  if (!opt.render_frames.empty()) {
    int written = 0;
    if (std::string e = render_take_frames(app, opt.render_frames, &written); !e.empty()) return e;
  }
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
