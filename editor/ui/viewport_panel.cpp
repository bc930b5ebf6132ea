// The current take frame drawn by the Renderer into an offscreen framebuffer
// sized to the panel and shown with ImGui::Image. Left-drag orbits,
// right/middle-drag pans, the wheel zooms.
#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>
#include <cstdint>

#include "ui/app.h"
#include "ui/panel_window.h"

namespace pliant::editor {

namespace {

void ensure_fbo(ViewportState& v, int w, int h) {
  if (v.fbo && v.fbo_w == w && v.fbo_h == h) return;
  if (!v.fbo) {
    glGenFramebuffers(1, &v.fbo);
    glGenTextures(1, &v.color_tex);
    glGenRenderbuffers(1, &v.depth_rb);
  }
  glBindTexture(GL_TEXTURE_2D, v.color_tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_2D, 0);
  glBindRenderbuffer(GL_RENDERBUFFER, v.depth_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, v.fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, v.color_tex, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, v.depth_rb);
  v.fbo_w = w;
  v.fbo_h = h;
}

// Uploads the frame the timeline points at when it changed.
void sync_frame(App& app) {
  std::string& shown_dir = app.viewport.shown_dir;
  int& shown_frame = app.viewport.shown_frame;
  int& shown_count = app.viewport.shown_count;
  TakeReader* rd = app.take.reader();
  if (!rd || app.take.frame_count() == 0) {
    if (app.renderer.has_frame()) app.renderer.clear_frame();
    shown_dir.clear();
    shown_frame = -1;
    return;
  }
  std::string dir = app.take.dir().string();
  int count = app.take.frame_count();
  if (dir == shown_dir && app.take.frame == shown_frame && count == shown_count) return;
  bool new_take = dir != shown_dir;
  try {
    app.renderer.set_frame(rd->read_frame_at(static_cast<size_t>(app.take.frame)));
    if (new_take) app.viewport.camera.reset();
  } catch (const std::exception& e) {
    app.log.error(std::string("cannot read frame: ") + e.what());
  }
  shown_dir = dir;
  shown_frame = app.take.frame;
  shown_count = count;
}

}  // namespace

void draw_viewport_panel(App& app, const PanelRect& r) {
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(4, 4));
  bool visible = begin_panel("Viewport", r);
  ImGui::PopStyleVar();
  if (!visible) {
    ImGui::End();
    return;
  }
  ViewportState& v = app.viewport;
  if (ImGui::Button("Reset view")) v.camera.reset();
  ui_mark("Reset view");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(120);
  ImGui::SliderFloat("density", &v.settings.density_scale, 0.05f, 10.0f, "%.2f",
                     ImGuiSliderFlags_Logarithmic);
  ImGui::SameLine();
  ImGui::Checkbox("grid", &v.settings.show_grid);
  ImGui::SameLine();
  ImGui::Checkbox("velocity", &v.settings.show_velocity);

  ImVec2 avail = ImGui::GetContentRegionAvail();
  int w = std::max(16, static_cast<int>(avail.x));
  int h = std::max(16, static_cast<int>(avail.y));
  ImVec2 pos = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("viewport_canvas", ImVec2(static_cast<float>(w), static_cast<float>(h)),
                         ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight |
                             ImGuiButtonFlags_MouseButtonMiddle);
  ui_mark("viewport");
  const ImGuiIO& io = ImGui::GetIO();
  if (ImGui::IsItemActive()) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) v.camera.orbit(io.MouseDelta.x, io.MouseDelta.y);
    else if (ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle))
      v.camera.pan(io.MouseDelta.x, io.MouseDelta.y, h);
  }
  if (ImGui::IsItemHovered() && io.MouseWheel != 0) v.camera.zoom(io.MouseWheel);

  if (app.has_gl()) {
    sync_frame(app);
    GLint prev_fb = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev_fb);
    ensure_fbo(v, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, v.fbo);
    glViewport(0, 0, w, h);
    const auto& bg = v.settings.background;
    glClearColor(bg[0], bg[1], bg[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (app.renderer.has_frame()) app.renderer.render(v.camera, v.settings, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(prev_fb));
    // GL's origin is bottom-left: flip v so the image is upright.
    ImGui::GetWindowDrawList()->AddImage(
        reinterpret_cast<ImTextureID>(static_cast<intptr_t>(v.color_tex)), pos,
        ImVec2(pos.x + w, pos.y + h), ImVec2(0, 1), ImVec2(1, 0));
  }
  if (!app.renderer.has_frame()) {
    const char* msg = app.take.dir().empty() ? "No take yet: press Run (F5)"
                      : app.take.is_open()   ? "Waiting for the first frame..."
                                             : "Waiting for the take to start...";
    ImGui::GetWindowDrawList()->AddText(ImVec2(pos.x + 12, pos.y + 12),
                                        IM_COL32(200, 200, 210, 255), msg);
  }
  ImGui::End();
}

}  // namespace pliant::editor
