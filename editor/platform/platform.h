// The editor's window system behind one small interface (Polyscope style):
// a GLFW window, an EGL headless context (llvmpipe works), and a mock with no
// GL at all for UI-logic tests. All create an OpenGL 3.3+ core context (except
// the mock) and own ImGui's platform side (display size, delta time, input).
#pragma once
#include <memory>
#include <string>
#include <vector>

namespace pliant::editor {

struct PlatformOptions {
  int width = 1600, height = 900;
  std::string title = "Pliant";
  bool vsync = true;
  double fixed_dt_s = 0;  // >0: ImGui DeltaTime is this constant (deterministic headless runs)
};

class Platform {
 public:
  virtual ~Platform() = default;
  // Creates the window/context; false with *err set on failure.
  virtual bool init(const PlatformOptions& opt, std::string* err) = 0;
  // Polls events and starts ImGui's platform frame (io.DisplaySize, DeltaTime,
  // inputs). Call before ImGui::NewFrame().
  virtual void new_frame() = 0;
  // Shows the frame (swap buffers; nothing for headless).
  virtual void present() = 0;
  virtual bool should_close() const = 0;
  virtual void request_close() = 0;
  virtual void framebuffer_size(int* w, int* h) const = 0;
  // The framebuffer the UI draws into: 0 for a window, an FBO for headless.
  virtual unsigned default_framebuffer() const = 0;
  // Files dropped on the window since the last call.
  virtual std::vector<std::string> take_dropped_files() = 0;
  // Headless platforms can be sent drops by UI scripts.
  virtual void inject_drop(const std::vector<std::string>& paths) {}
  virtual void set_title(const std::string& title) {}
  virtual bool headless() const = 0;
  virtual bool has_gl() const { return true; }
  virtual std::string gl_description() const { return ""; }  // GL_RENDERER/VERSION
  virtual void shutdown() = 0;
};

std::unique_ptr<Platform> make_glfw_platform();
std::unique_ptr<Platform> make_egl_platform();
std::unique_ptr<Platform> make_mock_platform();

}  // namespace pliant::editor
