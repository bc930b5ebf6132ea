// Test harness: an App in a fresh temp folder (its own config dir), driven by
// inline UI scripts through the same run_headless() the binary uses.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "render/image_compare.h"
#include "render/screenshot.h"
#include "ui/app.h"
#include "ui/headless_run.h"

namespace pliant::editor::test {

namespace fs = std::filesystem;

inline fs::path test_data(const std::string& rel) { return fs::path(PLIANT_EDITOR_TEST_DIR) / rel; }

// Compares an image with tests/editor/golden/NAME (per-pixel tolerance 48, mean
// 1.0: llvmpipe's rounding); PLIANT_UPDATE_GOLDEN=1 rewrites the golden. A
// failure writes the difference image to the temp folder and names it.
inline void match_golden_image(const Image& shot, const std::string& golden_name) {
  std::string err;
  fs::path golden = test_data("golden/" + golden_name);
  if (std::getenv("PLIANT_UPDATE_GOLDEN")) {
    ASSERT_TRUE(write_png(golden.string(), shot, &err)) << err;
  }
  Image want = read_png(golden.string(), &err);
  ASSERT_FALSE(want.empty()) << err << " (generate with PLIANT_UPDATE_GOLDEN=1)";
  CompareResult c = compare(shot, want, /*max_tol=*/48, /*mean_tol=*/1.0);
  if (!c.pass) {
    fs::path diff = fs::temp_directory_path() / ("pliant_diff_" + golden_name);
    write_png(diff.string(), diff_image(shot, want, 48));
    ADD_FAILURE() << golden_name << ": " << c.message << "; diff image: " << diff;
  }
}

// The same for a screenshot file.
inline void match_golden(const fs::path& shot_file, const std::string& golden_name) {
  std::string err;
  Image shot = read_png(shot_file.string(), &err);
  ASSERT_FALSE(shot.empty()) << err;
  match_golden_image(shot, golden_name);
}

class EditorHarness {
 public:
  explicit EditorHarness(const std::string& name) {
    dir = fs::temp_directory_path() /
          ("pliant-editor-test-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "config");
    ::setenv("PLIANT_CONFIG_DIR", (dir / "config").c_str(), 1);
  }
  ~EditorHarness() {
    if (app) app->shutdown(true);
    app.reset();
    std::error_code ec;
    if (!::getenv("PLIANT_KEEP_TEST_DIRS")) fs::remove_all(dir, ec);
  }

  // Copies a scene from tests/editor/scenes into the temp folder; returns its path.
  fs::path copy_scene(const std::string& name) {
    fs::path to = dir / name;
    fs::copy_file(test_data("scenes/" + name), to, fs::copy_options::overwrite_existing);
    return to;
  }

  // gl=false uses the mock platform (no pixels, faster).
  void start(const fs::path& scene, bool gl, int w = 1280, int h = 720, double autosave_s = 0) {
    AppOptions o;
    o.scene = scene;
    o.pliant = pliant;
    o.config_dir = dir / "config";
    o.width = w;
    o.height = h;
    o.fixed_dt_s = 1.0 / 60.0;
    o.autosave_s = autosave_s;
    o.job_threads = 1;  // OpenMP spin-waits badly on a loaded 2-core CI box
    app = std::make_unique<App>(o);
    std::string err;
    bool ok = app->init(gl ? make_egl_platform() : make_mock_platform(), &err);
    ASSERT_TRUE(ok) << err;
  }

  // Runs script text; returns "" or the runner's error.
  std::string run(const std::string& script_text, const std::string& name = "script.txt") {
    fs::path file = dir / name;
    std::ofstream(file) << script_text;
    HeadlessRunOptions h;
    h.script = file;
    h.tmp_dir = dir;
    h.max_frames = 20000;
    return run_headless(*app, h);
  }

  fs::path dir;
  fs::path pliant = PLIANT_BIN;  // the job binary (tests may substitute a fake)
  std::unique_ptr<App> app;
};

}  // namespace pliant::editor::test
