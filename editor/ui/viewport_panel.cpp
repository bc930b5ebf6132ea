// The current take frame drawn by the Renderer into an offscreen framebuffer
// sized to the panel and shown with ImGui::Image. Left-drag orbits,
// right/middle-drag pans, the wheel zooms.
#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>
#include <cstdint>

#include "doc/smoke_keyframes.h"
#include "render/contour.h"
#include "ui/app.h"
#include "ui/keyframe_canvas.h"
#include "ui/kind_panels.h"
#include "ui/panel_window.h"

namespace pliant::editor {

namespace fs = std::filesystem;

namespace {

// Progressive preview: before the take has frames, the newest Preview record
// (a coarse level of the solve, [T+1, ny, nx]) at the current frame (the last
// frame when none is chosen). Returns false when the take has no preview.
bool sync_preview(App& app, TakeReader& rd) {
  ViewportState& v = app.viewport;
  const int want = canvas_current_frame(app);
  const std::string dir = app.take.dir().string();
  if (v.showing_preview && v.shown_dir == dir && v.shown_records == rd.record_count() && v.shown_frame == want)
    return true;
  Record r;
  if (!rd.latest(RecordKind::Preview, &r)) return false;
  const Field* d = r.find("density");
  if (!d || d->shape.size() != 3) return false;  // 2D previews only: [T+1, ny, nx]
  const int frames = int(d->shape[0]), ny = int(d->shape[1]), nx = int(d->shape[2]);
  const int f = want > 0 && want < frames ? want : frames - 1;
  Record one;
  Field slice{"density", {uint32_t(ny), uint32_t(nx)}, {}};
  const size_t cells = size_t(nx) * ny;
  slice.data.assign(d->data.begin() + f * cells, d->data.begin() + (f + 1) * cells);
  one.fields.push_back(std::move(slice));
  const bool new_take = v.shown_dir != dir;
  if (new_take) app.renderer.reset_framing();
  app.renderer.set_frame(one);
  ++v.uploads;
  if (new_take) v.camera.reset();
  v.showing_preview = true;
  v.shown_dir = dir;
  v.shown_records = rd.record_count();
  v.shown_frame = want;
  v.shown_count = 0;
  v.preview_label = "preview " + std::to_string(nx) + "x" + std::to_string(ny) + " #" +
                    std::to_string(r.index + 1) + ", frame " + std::to_string(f);
  return true;
}

// Outline of the keyframe at the shown frame over the result (2D), in the panel's
// screen rectangle; cached per document revision and frame.
struct OutlineCache {
  uint64_t doc_id = 0;  // revisions restart per Document (and per App in tests)
  uint64_t revision = ~uint64_t(0);
  int frame = -1;
  int nx = 0, ny = 0;
  std::vector<ContourSegment> segs;
};

void draw_keyframe_outline(App& app, ImVec2 pos, int w, int h) {
  static OutlineCache cache;
  if (!app.viewport.show_outlines || app.renderer.frame_dim() != 2) return;
  const nlohmann::json& scene = app.doc.scene();
  const int frame = app.viewport.showing_preview ? app.viewport.shown_frame : app.take.frame;
  const int slot = keyframe_at_frame(scene, frame);
  if (slot < 0) return;
  if (cache.doc_id != app.doc.id() || cache.revision != app.doc.revision() || cache.frame != frame) {
    cache.doc_id = app.doc.id();
    std::string err;
    geom::PaintedGrid g = rasterize_slot(scene, app.doc.has_path() ? app.doc.path().parent_path() : fs::path(),
                                         slot, &err);
    std::vector<float> v(g.value.begin(), g.value.end());
    cache.segs = g.cells() ? contour_lines(v.data(), g.n[0], g.n[1], 127.5f) : std::vector<ContourSegment>{};
    cache.nx = g.n[0];
    cache.ny = g.n[1];
    cache.revision = app.doc.revision();
    cache.frame = frame;
  }
  if (cache.nx <= 0) return;
  const auto e = app.renderer.domain_extent();
  const auto m = app.viewport.camera.view_projection_2d(float(w) / float(h), e[0], e[1]);
  auto screen = [&](const std::array<float, 2>& c) {
    const float wx = -0.5f * e[0] + c[0] / cache.nx * e[0], wy = -0.5f * e[1] + c[1] / cache.ny * e[1];
    const float nx = m[0] * wx + m[4] * wy + m[12], ny = m[1] * wx + m[5] * wy + m[13];
    return ImVec2(pos.x + 0.5f * (nx + 1.0f) * w, pos.y + 0.5f * (1.0f - ny) * h);
  };
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->PushClipRect(pos, ImVec2(pos.x + w, pos.y + h), true);
  for (const auto& sgm : cache.segs) dl->AddLine(screen(sgm.a), screen(sgm.b), IM_COL32(90, 200, 255, 230), 1.5f);
  dl->PopClipRect();
}

// Uploads the frame the timeline points at when it changed.
void sync_frame(App& app) {
  std::string& shown_dir = app.viewport.shown_dir;
  int& shown_frame = app.viewport.shown_frame;
  int& shown_count = app.viewport.shown_count;
  if (const KindPanels* kp = kind_panels(scene_kind(app)); kp && kp->viewport_frame && kp->viewport_frame(app)) {
    shown_frame = -1;  // the take's frame is uploaded again when the kind lets go
    return;
  }
  TakeReader* rd = app.take.reader();
  if (rd && app.take.frame_count() == 0 && sync_preview(app, *rd)) return;
  app.viewport.showing_preview = false;
  if (!rd || app.take.frame_count() == 0) {
    if (app.renderer.has_frame()) {
      app.renderer.clear_frame();
      ++app.viewport.uploads;
    }
    shown_dir.clear();
    shown_frame = -1;
    return;
  }
  std::string dir = app.take.dir().string();
  int count = app.take.frame_count();
  if (dir == shown_dir && app.take.frame == shown_frame && count == shown_count) return;
  bool new_take = dir != shown_dir;
  try {
    if (new_take) app.renderer.reset_framing();
    app.renderer.set_take_frame(*rd, static_cast<size_t>(app.take.frame));
    ++app.viewport.uploads;
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
  // Smoke 2D scenes: the result or the keyframe canvas. Other kinds add their
  // editors beside this switch.
  const bool paintable = is_smoke_2d(app.doc.scene());
  const bool slices = !paintable && has_control(app.doc.scene());  // 3D keyframes
  if (paintable || slices) {
    if (ImGui::RadioButton("Result", !v.show_canvas)) v.show_canvas = false;
    ui_mark("view_result");
    ImGui::SameLine();
    if (ImGui::RadioButton("Keyframes", v.show_canvas)) v.show_canvas = true;
    ui_mark("view_keyframes");
    ImGui::SameLine();
  }
  if ((paintable || slices) && v.show_canvas) {
    if (paintable) draw_keyframe_canvas(app);
    else draw_keyframe_slices(app);
    ImGui::End();
    return;
  }
  const KindPanels* kp = kind_panels(scene_kind(app));
  if (kp && kp->viewport_editor && kp->viewport_editor(app)) {
    ImGui::End();
    return;
  }
  if (ImGui::Button("Reset view")) v.camera.reset();
  ui_mark("Reset view");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(120);
  ImGui::SliderFloat("density", &v.settings.density_scale, 0.05f, 10.0f, "%.2f",
                     ImGuiSliderFlags_Logarithmic);
  ImGui::Checkbox("grid", &v.settings.show_grid);
  ImGui::SameLine();
  ImGui::Checkbox("velocity", &v.settings.show_velocity);
  ImGui::SameLine();
  ImGui::Checkbox("force", &v.settings.show_force);
  if (paintable) {
    ImGui::SameLine();
    ImGui::Checkbox("outlines", &v.show_outlines);
  }
  ImGui::SameLine();
  if (ImGui::Checkbox("A/B", &app.compare.enabled) && app.compare.enabled)
    app.compare.open(default_compare_take(app));
  ui_mark("ab_compare");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("compare the shown take (A, left) with another (B, right)");
  if (app.compare.enabled) {
    ImGui::SameLine();
    if (ImGui::SmallButton("Swap") && !app.compare.dir.empty()) {
      fs::path a = app.take.dir();
      app.cmd_open_take(app.compare.dir);
      app.compare.open(a);
    }
    ui_mark("ab_swap");
  }
  if (kp && kp->viewport_toolbar) {
    ImGui::SameLine();
    kp->viewport_toolbar(app);
  }

  ImVec2 avail = ImGui::GetContentRegionAvail();
  const int full_w = std::max(16, static_cast<int>(avail.x));
  // A/B: A takes the left half, B the right half, same camera.
  int w = app.compare.enabled ? std::max(16, full_w / 2) : full_w;
  int h = std::max(16, static_cast<int>(avail.y));
  ImVec2 pos = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("viewport_canvas", ImVec2(static_cast<float>(full_w), static_cast<float>(h)),
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
    // Software GL (llvmpipe) pays per pixel: redraw the FBO only when the frame,
    // camera, settings or size changed.
    const OrbitCamera& cam = v.camera;
    const ViewSettings& vs = v.settings;
    std::vector<float> state = {float(v.uploads), cam.yaw_deg, cam.pitch_deg, cam.distance, cam.fov_deg,
                                cam.target[0], cam.target[1], cam.target[2], cam.zoom2d, cam.pan2d[0],
                                cam.pan2d[1], vs.density_scale, float(vs.show_grid), float(vs.show_velocity),
                                float(vs.show_force), vs.background[0], vs.background[1], vs.background[2],
                                vs.smoke_color[0], vs.smoke_color[1], vs.smoke_color[2], float(w), float(h),
                                float(app.renderer.has_frame())};
    if (v.target.ensure(w, h) || state != v.drawn_state) {
      v.target.bind();
      const auto& bg = v.settings.background;
      glClearColor(bg[0], bg[1], bg[2], 1.0f);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      if (app.renderer.has_frame()) app.renderer.render(v.camera, v.settings, w, h);
      glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(prev_fb));
      v.drawn_state = std::move(state);
    }
    // GL's origin is bottom-left: flip v so the image is upright.
    ImGui::GetWindowDrawList()->AddImage(
        reinterpret_cast<ImTextureID>(static_cast<intptr_t>(v.target.color_tex)), pos,
        ImVec2(pos.x + w, pos.y + h), ImVec2(0, 1), ImVec2(1, 0));
    if (app.renderer.has_frame()) draw_keyframe_outline(app, pos, w, h);
    if (kp && kp->viewport_overlay) kp->viewport_overlay(app, pos.x, pos.y, w, h);
    if (app.compare.enabled) app.compare.draw(app, pos.x + w, pos.y, full_w - w, h);
    if (v.showing_preview)
      ImGui::GetWindowDrawList()->AddText(ImVec2(pos.x + 12, pos.y + 12), IM_COL32(255, 210, 120, 255),
                                          v.preview_label.c_str());
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
