// The Character edit mode of soft scenes (replaces the result view): the body
// compiled from the document (lattice cells as lines, the embedded surface lit),
// deformed live by one slider per linear mode (x = X + U q with q from the
// sliders' amplitudes in metres: soft_q_from_amplitudes), a click on a surface
// vertex pins it at the current frame (the partial-keyframe objective, one
// undo step), and the objective gizmos. The sliders are UI state, not document
// data: moving them never edits the scene.
#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "doc/soft_scene.h"
#include "render/soft_drawer.h"
#include "ui/app.h"
#include "ui/panel_window.h"
#include "ui/soft_ui.h"

#ifdef PLIANT_HAVE_SOFT
#include "pliant/soft/soft.h"
#endif

namespace pliant::editor {

#ifndef PLIANT_HAVE_SOFT
bool soft_character_view(App& app) {
  SoftUi& ui = soft_ui(app);
  if (!ui.character_mode) return false;
  if (ImGui::Button("Result")) ui.character_mode = false;
  ImGui::TextColored(kErrorColor, "this editor was built without the soft module");
  return true;
}
#else

namespace {

constexpr LineDrawer::Color kLattice{0.55f, 0.75f, 1.0f, 0.45f};
constexpr LineDrawer::Color kGrid{0.45f, 0.48f, 0.55f, 0.55f};
constexpr LineDrawer::Color kPinned{1.0f, 0.3f, 0.3f, 1.0f};
constexpr LineDrawer::Color kHover{1.0f, 0.95f, 0.3f, 1.0f};
constexpr MeshDrawer::Color kBody{0.93f, 0.62f, 0.38f, 1.0f};

void add_cross(LineDrawer& l, const Vec3& p, float r, const LineDrawer::Color& c) {
  for (int a = 0; a < 3; ++a) {
    Vec3 lo = p, hi = p;
    lo[a] -= r;
    hi[a] += r;
    l.add(lo, hi, c);
  }
}

// Offset of a pin at `frame`: where the shown take has the vertex then
// (relative to frame 0), else where the velocity target would carry it.
SoftVec3 pin_offset(App& app, int frame, int vertex, size_t nverts) {
  const SoftSceneInfo info = soft_scene_info(app.doc.scene());
  SoftVec3 off{0, 0, 0};
  if (info.has_velocity)
    for (int a = 0; a < 3; ++a) off[a] = info.velocity_target[a] * frame * info.dt_s;
  TakeReader* rd = app.take.reader();
  if (!rd || rd->manifest().kind != "soft" || frame >= app.take.frame_count()) return off;
  try {
    const Record r0 = rd->read_frame_at(0), rf = rd->read_frame_at(size_t(frame));
    const Field* v0 = r0.find("vertices");
    const Field* vf = rf.find("vertices");
    if (!v0 || !vf || v0->data.size() != nverts * 3 || vf->data.size() != nverts * 3) return off;
    for (int a = 0; a < 3; ++a) off[a] = double(vf->data[3 * size_t(vertex) + a] - v0->data[3 * size_t(vertex) + a]);
  } catch (const std::exception&) {
  }
  return off;
}

}  // namespace

bool soft_character_view(App& app) {
  SoftUi& ui = soft_ui(app);
  if (!soft_character_shown(app)) return false;
  if (!app.take.dir().empty()) {  // with no take there is no result to go back to
    if (ImGui::Button("Result")) ui.character_mode = false;
    ui_mark("soft_result");
    ImGui::SameLine();
  }
  ImGui::Checkbox("lattice", &ui.show_lattice);
  ui_mark("soft_lattice");
  ImGui::SameLine();
  if (ImGui::Button("Reset view")) app.viewport.camera.reset();
  ImGui::SameLine();
  if (ImGui::Button("Rest shape")) std::fill(ui.amplitude_m.begin(), ui.amplitude_m.end(), 0.0f);
  ui_mark("soft_rest_shape");
  ImGui::SameLine();
  const int pin_frame = soft_pin_frame(app);
  ImGui::TextDisabled("click a vertex: pin it at frame %d%s%s", pin_frame, ui.last_pick.empty() ? "" : " | ",
                      ui.last_pick.c_str());

  const SoftPreviewModel& pm = soft_preview_model(app);
  if (pm.building()) {
    ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.45f, 1.0f), "building lattice...");
    ui_mark("soft_building");
  }
  if (!pm.model) {
    if (!pm.building()) {
      ImGui::PushTextWrapPos(0);
      ImGui::TextColored(kErrorColor, "%s", pm.error.c_str());
      ImGui::PopTextWrapPos();
    }
    return true;
  }
  const soft::SoftModel& m = *pm.model;
  const int r = m.character.basis.r();
  ui.amplitude_m.resize(size_t(r), 0.0f);

  // Rest body bounds: slider ranges and the framing.
  const auto& rest = m.character.surface.vertices;
  Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
  for (const auto& v : rest)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], float(v[a]));
      hi[a] = std::max(hi[a], float(v[a]));
    }
  const float size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-3f});

  // Mode sliders (left column).
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  ImGui::BeginChild("soft_modes", ImVec2(std::min(230.0f, 0.3f * avail.x), avail.y), true);
  ImGui::TextDisabled("%d modes, %d cells, %d nodes", r, int(m.character.lattice.cells.size()),
                      m.character.lattice.nodes());
  ImGui::TextDisabled("compiled in %.2f s", pm.compile_s);
  for (int k = 0; k < r; ++k) {
    ImGui::PushID(k);
    char label[32];
    std::snprintf(label, sizeof label, "mode %d", k);
    ImGui::SetNextItemWidth(-60);
    ImGui::SliderFloat(label, &ui.amplitude_m[size_t(k)], -0.3f * size, 0.3f * size, "%.3f m");
    ui_mark_field("mode_slider_" + std::to_string(k));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("largest node displacement of mode %d (omega^2 = %.3g)", k,
                                                  k < m.character.basis.omega2.size() ? m.character.basis.omega2[k] : 0.0);
    ImGui::PopID();
  }
  ImGui::EndChild();
  ImGui::SameLine();

  // The deformed body in world coordinates (frame 0 adds the start offset).
  const SoftSceneInfo info = soft_scene_info(app.doc.scene());
  Eigen::VectorXd amp(r);
  for (int k = 0; k < r; ++k) amp[k] = ui.amplitude_m[size_t(k)];
  std::vector<Eigen::Vector3d> surface;
  Eigen::VectorXd nodes;
  soft::soft_mode_shape(m, soft::soft_q_from_amplitudes(m, amp), surface, &nodes);
  const Vec3 off{float(info.start_offset[0]), float(info.start_offset[1]), float(info.start_offset[2])};
  ui.surface.resize(surface.size() * 3);
  for (size_t i = 0; i < surface.size(); ++i)
    for (int a = 0; a < 3; ++a) ui.surface[3 * i + size_t(a)] = float(surface[i][a]) + off[a];
  const Vec3 base{float(m.character.rest_com[0]) + off[0], float(m.character.rest_com[1]) + off[1],
                  float(m.character.rest_com[2]) + off[2]};

  // Framing: the body and a position target (a velocity's goal may be metres
  // away; the result view frames it, this view is for the body).
  const SoftVec3 goal = info.has_position ? info.position_target : SoftVec3{base[0], base[1], base[2]};
  Vec3 blo, bhi;
  for (int a = 0; a < 3; ++a) {
    blo[a] = std::min({lo[a] + off[a], float(goal[a])}) - 0.5f * size;
    bhi[a] = std::max({hi[a] + off[a], float(goal[a])}) + 0.5f * size;
  }
  if (info.ground && !info.water) blo[1] = float(info.ground_y);
  Vec3 centre;
  for (int a = 0; a < 3; ++a) centre[a] = 0.5f * (blo[a] + bhi[a]);
  const float scale = 1.0f / std::max({bhi[0] - blo[0], bhi[1] - blo[1], bhi[2] - blo[2], 1e-6f});
  Mat4 framing = mat4_identity();
  framing[0] = framing[5] = framing[10] = scale;
  for (int a = 0; a < 3; ++a) framing[12 + a] = -scale * centre[a];

  // Canvas: orbit (drag), zoom (wheel), pick (click without drag).
  const ImVec2 canvas = ImGui::GetContentRegionAvail();
  const int w = std::max(16, int(canvas.x)), h = std::max(16, int(canvas.y));
  const ImVec2 pos = ImGui::GetCursorScreenPos();
  const bool released = ImGui::InvisibleButton("soft_character_canvas", ImVec2(float(w), float(h)),
                                               ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
  ui_mark("soft_character_canvas");
  const ImGuiIO& io = ImGui::GetIO();
  OrbitCamera& cam = app.viewport.camera;
  if (ImGui::IsItemActive()) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) cam.orbit(io.MouseDelta.x, io.MouseDelta.y);
    else if (ImGui::IsMouseDown(ImGuiMouseButton_Right)) cam.pan(io.MouseDelta.x, io.MouseDelta.y, h);
  }
  if (ImGui::IsItemHovered() && io.MouseWheel != 0) cam.zoom(io.MouseWheel);
  const Mat4 view = mat4_mul(cam.view(), framing);
  ui.world_to_clip = mat4_mul(cam.projection(float(w) / float(h)), view);

  // Nearest surface vertex under the mouse (the front-most within 10 px).
  ui.hovered_vertex = -1;
  if (ImGui::IsItemHovered()) {
    float best_z = 1e30f;
    for (size_t i = 0; i < surface.size(); ++i) {
      const auto c = mat4_apply(ui.world_to_clip, {ui.surface[3 * i], ui.surface[3 * i + 1], ui.surface[3 * i + 2], 1});
      if (!(c[3] > 1e-6f)) continue;
      const float sx = pos.x + 0.5f * (c[0] / c[3] + 1) * w, sy = pos.y + 0.5f * (1 - c[1] / c[3]) * h;
      const float dx = sx - io.MousePos.x, dy = sy - io.MousePos.y;
      // Depth with a bias for screen distance, so a vertex right under the mouse wins a tie.
      const float z = c[2] / c[3] + 1e-3f * (dx * dx + dy * dy);
      if (dx * dx + dy * dy < 100.0f && z < best_z) {
        best_z = z;
        ui.hovered_vertex = int(i);
      }
    }
  }
  if (released && ui.drag_handle == 0 && io.MouseDragMaxDistanceSqr[0] < 9.0f && ui.hovered_vertex >= 0) {
    const int v = ui.hovered_vertex;
    const SoftVec3 o = pin_offset(app, pin_frame, v, surface.size());
    app.doc.edit("Pin vertex " + std::to_string(v) + " at frame " + std::to_string(pin_frame),
                 soft_with_pin(app.doc.scene(), pin_frame, v, o));
    ui.last_pick = "vertex " + std::to_string(v) + " pinned at frame " + std::to_string(pin_frame);
    app.log.info(ui.last_pick);
  }

  if (app.has_gl()) {
    if (!ui.gl_ready) {
      std::string err;
      if (!ui.mesh.init(&err) || !ui.lines.init(&err)) {
        app.log.error("character view: " + err);
        ui.character_mode = false;
        ui.gl_failed = true;
        return true;
      }
      ui.gl_ready = true;
    }
    const std::vector<SoftPin> pins = soft_pins_at(app.doc.scene(), pin_frame);
    std::vector<float> state = {float(w), float(h), float(ui.show_lattice), float(ui.hovered_vertex),
                                float(pins.size()), float(app.doc.revision()), float(pm.key & 0xffffff)};
    state.insert(state.end(), ui.world_to_clip.begin(), ui.world_to_clip.end());
    state.insert(state.end(), ui.amplitude_m.begin(), ui.amplitude_m.end());
    if (ui.target.ensure(w, h) || state != ui.drawn_state) {
      ++ui.redraws;
      GLint prev_fb = 0;
      glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev_fb);
      ui.target.bind();
      const auto& bg = app.viewport.settings.background;
      glClearColor(bg[0], bg[1], bg[2], 1.0f);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      glEnable(GL_DEPTH_TEST);
      std::vector<uint32_t> tris;
      tris.reserve(m.character.surface.triangles.size() * 3);
      for (const auto& t : m.character.surface.triangles)
        for (int c : t) tris.push_back(uint32_t(c));
      ui.mesh.clear();
      ui.mesh.add_mesh(ui.surface.data(), surface.size(), tris.data(), tris.size() / 3, kBody, mat4_identity());
      ui.mesh.draw(ui.world_to_clip, view);
      glDisable(GL_DEPTH_TEST);
      LineDrawer& l = ui.lines;
      l.clear();
      if (info.ground && !info.water) {
        const float step = size / 4;
        for (float x = std::floor(blo[0] / step) * step; x <= bhi[0]; x += step)
          l.add({x, float(info.ground_y), blo[2]}, {x, float(info.ground_y), bhi[2]}, kGrid);
        for (float z = std::floor(blo[2] / step) * step; z <= bhi[2]; z += step)
          l.add({blo[0], float(info.ground_y), z}, {bhi[0], float(info.ground_y), z}, kGrid);
      }
      if (ui.show_lattice) {
        const auto& cells = m.character.lattice.cells;
        auto node = [&](int n) {
          return Vec3{float(nodes[3 * n]) + off[0], float(nodes[3 * n + 1]) + off[1], float(nodes[3 * n + 2]) + off[2]};
        };
        for (const auto& c : cells)
          for (int a = 0; a < 8; ++a)
            for (int bit : {1, 2, 4})
              if (!(a & bit)) l.add(node(c[size_t(a)]), node(c[size_t(a | bit)]), kLattice);
      }
      for (const SoftPin& p : pins)
        if (p.vertex >= 0 && size_t(p.vertex) < surface.size())
          add_cross(l, {ui.surface[3 * size_t(p.vertex)], ui.surface[3 * size_t(p.vertex) + 1],
                        ui.surface[3 * size_t(p.vertex) + 2]}, 0.04f * size, kPinned);
      if (ui.hovered_vertex >= 0)
        add_cross(l, {ui.surface[3 * size_t(ui.hovered_vertex)], ui.surface[3 * size_t(ui.hovered_vertex) + 1],
                      ui.surface[3 * size_t(ui.hovered_vertex) + 2]}, 0.05f * size, kHover);
      l.draw(ui.world_to_clip);
      glDisable(GL_BLEND);
      glUseProgram(0);
      glBindFramebuffer(GL_FRAMEBUFFER, GLuint(prev_fb));
      ui.drawn_state = std::move(state);
    }
    ImGui::GetWindowDrawList()->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(ui.target.color_tex)), pos,
                                         ImVec2(pos.x + w, pos.y + h), ImVec2(0, 1), ImVec2(1, 0));
  }
  soft_gizmos(app, ui.world_to_clip, base, size, pos.x, pos.y, w, h);
  return true;
}

#endif  // PLIANT_HAVE_SOFT

}  // namespace pliant::editor
