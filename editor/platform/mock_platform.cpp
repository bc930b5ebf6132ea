// A platform with no window and no GL: for UI-logic tests that need no pixels.
#include <utility>

#include "platform/imgui_headless_io.h"
#include "platform/platform.h"

namespace pliant::editor {
namespace {

class MockPlatform final : public Platform {
 public:
  bool init(const PlatformOptions& opt, std::string* err) override {
    if (opt.width <= 0 || opt.height <= 0) {
      if (err) *err = "mock platform: framebuffer size must be positive, got " +
                      std::to_string(opt.width) + "x" + std::to_string(opt.height);
      return false;
    }
    opt_ = opt;
    return true;
  }
  void new_frame() override { clock_.new_frame(opt_.width, opt_.height, opt_.fixed_dt_s); }
  void present() override {}
  bool should_close() const override { return close_; }
  void request_close() override { close_ = true; }
  void framebuffer_size(int* w, int* h) const override {
    *w = opt_.width;
    *h = opt_.height;
  }
  unsigned default_framebuffer() const override { return 0; }
  std::vector<std::string> take_dropped_files() override { return std::exchange(drops_, {}); }
  void inject_drop(const std::vector<std::string>& paths) override {
    drops_.insert(drops_.end(), paths.begin(), paths.end());
  }
  void set_title(const std::string& title) override { opt_.title = title; }
  bool headless() const override { return true; }
  bool has_gl() const override { return false; }
  std::string gl_description() const override { return "none (mock platform)"; }
  void shutdown() override {}

 private:
  PlatformOptions opt_;
  HeadlessImGuiClock clock_;
  std::vector<std::string> drops_;
  bool close_ = false;
};

}  // namespace

std::unique_ptr<Platform> make_mock_platform() { return std::make_unique<MockPlatform>(); }

}  // namespace pliant::editor
