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
  target.release();
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
    renderer.set_take_frame(*reader, size_t(f));
    shown_frame = f;
    shown_count = size_t(n);
  }
  target.ensure(w, h);
  GLint prev = 0;
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev);
  target.bind();
  renderer.render(app.viewport.camera, app.viewport.settings, w, h);
  glBindFramebuffer(GL_FRAMEBUFFER, GLuint(prev));
  dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(target.color_tex)), ImVec2(x, y),
               ImVec2(x + w, y + h), ImVec2(0, 1), ImVec2(1, 0));
  dl->AddLine(ImVec2(x, y), ImVec2(x, y + h), IM_COL32(200, 200, 210, 255), 2.0f);
  const std::string label = "B: " + dir.filename().string() + " (" + reader->manifest().status + "), frame " +
                            std::to_string(f);
  message(label);
}

}  // namespace pliant::editor
