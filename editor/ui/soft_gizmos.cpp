// Objective gizmos of soft scenes, drawn with ImGui over a rendered image:
// the position target (green, dragged in its horizontal plane), the heading
// arrow's tip (blue, turns the direction in the ground plane) and the jump
// height (pink, dragged up and down). Each drag is one undo step: the edits of
// one drag share a merge key, and the canvas under the gizmo stays the active
// item for the whole drag (its camera orbit is undone while a handle is held).
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "doc/soft_scene.h"
#include "render/screen_ray.h"
#include "render/soft_drawer.h"
#include "ui/app.h"
#include "ui/soft_ui.h"

#ifdef PLIANT_HAVE_SOFT
#include "pliant/soft/soft.h"
#endif

namespace pliant::editor {

namespace {

// The value at a JSON pointer, or null (const operator[] must not see a missing key).
nlohmann::json at(const nlohmann::json& j, const std::string& pointer) {
  const nlohmann::json::json_pointer p(pointer);
  return j.contains(p) ? j.at(p) : nlohmann::json();
}

// Frame-0 positions (world) of the surface vertices, xyz: the preview body +
// start offset in the Character mode, the shown take's frame 0 over a result.
std::vector<float> rest_vertices(App& app, const SoftSceneInfo& info) {
  SoftUi& ui = soft_ui(app);
  std::vector<float> out;
  if (soft_character_shown(app)) {
#ifdef PLIANT_HAVE_SOFT
    if (!ui.preview.model) return out;
    const auto& rest = ui.preview.model->character.surface.vertices;
    out.reserve(3 * rest.size());
    for (const auto& v : rest)
      for (int a = 0; a < 3; ++a) out.push_back(float(v[a] + info.start_offset[size_t(a)]));
#endif
    return out;
  }
  TakeReader* rd = app.take.reader();
  const SoftTakeData* data = rd ? soft_drawer_take_data(soft_scene_key(rd->manifest().scene)) : nullptr;
  if (data) out = data->rest_vertices;
  return out;
}

constexpr int kPinHandle = 4;

uint64_t drag_key(uint64_t serial) { return (std::hash<std::string>{}("soft_gizmo") ^ (serial * 0x9e3779b97f4a7c15ull)) | 1; }

}  // namespace

void soft_gizmos(App& app, const Mat4& m, const Vec3& base, float size, float x, float y, int w, int h) {
  SoftUi& ui = soft_ui(app);
  ui.handles.clear();
  if (w <= 0 || h <= 0) return;
  const SoftSceneInfo info = soft_scene_info(app.doc.scene());
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->PushClipRect(ImVec2(x, y), ImVec2(x + w, y + h), true);
  const float len = 0.8f * size;
  struct Drawn {
    int id;
    ScreenPoint at;
    ImU32 color;
    const char* label;
  };
  std::vector<Drawn> drawn;
  if (info.has_position) {
    const Vec3 t{float(info.position_target[0]), float(info.position_target[1]), float(info.position_target[2])};
    drawn.push_back({1, project_to_screen(m, t, x, y, w, h), IM_COL32(90, 240, 110, 255), "target"});
  }
  const ScreenPoint sb = project_to_screen(m, base, x, y, w, h);
  if (info.has_heading) {
    const auto& d = info.heading_direction;
    const Vec3 tip{base[0] + len * float(d[0]), base[1] + len * float(d[1]), base[2] + len * float(d[2])};
    const ScreenPoint st = project_to_screen(m, tip, x, y, w, h);
    if (sb.ok && st.ok) dl->AddLine(ImVec2(sb.x, sb.y), ImVec2(st.x, st.y), IM_COL32(80, 200, 255, 200), 2.0f);
    drawn.push_back({2, st, IM_COL32(80, 200, 255, 255), "heading"});
  }
  if (info.has_jump) {
    const Vec3 top{base[0], base[1] + float(info.jump_height), base[2]};
    const ScreenPoint st = project_to_screen(m, top, x, y, w, h);
    if (sb.ok && st.ok) dl->AddLine(ImVec2(sb.x, sb.y), ImVec2(st.x, st.y), IM_COL32(255, 110, 215, 200), 2.0f);
    drawn.push_back({3, st, IM_COL32(255, 110, 215, 255), "jump"});
  }
  // Pin targets at the pin frame: frame-0 vertex + offset.
  const int pin_frame = soft_pin_frame(app);
  const std::vector<SoftPin> pins = soft_pins_at(app.doc.scene(), pin_frame);
  std::vector<float> rest;
  if (!pins.empty()) rest = rest_vertices(app, info);
  struct PinSpot {
    SoftPin pin;
    Vec3 target;
    ScreenPoint at;
  };
  std::vector<PinSpot> pin_spots;
  for (const SoftPin& p : pins) {
    if (p.vertex < 0 || 3 * size_t(p.vertex) + 2 >= rest.size()) continue;
    const float* r = &rest[3 * size_t(p.vertex)];
    const Vec3 t{r[0] + float(p.offset[0]), r[1] + float(p.offset[1]), r[2] + float(p.offset[2])};
    pin_spots.push_back({p, t, project_to_screen(m, t, x, y, w, h)});
  }
  const ImGuiIO& io = ImGui::GetIO();
  const ImVec2 mouse = io.MousePos;
  const bool inside = mouse.x >= x && mouse.x < x + w && mouse.y >= y && mouse.y < y + h;
  int hovered = 0, hovered_pin = -1;
  for (const Drawn& d : drawn) {
    if (!d.at.ok) continue;
    ui.handles.push_back({d.id, d.at.x, d.at.y});
    const float dx = mouse.x - d.at.x, dy = mouse.y - d.at.y;
    if (inside && dx * dx + dy * dy < 10.0f * 10.0f) hovered = d.id;
  }
  for (size_t i = 0; i < pin_spots.size(); ++i) {
    const ScreenPoint& a = pin_spots[i].at;
    if (!a.ok) continue;
    ui.handles.push_back({kPinHandle, a.x, a.y, pin_spots[i].pin.vertex});
    ui_mark_rect("soft_pin_" + std::to_string(pin_spots[i].pin.vertex), a.x - 6, a.y - 6, a.x + 6, a.y + 6);
    const float dx = mouse.x - a.x, dy = mouse.y - a.y;
    if (inside && !hovered && dx * dx + dy * dy < 8.0f * 8.0f) hovered_pin = int(i);
  }
  if (hovered_pin >= 0) hovered = kPinHandle;
  // Start, continue and end a drag.
  if (ui.drag_handle == 0 && hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    ui.drag_handle = hovered;
    ++ui.drag_serial;
    ui.drag_start_y = mouse.y;
    ui.drag_start_value = info.jump_height;
    if (hovered == kPinHandle) {
      const PinSpot& ps = pin_spots[size_t(hovered_pin)];
      ui.drag_pin = ps.pin;
      ui.drag_pin_target = ps.target;
      ui.drag_scene = app.doc.scene();
      ui.drag_start_hit = ps.target;
      Vec3 hit;
      if (screen_ray_plane_y(m, mouse.x, mouse.y, x, y, w, h, ps.target[1], &hit)) ui.drag_start_hit = hit;
    }
  } else if (ui.drag_handle && !ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    ui.drag_handle = 0;
    ui.drag_scene = nlohmann::json();
  }
  if (ui.drag_handle) {
    // The canvas orbits on a left drag; keep the view still while a handle is held.
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) ui.drag_camera = app.viewport.camera;
    app.viewport.camera = ui.drag_camera;
    const uint64_t key = drag_key(ui.drag_serial);
    Vec3 hit;
    if (ui.drag_handle == 1 && screen_ray_plane_y(m, mouse.x, mouse.y, x, y, w, h, float(info.position_target[1]), &hit)) {
      const nlohmann::json v = {hit[0], info.position_target[1], hit[2]};
      if (v != at(app.doc.scene(), "/objectives/position/target_m")) app.doc.set("/objectives/position/target_m", v, key);
    } else if (ui.drag_handle == 2 && screen_ray_plane_y(m, mouse.x, mouse.y, x, y, w, h, base[1], &hit)) {
      const float dx = hit[0] - base[0], dz = hit[2] - base[2], n = std::sqrt(dx * dx + dz * dz);
      if (n > 1e-6f) {
        const nlohmann::json v = {std::round(1e4 * dx / n) / 1e4, 0.0, std::round(1e4 * dz / n) / 1e4};
        if (v != at(app.doc.scene(), "/objectives/heading/direction")) app.doc.set("/objectives/heading/direction", v, key);
      }
    } else if (ui.drag_handle == kPinHandle) {
      // Horizontal plane through the target; Shift: up and down (metres per
      // pixel along the screen's vertical at the target).
      SoftVec3 off = ui.drag_pin.offset;
      bool ok = false;
      const Vec3& t0 = ui.drag_pin_target;
      if (io.KeyShift) {
        const ScreenPoint a = project_to_screen(m, t0, x, y, w, h), b = project_to_screen(m, {t0[0], t0[1] + size, t0[2]}, x, y, w, h);
        const float px_per_m = a.ok && b.ok ? std::abs(a.y - b.y) / size : 0.0f;
        if (px_per_m > 1e-3f) {
          off[1] += double(ui.drag_start_y - mouse.y) / px_per_m;
          ok = true;
        }
      } else if (screen_ray_plane_y(m, mouse.x, mouse.y, x, y, w, h, t0[1], &hit)) {
        off[0] += double(hit[0] - ui.drag_start_hit[0]);
        off[2] += double(hit[2] - ui.drag_start_hit[2]);
        ok = true;
      }
      if (ok) {
        for (double& c : off) c = std::round(c * 1e5) / 1e5;
        nlohmann::json next = soft_with_pin(ui.drag_scene, ui.drag_pin.frame, ui.drag_pin.vertex, off);
        if (next != app.doc.scene())
          app.doc.edit("Move pin target of vertex " + std::to_string(ui.drag_pin.vertex), std::move(next), key);
      }
    } else if (ui.drag_handle == 3) {
      // Metres per pixel along the screen's vertical at the base.
      const ScreenPoint up = project_to_screen(m, {base[0], base[1] + size, base[2]}, x, y, w, h);
      const float px_per_m = sb.ok && up.ok ? std::abs(sb.y - up.y) / size : 0.0f;
      if (px_per_m > 1e-3f) {
        double hgt = ui.drag_start_value + double(ui.drag_start_y - mouse.y) / px_per_m;
        hgt = std::max(0.0, std::round(hgt * 1e4) / 1e4);
        if (hgt != info.jump_height) app.doc.set("/objectives/jump/height_m", hgt, key);
      }
    }
  }
  for (size_t i = 0; i < pin_spots.size(); ++i) {
    const ScreenPoint& a = pin_spots[i].at;
    if (!a.ok) continue;
    const bool hot = int(i) == hovered_pin ||
                     (ui.drag_handle == kPinHandle && ui.drag_pin.vertex == pin_spots[i].pin.vertex);
    const float r = hot ? 6.0f : 4.5f;
    dl->AddRectFilled(ImVec2(a.x - r, a.y - r), ImVec2(a.x + r, a.y + r), IM_COL32(255, 80, 80, 255));
    dl->AddRect(ImVec2(a.x - r - 1, a.y - r - 1), ImVec2(a.x + r + 1, a.y + r + 1), IM_COL32(20, 20, 20, 255));
    if (hot) dl->AddText(ImVec2(a.x + 10, a.y - 8), IM_COL32(255, 80, 80, 255), "pin target (Shift: up/down)");
  }
  for (const Drawn& d : drawn) {
    if (!d.at.ok) continue;
    const bool hot = d.id == hovered || d.id == ui.drag_handle;
    dl->AddCircleFilled(ImVec2(d.at.x, d.at.y), hot ? 8.0f : 6.0f, d.color);
    dl->AddCircle(ImVec2(d.at.x, d.at.y), hot ? 9.0f : 7.0f, IM_COL32(20, 20, 20, 255), 0, 1.5f);
    if (hot) dl->AddText(ImVec2(d.at.x + 10, d.at.y - 8), d.color, d.label);
  }
  dl->PopClipRect();
}

}  // namespace pliant::editor
