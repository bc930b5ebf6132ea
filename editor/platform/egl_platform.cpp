// Headless OpenGL through EGL (ARCHITECTURE.md, Headless mode). Prefers an
// EGL_EXT_platform_device software device (Mesa llvmpipe/swrast), falls back
// to EGL_PLATFORM_SURFACELESS_MESA. The context has no surface; an FBO with
// RGBA8 colour and depth24/stencil8 stands in for the default framebuffer.
// PLIANT_EGL_PLATFORM=surfaceless in the environment forces the fallback.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include "platform/imgui_headless_io.h"
#include "platform/platform.h"

namespace pliant::editor {
namespace {

std::string egl_error_name(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return "EGL error 0x" + [&] {
      char b[16];
      std::snprintf(b, sizeof b, "%04x", static_cast<unsigned>(e));
      return std::string(b);
    }();
  }
}

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    const bool starts = p == list || p[-1] == ' ';
    const bool ends = p[n] == '\0' || p[n] == ' ';
    if (starts && ends) return true;
  }
  return false;
}

class EglPlatform final : public Platform {
 public:
  ~EglPlatform() override { shutdown(); }

  bool init(const PlatformOptions& opt, std::string* err) override {
    opt_ = opt;
    if (opt.width <= 0 || opt.height <= 0)
      return fail(err, "framebuffer size must be positive, got " + std::to_string(opt.width) +
                           "x" + std::to_string(opt.height));
    std::string why;
    if (!open_display(&why)) return fail(err, why);
    if (!eglBindAPI(EGL_OPENGL_API))
      return fail(err, "eglBindAPI(EGL_OPENGL_API) failed: " + egl_error_name(eglGetError()));
    if (!create_context(&why)) return fail(err, why);
    if (!create_framebuffer(&why)) return fail(err, why);
    return true;
  }

  void new_frame() override { clock_.new_frame(opt_.width, opt_.height, opt_.fixed_dt_s); }
  void present() override {
    if (ctx_ != EGL_NO_CONTEXT) glFinish();
  }
  bool should_close() const override { return close_; }
  void request_close() override { close_ = true; }
  void framebuffer_size(int* w, int* h) const override {
    *w = opt_.width;
    *h = opt_.height;
  }
  unsigned default_framebuffer() const override { return fbo_; }
  std::vector<std::string> take_dropped_files() override { return std::exchange(drops_, {}); }
  void inject_drop(const std::vector<std::string>& paths) override {
    drops_.insert(drops_.end(), paths.begin(), paths.end());
  }
  void set_title(const std::string& title) override { opt_.title = title; }
  bool headless() const override { return true; }
  std::string gl_description() const override {
    if (ctx_ == EGL_NO_CONTEXT) return "";
    auto str = [](GLenum e) {
      const GLubyte* s = glGetString(e);
      return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    return str(GL_RENDERER) + ", OpenGL " + str(GL_VERSION) + " (" + device_ + ")";
  }

  void shutdown() override {
    if (dpy_ == EGL_NO_DISPLAY) return;
    if (ctx_ != EGL_NO_CONTEXT) {
      if (fbo_) glDeleteFramebuffers(1, &fbo_);
      GLuint rbs[2] = {color_rb_, depth_rb_};
      glDeleteRenderbuffers(2, rbs);
      fbo_ = color_rb_ = depth_rb_ = 0;
      eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(dpy_, ctx_);
      ctx_ = EGL_NO_CONTEXT;
    }
    // No eglTerminate: EGL hands every caller the same display for a device, so
    // terminating would break other live platforms; and keeping the driver loaded
    // makes the next init cheap (the process exit releases it).
    eglReleaseThread();
    dpy_ = EGL_NO_DISPLAY;
  }

 private:
  bool fail(std::string* err, const std::string& why) {
    if (err) *err = "EGL headless platform: " + why;
    shutdown();
    return false;
  }

  // Device platform first (a software device if there is one), then surfaceless Mesa.
  bool open_display(std::string* why) {
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (client_ext == nullptr || get_platform_display == nullptr) {
      *why = "no EGL client extensions or eglGetPlatformDisplayEXT (no EGL vendor library found?);"
             " install Mesa's EGL (libegl-mesa0) for the llvmpipe software renderer";
      return false;
    }
    std::string tried;
    // PLIANT_EGL_PLATFORM=surfaceless skips the device platform (tests the fallback).
    const char* forced = std::getenv("PLIANT_EGL_PLATFORM");
    if (forced != nullptr && std::string(forced) == "surfaceless")
      tried += " device platform skipped (PLIANT_EGL_PLATFORM=surfaceless);";
    else if (!has_extension(client_ext, "EGL_EXT_platform_device"))
      tried += " EGL_EXT_platform_device not available;";
    else if (try_device_platform(get_platform_display, &tried))
      return true;
    if (has_extension(client_ext, "EGL_MESA_platform_surfaceless")) {
      EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (d != EGL_NO_DISPLAY && initialize(d)) {
        device_ = "EGL_PLATFORM_SURFACELESS_MESA";
        return true;
      }
      tried += " surfaceless Mesa display failed (" + egl_error_name(eglGetError()) + ");";
    } else {
      tried += " EGL_MESA_platform_surfaceless not available;";
    }
    *why = "could not open an EGL display:" + tried +
           " install Mesa's EGL (libegl-mesa0) for the llvmpipe software renderer";
    return false;
  }

  bool try_device_platform(PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display, std::string* tried) {
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
        eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (query_devices == nullptr || query_string == nullptr) {
      *tried += " eglQueryDevicesEXT missing;";
      return false;
    }
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (!query_devices(16, devices, &count) || count == 0) {
      *tried += " no EGL devices;";
      return false;
    }
    // Software devices first: deterministic pixels for golden images.
    for (int pass = 0; pass < 2; ++pass) {
      for (EGLint i = 0; i < count; ++i) {
        const char* ext = query_string(devices[i], EGL_EXTENSIONS);
        const bool software = has_extension(ext, "EGL_MESA_device_software");
        if (software != (pass == 0)) continue;
        EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (d != EGL_NO_DISPLAY && initialize(d)) {
          device_ = std::string("EGL device ") + std::to_string(i) + (software ? " (software)" : "");
          return true;
        }
        *tried += " device " + std::to_string(i) + " failed (" + egl_error_name(eglGetError()) + ");";
      }
    }
    return false;
  }

  bool initialize(EGLDisplay d) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(d, &major, &minor)) return false;
    dpy_ = d;
    return true;
  }

  bool create_context(std::string* why) {
    EGLConfig config = nullptr;  // EGL_NO_CONFIG_KHR
    const char* ext = eglQueryString(dpy_, EGL_EXTENSIONS);
    if (!has_extension(ext, "EGL_KHR_no_config_context")) {
      const EGLint attrs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(dpy_, attrs, &config, 1, &n) || n == 0) {
        *why = "no EGL config renders OpenGL (" + egl_error_name(eglGetError()) + ")";
        return false;
      }
    }
    const EGLint ctx_attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                EGL_NONE};
    ctx_ = eglCreateContext(dpy_, config, EGL_NO_CONTEXT, ctx_attrs);
    if (ctx_ == EGL_NO_CONTEXT) {
      *why = "eglCreateContext for OpenGL 3.3 core failed on " + device_ + " (" +
             egl_error_name(eglGetError()) + ")";
      return false;
    }
    if (!eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_)) {
      *why = "eglMakeCurrent without a surface failed (" + egl_error_name(eglGetError()) +
             "); the driver needs EGL_KHR_surfaceless_context";
      return false;
    }
    return true;
  }

  bool create_framebuffer(std::string* why) {
    glGenRenderbuffers(1, &color_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, color_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, opt_.width, opt_.height);
    glGenRenderbuffers(1, &depth_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, opt_.width, opt_.height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rb_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      *why = "offscreen framebuffer " + std::to_string(opt_.width) + "x" + std::to_string(opt_.height) +
             " is incomplete (status " + std::to_string(status) + ")";
      return false;
    }
    glViewport(0, 0, opt_.width, opt_.height);
    return true;
  }

  PlatformOptions opt_;
  HeadlessImGuiClock clock_;
  EGLDisplay dpy_ = EGL_NO_DISPLAY;
  EGLContext ctx_ = EGL_NO_CONTEXT;
  GLuint fbo_ = 0, color_rb_ = 0, depth_rb_ = 0;
  std::string device_;
  std::vector<std::string> drops_;
  bool close_ = false;
};

}  // namespace

std::unique_ptr<Platform> make_egl_platform() { return std::make_unique<EglPlatform>(); }

}  // namespace pliant::editor
