// Jobs through the UI with real `pliant run` children and EGL rendering:
// run + scrub + golden viewport screenshot, cancel, and the binary's own
// script-error exit.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sys/wait.h>

#include "editor_harness.h"
#include "pliant/core/take.h"
#include "render/image_compare.h"
#include "render/screenshot.h"

namespace pliant::editor::test {

TEST(EditorJobs, RunScrubAndViewportMatchesGolden) {
  EditorHarness h("golden");
  fs::path scene = h.copy_scene("small_plume.json");
  h.start(scene, /*gl=*/true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\n"
                  "click_item Run\n"
                  "wait_job 60\n"
                  "expect \"Job 1: done\"\n"
                  "wait_frames 41 10\n"
                  "set_frame 30\n"
                  "wait 2\n"
                  "screenshot $TMP/viewport.png viewport\n"
                  "screenshot $TMP/window.png\n"),
            "");
  EXPECT_EQ(h.app->take.frame, 30);
  EXPECT_TRUE(h.app->take.user_scrubbed);
  EXPECT_EQ(h.app->take.status(), "done");
  JobStatus st = h.app->newest_job()->snapshot();
  EXPECT_EQ(st.state, JobState::Done);
  EXPECT_EQ(st.exit_code, 0);
  // Timeline hotkeys: Left/Right step, Space plays (25 fps at a fixed 1/60 s).
  ASSERT_EQ(h.run("key LEFT\nwait 1\nkey LEFT\nwait 1\nkey RIGHT\nwait 1\n"), "");
  EXPECT_EQ(h.app->take.frame, 29);
  ASSERT_EQ(h.run("key SPACE\nwait 24\nkey SPACE\nwait 1\n"), "");
  EXPECT_FALSE(h.app->take.playing);
  EXPECT_GE(h.app->take.frame, 29 + 9);  // ~26 frames of 1/60 s at 25 fps = ~10.8
  EXPECT_LE(h.app->take.frame, 29 + 12);
  // The take lives beside the scene.
  EXPECT_EQ(h.app->take.dir().parent_path(), fs::path(scene.string() + ".takes"));

  std::string err;
  Image shot = read_png((h.dir / "viewport.png").string(), &err);
  ASSERT_FALSE(shot.empty()) << err;
  // Smoke is visible: some pixels are much brighter than the background.
  int bright = 0;
  for (int y = 0; y < shot.height; ++y)
    for (int x = 0; x < shot.width; ++x)
      if (shot.pixel(x, y)[0] > 150) ++bright;
  EXPECT_GT(bright, 500);

  fs::path golden = test_data("golden/run_and_scrub_viewport.png");
  if (std::getenv("PLIANT_UPDATE_GOLDEN")) {
    ASSERT_TRUE(write_png(golden.string(), shot, &err)) << err;
    fs::copy_file(h.dir / "window.png", test_data("golden/run_and_scrub_window.png"),
                  fs::copy_options::overwrite_existing);
  }
  Image want = read_png(golden.string(), &err);
  ASSERT_FALSE(want.empty()) << err << " (generate with PLIANT_UPDATE_GOLDEN=1)";
  CompareResult c = compare(shot, want, /*max_tol=*/48, /*mean_tol=*/1.0);
  if (!c.pass && !c.size_mismatch) {
    fs::path diff = fs::temp_directory_path() / "pliant_editor_golden_diff.png";
    write_png(diff.string(), diff_image(shot, want, 48));
    ADD_FAILURE() << c.message << "; diff image: " << diff;
  }
  EXPECT_FALSE(c.size_mismatch) << c.message;
}

TEST(EditorJobs, CancelLeavesACancelledTakeAndTheUiKeepsRendering) {
  EditorHarness h("cancel");
  fs::path scene = h.copy_scene("long_plume.json");
  h.start(scene, true, 1280, 720);
  ASSERT_EQ(h.run("wait 2\nkey F5\nwait_frames 3 60\nclick_item Cancel\n"
                  "wait_job 30\nexpect \"Job 1: cancelled\"\n"),
            "");
  JobStatus st = h.app->newest_job()->snapshot();
  EXPECT_EQ(st.state, JobState::Cancelled);
  EXPECT_EQ(st.exit_code, 3);
  TakeReader take(h.app->take.dir());
  EXPECT_EQ(take.manifest().status, "cancelled");
  EXPECT_GE(take.frame_count(), 3u);
  EXPECT_LT(take.frame_count(), 5000u);
  EXPECT_FALSE(take.torn_tail());
  // Still responsive: frames keep coming, quickly, and the last frame is shown.
  uint64_t before = h.app->frame_count();
  auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(h.run("wait 20\nclick_item prev_frame\nwait 2\n"), "");
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GE(h.app->frame_count(), before + 20);
  EXPECT_LT(s, 10.0);
  EXPECT_EQ(h.app->take.frame, static_cast<int>(take.frame_count()) - 2);
  EXPECT_EQ(h.app->take.status(), "cancelled");

  // Dropping the take folder on the window opens it again (from frame 0).
  fs::path take_dir = h.app->take.dir();
  h.app->cmd_new();
  EXPECT_TRUE(h.app->take.dir().empty());
  ASSERT_EQ(h.run("drop " + take_dir.string() + "\nwait 2\nexpect \"Opened take\"\n"), "");
  EXPECT_EQ(h.app->take.dir(), take_dir);
  EXPECT_EQ(h.app->take.frame_count(), static_cast<int>(take.frame_count()));
  EXPECT_EQ(h.app->take.frame, 0);
}

TEST(EditorJobs, BinaryReportsScriptErrorsWithTheLine) {
  EditorHarness h("cli");
  fs::path scene = h.copy_scene("small_plume.json");
  fs::path script = h.dir / "bad.txt";
  std::ofstream(script) << "wait 1\nclick_item\n";
  std::string cmd = std::string(PLIANT_EDITOR_BIN) + " --headless --size 640x400 --script " +
                    script.string() + " " + scene.string() + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  char buf[512];
  while (size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  int st = ::pclose(p);
  EXPECT_NE(WEXITSTATUS(st), 0);
  EXPECT_NE(out.find("bad.txt:2: click_item: expected 1 to 2 arguments, got 0"), std::string::npos)
      << out;

  // And a good headless run writes its screenshot and exits 0.
  fs::path png = h.dir / "shot.png";
  cmd = std::string(PLIANT_EDITOR_BIN) + " --headless --size 800x600 --frames 3 --screenshot " +
        png.string() + " " + scene.string() + " 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  std::string err;
  Image img = read_png(png.string(), &err);
  EXPECT_EQ(img.width, 800) << err;
  EXPECT_EQ(img.height, 600);

  // --viewport-only writes just the viewport panel's image: smaller than the window.
  cmd = std::string(PLIANT_EDITOR_BIN) + " --headless --size 800x600 --viewport-only --screenshot " +
        png.string() + " " + scene.string() + " 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  img = read_png(png.string(), &err);
  ASSERT_FALSE(img.empty()) << err;
  EXPECT_LT(img.width, 800);
  EXPECT_LT(img.height, 600);
  EXPECT_GT(img.width, 100);
}

}  // namespace pliant::editor::test
