// A desktop window through GLFW 3.3 with an OpenGL 3.3 core, forward-compatible
// context. ImGui's GLFW backend feeds mouse and keyboard; dropped paths are
// collected for take_dropped_files().
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <GL/gl.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>

#include <string>
#include <utility>

#include "platform/platform.h"

namespace pliant::editor {
namespace {

std::string g_last_glfw_error;

void on_glfw_error(int code, const char* msg) {
  g_last_glfw_error = "GLFW error " + std::to_string(code) + ": " + (msg ? msg : "");
}

class GlfwPlatform final : public Platform {
 public:
  ~GlfwPlatform() override { shutdown(); }

  bool init(const PlatformOptions& opt, std::string* err) override {
    opt_ = opt;
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
      if (err) *err = "GLFW window platform: glfwInit failed (" + g_last_glfw_error +
                      "); is a display available (DISPLAY/WAYLAND_DISPLAY)?";
      return false;
    }
    glfw_inited_ = true;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DEPTH_BITS, 24);
    glfwWindowHint(GLFW_STENCIL_BITS, 8);
    window_ = glfwCreateWindow(opt.width, opt.height, opt.title.c_str(), nullptr, nullptr);
    if (window_ == nullptr) {
      if (err) *err = "GLFW window platform: could not create a " + std::to_string(opt.width) + "x" +
                      std::to_string(opt.height) + " window with an OpenGL 3.3 core context (" +
                      g_last_glfw_error + ")";
      shutdown();
      return false;
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(opt.vsync ? 1 : 0);
    glfwSetWindowUserPointer(window_, this);
    glfwSetDropCallback(window_, [](GLFWwindow* w, int n, const char** paths) {
      auto* self = static_cast<GlfwPlatform*>(glfwGetWindowUserPointer(w));
      for (int i = 0; i < n; ++i) self->drops_.emplace_back(paths[i]);
    });
    return true;
  }

  void new_frame() override {
    glfwPollEvents();
    // The ImGui context may be created after init(): hook the backend lazily.
    if (!imgui_backend_ && ImGui::GetCurrentContext() != nullptr) {
      // install_callbacks=true: ImGui takes mouse/key/char callbacks; drops stay ours.
      ImGui_ImplGlfw_InitForOpenGL(window_, true);
      imgui_backend_ = ImGui::GetCurrentContext();
    }
    if (imgui_backend_ != nullptr) ImGui_ImplGlfw_NewFrame();
  }
  void present() override { glfwSwapBuffers(window_); }
  bool should_close() const override { return window_ == nullptr || glfwWindowShouldClose(window_); }
  void request_close() override {
    if (window_) glfwSetWindowShouldClose(window_, GLFW_TRUE);
  }
  void framebuffer_size(int* w, int* h) const override {
    if (window_) {
      glfwGetFramebufferSize(window_, w, h);
    } else {
      *w = *h = 0;
    }
  }
  unsigned default_framebuffer() const override { return 0; }
  std::vector<std::string> take_dropped_files() override { return std::exchange(drops_, {}); }
  void inject_drop(const std::vector<std::string>& paths) override {
    drops_.insert(drops_.end(), paths.begin(), paths.end());
  }
  void set_title(const std::string& title) override {
    if (window_) glfwSetWindowTitle(window_, title.c_str());
  }
  bool headless() const override { return false; }
  std::string gl_description() const override {
    if (window_ == nullptr) return "";
    auto str = [](GLenum e) {
      const GLubyte* s = glGetString(e);
      return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    return str(GL_RENDERER) + ", OpenGL " + str(GL_VERSION) + " (GLFW window)";
  }
  void shutdown() override {
    if (imgui_backend_ != nullptr && ImGui::GetCurrentContext() == imgui_backend_) ImGui_ImplGlfw_Shutdown();
    imgui_backend_ = nullptr;
    if (window_) glfwDestroyWindow(window_);
    window_ = nullptr;
    if (glfw_inited_) glfwTerminate();
    glfw_inited_ = false;
  }

 private:
  PlatformOptions opt_;
  GLFWwindow* window_ = nullptr;
  ImGuiContext* imgui_backend_ = nullptr;
  bool glfw_inited_ = false;
  std::vector<std::string> drops_;
};

}  // namespace

std::unique_ptr<Platform> make_glfw_platform() { return std::make_unique<GlfwPlatform>(); }

}  // namespace pliant::editor
