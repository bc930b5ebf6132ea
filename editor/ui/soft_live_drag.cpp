// Click-and-drag push in Live playback (see soft_ui.h): the animator grabs the
// body and pulls it the way it should be shoved. The push acts while the
// button is held, not as an impulse on release: the body answers while the
// arrow is on screen (a spring-like pull one can steer, stop or aim again), the
// arrow never shows a force that has not acted yet, and the strength follows
// the drag length continuously instead of a guessed duration. The force acts
// where the body was grabbed (SoftPlayback::push_nodal): a leg pulled at its tip
// swings the body round, as a hand would. One vertex puts the whole force on the
// 8 nodes of one cell, so it is spread over the surface vertices within half a
// lattice cell of the picked one (hat weights 1 - d / radius, normalised; taken
// once at the press): the same total force, its moment about the picked vertex
// zero to first order (the patch's weighted centre is within the radius).
#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "render/screen_ray.h"
#include "ui/app.h"
#include "ui/soft_ui.h"
#include "ui/ui_mark.h"

#ifdef PLIANT_HAVE_SOFT
#include "pliant/soft/soft.h"
#endif

namespace pliant::editor {

namespace {

// Full drag (one body length or more): the Push button's 20 m/s^2.
constexpr float kDragPushAccel = 20;
constexpr float kPickRadiusPx = 12;




Vec3 live_vertex(const SoftLive& live, int v) {
  const size_t i = 3 * size_t(v);
  return {live.vertices[i], live.vertices[i + 1], live.vertices[i + 2]};
}

// The front-most surface vertex within kPickRadiusPx of the mouse (-1: none).
int pick_live_vertex(const SoftLive& live, const Mat4& m, const ImVec2& mouse, float x, float y, int w, int h) {
  int best = -1;
  float best_z = 1e30f;
  for (size_t i = 0; 3 * i + 2 < live.vertices.size(); ++i) {
    const ScreenPoint s = project_to_screen(m, live_vertex(live, int(i)), x, y, w, h);
    const float dx = s.x - mouse.x, dy = s.y - mouse.y;
    // Depth with a bias for screen distance: the vertex right under the mouse wins a tie.
    const float z = s.depth + 1e-3f * (dx * dx + dy * dy);
    if (s.ok && dx * dx + dy * dy < kPickRadiusPx * kPickRadiusPx && z < best_z) {
      best_z = z;
      best = int(i);
    }
  }
  return best;
}

// The surface vertices that share the grab of vertex v (see the file comment).
void live_drag_patch(SoftLive& live, int v) {
  live.drag_patch.clear();
  if (v < 0) return;
#ifdef PLIANT_HAVE_SOFT
  const float radius = live.model ? 0.5f * float(live.model->character.lattice.cell_size_m) : 0.0f;
  const Vec3 a = live_vertex(live, v);
  float total = 0;
  for (size_t i = 0; 3 * i + 2 < live.vertices.size(); ++i) {
    const Vec3 b = live_vertex(live, int(i));
    const float d = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
    const float w = int(i) == v ? 1.0f : (radius > 0 ? 1.0f - d / radius : 0.0f);
    if (w <= 0) continue;
    live.drag_patch.push_back({int(i), w});
    total += w;
  }
  for (auto& p : live.drag_patch) p.second /= total;
#endif
}

float live_mass_kg(const SoftLive& live) {
#ifdef PLIANT_HAVE_SOFT
  return live.model ? float(live.model->character.mass_kg) : 0.0f;
#else
  (void)live;
  return 0.0f;
#endif
}

// Horizontal extent of the shown surface: the drag length of a full push.
float live_body_length(const SoftLive& live) {
  float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
  for (size_t i = 0; i + 2 < live.vertices.size(); i += 3)
    for (int k = 0; k < 2; ++k) {
      const float v = live.vertices[i + 2 * k];  // x, z
      lo[k] = std::min(lo[k], v);
      hi[k] = std::max(hi[k], v);
    }
  return std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-3f});
}

}  // namespace

void soft_live_drag(App& app, const Mat4& m, float x, float y, int w, int h) {
  SoftUi& ui = soft_ui(app);
  SoftLive& live = ui.live;
  if (!live.on || !live.pb || live.vertices.empty()) {
    live.drag_vertex = -1;
    live.drag_force = {0, 0, 0};
    return;
  }
  const ImGuiIO& io = ImGui::GetIO();
  const ImVec2 mouse = io.MousePos;
  const bool inside = mouse.x >= x && mouse.y >= y && mouse.x < x + w && mouse.y < y + h;
  // The press has just made the canvas button active: hovered despite it.
  if (live.drag_vertex < 0 && ui.drag_handle == 0 && inside &&
      ImGui::IsWindowHovered(ImGuiHoveredFlags_AllowWhenBlockedByActiveItem) &&
      ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    live.drag_vertex = pick_live_vertex(live, m, mouse, x, y, w, h);
    live_drag_patch(live, live.drag_vertex);
    live.drag_camera = app.viewport.camera;
  }

  if (live.drag_vertex < 0) return;
  if (!ImGui::IsMouseDown(ImGuiMouseButton_Left) || 3 * size_t(live.drag_vertex) + 2 >= live.vertices.size()) {
    live.drag_vertex = -1;
    live.drag_force = {0, 0, 0};
    return;
  }
  // The canvas orbits on a left drag; keep the view still while the body is held.
  app.viewport.camera = live.drag_camera;
  const Vec3 a = live_vertex(live, live.drag_vertex);
  Vec3 hit;
  live.drag_force = {0, 0, 0};
  if (!screen_ray_plane_y(m, mouse.x, mouse.y, x, y, w, h, a[1], &hit)) return;
  const float dx = hit[0] - a[0], dz = hit[2] - a[2], len = std::sqrt(dx * dx + dz * dz);
  const float full = live_body_length(live);
  const float frac = std::min(len / full, 1.0f);
  const float f = kDragPushAccel * live_mass_kg(live) * frac;
  if (len > 1e-6f) live.drag_force = {f * dx / len, 0, f * dz / len};

  // The arrow: from the picked vertex along the drag, capped at the full length.
  const float shown = std::min(len, full);
  const Vec3 tip = len > 1e-6f ? Vec3{a[0] + shown * dx / len, a[1], a[2] + shown * dz / len} : a;
  const ScreenPoint s0 = project_to_screen(m, a, x, y, w, h), s1 = project_to_screen(m, tip, x, y, w, h);
  if (!s0.ok || !s1.ok) return;
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImU32 col = IM_COL32(255, 120, 60, 255);
  dl->AddCircleFilled(ImVec2(s0.x, s0.y), 4, col);
  dl->AddLine(ImVec2(s0.x, s0.y), ImVec2(s1.x, s1.y), col, 2.5f);
  const float ex = s1.x - s0.x, ey = s1.y - s0.y, el = std::sqrt(ex * ex + ey * ey);
  if (el > 4) {
    const float ux = ex / el, uy = ey / el, head = std::min(12.0f, 0.4f * el);
    for (int side : {-1, 1})
      dl->AddLine(ImVec2(s1.x, s1.y), ImVec2(s1.x - head * ux + side * 0.5f * head * uy, s1.y - head * uy - side * 0.5f * head * ux),
                  col, 2.5f);
  }
  char label[64];
  std::snprintf(label, sizeof label, "push %.4g N (%.0f%%)", f, 100 * frac);
  dl->AddText(ImVec2(s1.x + 8, s1.y - 8), col, label);
}

}  // namespace pliant::editor
