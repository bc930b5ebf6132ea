// bench_editor: the editor's responsiveness during keyframe control (issue 4).
//
// For each case a headless editor (EGL, the same renderer and ImGui frame as the
// window) opens a scene, presses Solve and then draws UI frames flat out (no
// vsync, no sleeps) while the `pliant run` child solves with one thread:
//   first_preview_s      Solve pressed -> the viewport shows the first preview
//                        (or frame) of the take
//   ui_fps_while_solving UI frames per second between Solve and the end of the
//                        measuring window (quick 15 s, full 60 s) or of the job
//   ui_fps_idle          baseline in the same run: the same window, no job (3 s)
//   frame_ms_p95/max     frame times over that window (hitches when records land)
// Targets (issue 4): ui_fps_while_solving > 30, first_preview_s < 5 at 128^2 x 40.
// The job is cancelled at the end of the window. One JSON object per case on
// stdout; the array goes to bench/results/editor.json (--out FILE).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

#include "platform/platform.h"
#include "ui/app.h"
#include "../bench_machine.h"

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {


std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

struct Case {
  std::string name, scene;  // scene relative to assets/scenes
  int resolution = 0;       // overrides grid.resolution when > 0 (square)
  std::string method;       // overrides control.method when set
};

json run_case(const Case& c, double window_s, const fs::path& work) {
  using namespace pliant::editor;
  fs::path dir = work / c.name;
  fs::remove_all(dir);
  fs::create_directories(dir / "config");
  json scene = json::parse(std::ifstream(fs::path(PLIANT_SOURCE_DIR) / "assets/scenes" / c.scene));
  if (c.resolution > 0) {
    // Same domain, finer cells.
    const double extent = scene["grid"]["resolution"][0].get<double>() * scene["grid"]["cell_size_m"].get<double>();
    scene["grid"]["resolution"] = {c.resolution, c.resolution};
    scene["grid"]["cell_size_m"] = extent / c.resolution;
  }
  if (!c.method.empty()) scene["control"]["method"] = c.method;
  fs::path scene_file = dir / "scene.json";
  std::ofstream(scene_file) << scene.dump(2);
  // Relative assets (fonts) resolve from the scene's folder: the shipped font is
  // found through the source tree by the engine.

  AppOptions o;
  o.scene = scene_file;
  o.pliant = PLIANT_BIN;
  o.config_dir = dir / "config";
  o.width = 1600;
  o.height = 900;
  o.job_threads = 1;
  o.check_recovery = false;
  App app(o);
  std::string err;
  if (!app.init(make_egl_platform(), &err)) throw std::runtime_error("editor init: " + err);
  for (int i = 0; i < 3; ++i) app.frame();
  // Baseline in the same run: the same window with no job (3 s).
  int idle_frames = 0;
  const auto ti = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - ti).count() < 3.0) {
    app.frame();
    ++idle_frames;
  }
  const double idle_fps = idle_frames / std::chrono::duration<double>(Clock::now() - ti).count();

  const auto t0 = Clock::now();
  if (!app.cmd_run()) throw std::runtime_error("cannot start the solve: " + app.status());
  double first_preview = -1;
  std::vector<double> frame_ms;
  auto last = Clock::now();
  bool ended = false;
  while (true) {
    app.frame();
    const auto now = Clock::now();
    frame_ms.push_back(std::chrono::duration<double, std::milli>(now - last).count());
    last = now;
    const double t = std::chrono::duration<double>(now - t0).count();
    if (first_preview < 0 && (app.viewport.showing_preview || app.renderer.has_frame())) first_preview = t;
    JobStatus st = app.newest_job()->snapshot();
    if (st.ended()) {
      ended = true;
      if (st.state == JobState::Failed) throw std::runtime_error("solve failed: " + st.error);
      break;
    }
    if (t >= window_s) break;
  }
  const double elapsed = std::chrono::duration<double>(last - t0).count();
  JobStatus st = app.newest_job()->snapshot();
  std::vector<double> sorted = frame_ms;
  std::sort(sorted.begin(), sorted.end());
  const double p95 = sorted.empty() ? 0 : sorted[size_t(0.95 * (sorted.size() - 1))];
  json j = {{"case", c.name},
            {"first_preview_s", first_preview},
            {"ui_fps_while_solving", frame_ms.size() / elapsed},
            {"ui_fps_idle", idle_fps},
            {"fps_ratio_solving_vs_idle", frame_ms.size() / elapsed / idle_fps},
            {"frame_ms_p95", p95},
            {"frame_ms_max", sorted.empty() ? 0 : sorted.back()},
            {"ui_frames", frame_ms.size()},
            {"window_s", elapsed},
            {"solve_ended_in_window", ended},
            {"solver_iterations_seen", st.iter},
            {"solver_stage", st.stage},
            {"job_threads", 1},
            {"viewport", "1600x900 window, Mesa/EGL " + app.platform().gl_description()},
            {"method", scene["control"].value("method", "admm")},
            {"machine", pliant::bench::machine_description()}};
  if (!ended) app.cmd_cancel(app.jobs.size() - 1);
  app.shutdown(true);
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string out = std::string(PLIANT_SOURCE_DIR) + "/bench/results/editor.json";
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else {
      std::fprintf(stderr, "usage: bench_editor [--quick] [--out FILE]\n");
      return 2;
    }
  }
  const double window = quick ? 15.0 : 60.0;
  const std::vector<Case> cases = {
      {"fluid_letters_128x40_admm", "smoke_fluid_letters.json", 0, ""},
      {"circle_to_letter_128x40_lbfgs", "smoke_circle_to_letter.json", 128, "lbfgs"},
  };
  fs::path work = fs::temp_directory_path() / ("pliant-bench-editor-" + std::to_string(::getpid()));
  json results = json::array();
  int rc = 0;
  for (const auto& c : cases) {
    const std::string load = load_average();
    try {
      json j = run_case(c, window, work);
      j["load_average_at_start"] = load;
      j["mode"] = quick ? "quick" : "full";
      std::cout << j.dump() << std::endl;
      results.push_back(j);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_editor: %s: %s\n", c.name.c_str(), e.what());
      rc = 1;
    }
  }
  fs::remove_all(work);
  std::ofstream(out) << results.dump(2) << "\n";
  return rc;
}
