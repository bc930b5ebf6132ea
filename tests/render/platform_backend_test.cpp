// The same platform tests against every backend that can run here (Polyscope
// style): the mock (no GL) and EGL headless. GLFW runs in render_glfw_test.
#include <gtest/gtest.h>
#include <imgui.h>

#include <cstdlib>
#include <memory>

#include "platform/platform.h"

namespace pliant::test {
namespace {
using editor::Platform;
using editor::PlatformOptions;

std::unique_ptr<Platform> make_backend(const std::string& name) {
  if (name == "egl") return editor::make_egl_platform();
  return editor::make_mock_platform();
}

class PlatformBackend : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    platform_ = make_backend(GetParam());
    PlatformOptions opt;
    opt.width = 200;
    opt.height = 120;
    opt.fixed_dt_s = 0.25;
    std::string err;
    ASSERT_TRUE(platform_->init(opt, &err)) << GetParam() << ": " << err;
    ctx_ = ImGui::CreateContext();
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    ImGui::GetIO().Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);  // NewFrame needs a built atlas
  }
  void TearDown() override {
    if (ctx_) ImGui::DestroyContext(ctx_);
    if (platform_) platform_->shutdown();
  }
  std::unique_ptr<Platform> platform_;
  ImGuiContext* ctx_ = nullptr;
};

TEST_P(PlatformBackend, ReportsSizeAndKind) {
  int w = 0, h = 0;
  platform_->framebuffer_size(&w, &h);
  EXPECT_EQ(w, 200);
  EXPECT_EQ(h, 120);
  EXPECT_TRUE(platform_->headless());
  EXPECT_EQ(platform_->has_gl(), GetParam() != "mock");
  EXPECT_FALSE(platform_->should_close());
  platform_->request_close();
  EXPECT_TRUE(platform_->should_close());
  if (platform_->has_gl()) {
    EXPECT_NE(platform_->default_framebuffer(), 0u);  // headless draws into an FBO
    EXPECT_NE(platform_->gl_description().find("OpenGL"), std::string::npos) << platform_->gl_description();
    const char* forced = std::getenv("PLIANT_EGL_PLATFORM");
    if (GetParam() == "egl" && forced && std::string(forced) == "surfaceless") {
      EXPECT_NE(platform_->gl_description().find("SURFACELESS"), std::string::npos) << platform_->gl_description();
    }
  }
}

TEST_P(PlatformBackend, NewFrameSetsDisplayAndFixedDeltaButNotInput) {
  ImGuiIO& io = ImGui::GetIO();
  io.MousePos = ImVec2(12, 34);
  io.MouseDown[0] = true;
  platform_->new_frame();
  EXPECT_FLOAT_EQ(io.DisplaySize.x, 200.0f);
  EXPECT_FLOAT_EQ(io.DisplaySize.y, 120.0f);
  EXPECT_FLOAT_EQ(io.DisplayFramebufferScale.x, 1.0f);
  EXPECT_FLOAT_EQ(io.DeltaTime, 0.25f);
  EXPECT_FLOAT_EQ(io.MousePos.x, 12.0f);
  EXPECT_FLOAT_EQ(io.MousePos.y, 34.0f);
  EXPECT_TRUE(io.MouseDown[0]);
}

// A scripted click (mouse move, press, release injected into ImGuiIO) reaches a button.
TEST_P(PlatformBackend, InjectedClickPressesButton) {
  ImGuiIO& io = ImGui::GetIO();
  bool clicked = false;
  ImVec2 button_centre;
  auto frame = [&](ImVec2 mouse, bool down) {
    io.MousePos = mouse;
    io.MouseDown[0] = down;
    platform_->new_frame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(200, 120));
    ImGui::Begin("test", nullptr, ImGuiWindowFlags_NoDecoration);
    clicked |= ImGui::Button("Press me", ImVec2(80, 30));
    button_centre = ImVec2((ImGui::GetItemRectMin().x + ImGui::GetItemRectMax().x) / 2,
                           (ImGui::GetItemRectMin().y + ImGui::GetItemRectMax().y) / 2);
    ImGui::End();
    ImGui::Render();
    platform_->present();
  };
  frame(ImVec2(-1000, -1000), false);
  EXPECT_FALSE(clicked);
  frame(button_centre, false);
  frame(button_centre, true);
  frame(button_centre, false);
  EXPECT_TRUE(clicked);
}

// Keys use GLFW's codes, as in a window: an injected Enter activates the
// keyboard-focused text field's "enter returns true" path.
TEST_P(PlatformBackend, InjectedEnterKeyReachesImGui) {
  ImGuiIO& io = ImGui::GetIO();
  platform_->new_frame();
  EXPECT_EQ(io.KeyMap[ImGuiKey_Enter], 257);  // GLFW_KEY_ENTER
  EXPECT_EQ(io.KeyMap[ImGuiKey_A], 'A');
  char text[32] = "abc";
  bool entered = false;
  for (int f = 0; f < 4; ++f) {
    io.KeysDown[io.KeyMap[ImGuiKey_Enter]] = (f == 2);
    platform_->new_frame();
    ImGui::NewFrame();
    ImGui::Begin("keys");
    if (f == 0) ImGui::SetKeyboardFocusHere();
    entered |= ImGui::InputText("field", text, sizeof text, ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::End();
    ImGui::Render();
  }
  EXPECT_TRUE(entered);
}

TEST_P(PlatformBackend, DropsAreQueuedAndTakenOnce) {
  EXPECT_TRUE(platform_->take_dropped_files().empty());
  platform_->inject_drop({"/tmp/a.json", "/tmp/b.png"});
  platform_->inject_drop({"/tmp/c.obj"});
  const auto drops = platform_->take_dropped_files();
  ASSERT_EQ(drops.size(), 3u);
  EXPECT_EQ(drops[0], "/tmp/a.json");
  EXPECT_EQ(drops[2], "/tmp/c.obj");
  EXPECT_TRUE(platform_->take_dropped_files().empty());
}

TEST_P(PlatformBackend, RejectsEmptyFramebuffer) {
  auto p = make_backend(GetParam());
  PlatformOptions opt;
  opt.width = 0;
  std::string err;
  EXPECT_FALSE(p->init(opt, &err));
  EXPECT_NE(err.find("positive"), std::string::npos) << err;
}

INSTANTIATE_TEST_SUITE_P(Backends, PlatformBackend, ::testing::Values("mock", "egl"),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace pliant::test
