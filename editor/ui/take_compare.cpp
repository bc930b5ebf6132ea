#include "ui/take_compare.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>
#include <cstdint>

#include "ui/app.h"

namespace pliant::editor {

namespace fs = std::filesystem;

void TakeCompare::open(const fs::path& take_dir) {
  dir = take_dir;
  reader.reset();
  error.clear();
  shown_frame = -1;
  shown_count = 0;
  renderer.reset_framing();
}

fs::path default_compare_take(App& app) {
  for (size_t i = app.jobs.size(); i-- > 0;)
    if (app.jobs[i]->spec().take != app.take.dir()) return app.jobs[i]->spec().take;
  return {};
}

void TakeCompare::release_gl() {
  if (fbo) glDeleteFramebuffers(1, &fbo);
  if (color_tex) glDeleteTextures(1, &color_tex);
  if (depth_rb) glDeleteRenderbuffers(1, &depth_rb);
  fbo = color_tex = depth_rb = 0;
  if (renderer_ready) renderer.shutdown();
  renderer_ready = false;
}

void TakeCompare::draw(App& app, float x, float y, int w, int h) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  auto message = [&](const std::string& m) {
    dl->AddText(ImVec2(x + 12, y + 12), IM_COL32(200, 200, 210, 255), m.c_str());
  };
  if (dir.empty()) return message("B: no other take (run another job, or Open Take)");
  try {
    if (!reader) reader = std::make_unique<TakeReader>(dir);
    else reader->refresh();
  } catch (const std::exception& e) {
    error = e.what();
    return message("B: " + error);
  }
  if (!renderer_ready) {
    std::string err;
    renderer_ready = renderer.init(&err);
    if (!renderer_ready) return message("B: " + err);
  }
  const int n = int(reader->frame_count());
  if (n == 0) return message("B: no frames yet");
  const int f = std::clamp(app.take.frame, 0, n - 1);
  if (f != shown_frame || size_t(n) != shown_count) {
    renderer.set_frame(reader->read_frame_at(size_t(f)), &reader->manifest().scene);
    shown_frame = f;
    shown_count = size_t(n);
  }
  if (!fbo) {
    glGenFramebuffers(1, &fbo);
    glGenTextures(1, &color_tex);
    glGenRenderbuffers(1, &depth_rb);
  }
  if (fbo_w != w || fbo_h != h) {
    glBindTexture(GL_TEXTURE_2D, color_tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_tex, 0);
    // Depth for the kind drawers' meshes (soft characters, articulated bodies).
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
    fbo_w = w;
    fbo_h = h;
  }
  GLint prev = 0;
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, w, h);
  renderer.render(app.viewport.camera, app.viewport.settings, w, h);
  glBindFramebuffer(GL_FRAMEBUFFER, GLuint(prev));
  dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(color_tex)), ImVec2(x, y),
               ImVec2(x + w, y + h), ImVec2(0, 1), ImVec2(1, 0));
  dl->AddLine(ImVec2(x, y), ImVec2(x, y + h), IM_COL32(200, 200, 210, 255), 2.0f);
  const std::string label = "B: " + dir.filename().string() + " (" + reader->manifest().status + "), frame " +
                            std::to_string(f);
  message(label);
}

}  // namespace pliant::editor
