// The renderer in a real GLFW window (under Xvfb in CI). Exits 77 (ctest
// SKIP_RETURN_CODE) when there is no display, so machines without X skip it.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <memory>

#include "golden.h"
#include "render_test_util.h"
#include "synthetic_frames.h"

namespace pliant::test {
namespace {

TEST(GlfwRender, WindowRendersTheSameBlobAsEgl) {
  auto platform = editor::make_glfw_platform();
  editor::PlatformOptions opt;
  opt.width = kWidth;
  opt.height = kHeight;
  opt.vsync = false;
  opt.title = "pliant render test";
  std::string err;
  ASSERT_TRUE(platform->init(opt, &err)) << err;
  EXPECT_FALSE(platform->headless());
  EXPECT_EQ(platform->default_framebuffer(), 0u);
  int w = 0, h = 0;
  platform->framebuffer_size(&w, &h);
  ASSERT_EQ(w, kWidth);
  ASSERT_EQ(h, kHeight);
  platform->inject_drop({"/tmp/x.json"});
  EXPECT_EQ(platform->take_dropped_files().size(), 1u);
  {
    editor::Renderer renderer;
    ASSERT_TRUE(renderer.init(&err)) << err;
    const auto img = render_frame(*platform, renderer, frame_of({gaussian_blob_2d(64, 48, 40, 30, 6.0f)}), {},
                                  golden_view());
    // The EGL golden; a window may use another driver, so allow a little more.
    if (!updating_goldens()) {
      EXPECT_TRUE(matches_golden(img, golden_path("blob2d"), diff_path("glfw_blob2d"), 24, 2.0));
    }
    renderer.shutdown();
  }
  platform->present();
  platform->shutdown();
}

}  // namespace
}  // namespace pliant::test

int main(int argc, char** argv) {
  const char* display = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((display == nullptr || *display == '\0') && (wayland == nullptr || *wayland == '\0')) {
    std::printf("no DISPLAY or WAYLAND_DISPLAY: skipping the GLFW render test\n");
    return 77;
  }
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
