// pliant-editor [SCENE] [--take DIR] [--headless] [--script FILE]
//               [--screenshot PNG] [--viewport-only] [--size WxH] [--frames N]
//               [--pliant PATH] [--run] [--render-frames DIR]
// Windowed by default (GLFW); --headless uses EGL with a fixed 1/60 s step,
// runs the UI script, writes the screenshot and exits (nonzero on failure).
// With --script or --screenshot a window does the same and then closes.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>

#include "ui/app.h"
#include "ui/headless_run.h"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

}  // namespace

int main(int argc, char** argv) {
  using namespace pliant::editor;
  CLI::App cli{"Pliant editor"};
  std::string scene, take, script, screenshot, size = "1600x900", pliant;
  std::string render_frames;
  bool headless = false, viewport_only = false, run = false;
  int frames = 2;
  cli.add_option("scene", scene, "scene file to open");
  cli.add_option("--take", take, "take folder to show");
  cli.add_flag("--headless", headless, "no window: EGL, fixed time step");
  cli.add_option("--script", script, "UI script to run (headless)");
  cli.add_option("--screenshot", screenshot, "PNG written at the end (headless)");
  cli.add_flag("--viewport-only", viewport_only, "screenshots show only the viewport");
  cli.add_option("--size", size, "window size WxH");
  cli.add_option("--frames", frames, "frames to render without a script (headless)");
  cli.add_option("--pliant", pliant, "the pliant binary that runs jobs");
  cli.add_flag("--run", run, "start the scene's job (into --take when given) and wait for it");
  cli.add_option("--render-frames", render_frames,
                 "render every frame of the take to DIR/frame_NNNNN.png (headless)");
  CLI11_PARSE(cli, argc, argv);

  AppOptions opt;
  if (std::sscanf(size.c_str(), "%dx%d", &opt.width, &opt.height) != 2 || opt.width < 200 ||
      opt.height < 150) {
    std::fprintf(stderr, "pliant-editor: --size: expected WxH (at least 200x150), got '%s'\n",
                 size.c_str());
    return 2;
  }
  opt.scene = scene;
  opt.take = run ? std::string() : take;  // with --run, --take names the new take
  opt.pliant = pliant;
  opt.viewport_only = viewport_only;
  if (headless) {
    opt.fixed_dt_s = 1.0 / 60.0;
    opt.check_recovery = !script.empty();  // a recovery prompt is only useful if something answers it
  }

  App app(opt);
  std::string err;
  if (!app.init(headless ? make_egl_platform() : make_glfw_platform(), &err)) {
    std::fprintf(stderr, "pliant-editor: %s\n", err.c_str());
    app.shutdown(true);
    return 1;
  }
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);

  int code = 0;
  // Scripts and screenshots also work in a window (same loop, real clock).
  if (headless || !script.empty() || !screenshot.empty() || run || !render_frames.empty()) {
    HeadlessRunOptions h;
    h.script = script;
    h.screenshot = screenshot;
    h.viewport_only = viewport_only;
    h.frames = std::max(1, frames);
    h.run = run;
    h.run_take = run ? take : std::string();
    h.render_frames = render_frames;
    err = run_headless(app, h);
    if (!err.empty()) {
      std::fprintf(stderr, "pliant-editor: %s\n", err.c_str());
      code = 1;
    }
  } else {
    while (!app.should_quit() && !g_stop) app.frame();
  }
  app.shutdown(true);
  return code;
}
