// Viewport gizmos for liquid scenes: a round handle at each container's origin
// moves it in the x-y plane (the source's key poses move with it), a square
// handle at its upper outer corner sets the cavity radius and height (a file
// container is inlined first), a diamond at each hand-drawn key pose
// (/source/trajectory) moves that key, and the selected key's lever (along the
// container's axis) sets its tilt. The shown take's planned trajectory
// (metrics "trajectory") is drawn as the engine's curve through its keys
// (magenta). One undo step per drag (a fresh merge key).
// The document's container outlines are drawn over the result, so an edit
// shows before the next run. World <-> screen through the liquid drawer's last
// world -> clip transform (render/liquid_drawer.h); in 3D the drag runs in the
// plane z = the container's z.
#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "doc/liquid_scene_edit.h"
#include "render/screen_ray.h"
#include "ui/liquid_scene_geometry.h"
#include "ui/app.h"
#include "ui/liquid_ui.h"

namespace pliant::editor {

using nlohmann::json;

namespace {

constexpr float kHandlePx = 7.0f;
constexpr ImU32 kKeyColor = IM_COL32(245, 150, 50, 240);
constexpr ImU32 kPlanColor = IM_COL32(230, 90, 230, 220);

struct ScreenMap {
  const LiquidViewTransform& v;
  float x, y, w, h;
  bool to_screen(double wx, double wy, double wz, ImVec2* out) const {
    const auto c = mat4_apply(v.world_to_clip, {float(wx), float(wy), float(wz), 1.0f});
    if (!(c[3] > 1e-9f)) return false;
    out->x = x + (0.5f * c[0] / c[3] + 0.5f) * w;
    out->y = y + (0.5f - 0.5f * c[1] / c[3]) * h;
    return true;
  }
  // The mouse ray hits the plane z = z0 at (*wx, *wy).
  bool to_plane(ImVec2 p, double z0, double* wx, double* wy) const {
    Vec3 na, fa;
    if (!screen_ray(v.world_to_clip, p.x, p.y, x, y, w, h, &na, &fa)) return false;
    const std::array<double, 3> a{na[0], na[1], na[2]}, b{fa[0], fa[1], fa[2]};
    const double dz = b[2] - a[2];
    const double t = std::abs(dz) > 1e-12 ? (z0 - a[2]) / dz : 0.0;
    *wx = a[0] + t * (b[0] - a[0]);
    *wy = a[1] + t * (b[1] - a[1]);
    return std::isfinite(*wx) && std::isfinite(*wy);
  }
};

struct Placement {
  bool present = false;
  double pos[3] = {0, 0, 0};
  double tilt_rad = 0;
  double radius = 0.05, height = 0.1, wall = 0.01;
  bool mesh = false;  // a mesh container: sized by its file (no size handle)
};

Placement placement(const json& scene, ContainerRole role, const LiquidContainerGeometry* g) {
  Placement p;
  if (!scene.contains(role) || !scene[role].is_object()) return p;
  const json& c = scene[role];
  p.present = true;
  const json pos = c.value("position_m", json::array());
  for (size_t i = 0; i < 3 && i < pos.size(); ++i) p.pos[i] = pos[i].is_number() ? pos[i].get<double>() : 0.0;
  p.tilt_rad = c.value("tilt_deg", 0.0) * 3.14159265358979 / 180.0;
  const json& shape = c.value("container", json());
  p.mesh = shape.is_object() && shape.value("shape", std::string()) == "mesh";
  if (shape.is_object() && !p.mesh) {
    p.radius = shape.value("radius_m", p.radius);
    p.height = shape.value("height_m", p.height);
    p.wall = shape.value("wall_m", p.wall);
  } else if (g && g->wall_sdf) {
    // A file container: its size from the compiled geometry's box.
    p.height = g->hi[1];
    p.radius = g->hi[0] - p.wall;
  }
  return p;
}

// Local (container frame) -> world: rotation by -tilt about z, then the position.
void local_to_world(const Placement& p, double lx, double ly, double* wx, double* wy) {
  const double c = std::cos(p.tilt_rad), s = std::sin(p.tilt_rad);
  *wx = c * lx + s * ly + p.pos[0];
  *wy = -s * lx + c * ly + p.pos[1];
}

void draw_outline(ImDrawList* dl, const ScreenMap& m, const Placement& p, const std::vector<LineSegment2>& section,
                  ImU32 col) {
  for (const LineSegment2& s : section) {
    double ax, ay, bx, by;
    local_to_world(p, s.ax, s.ay, &ax, &ay);
    local_to_world(p, s.bx, s.by, &bx, &by);
    ImVec2 a, b;
    if (m.to_screen(ax, ay, p.pos[2], &a) && m.to_screen(bx, by, p.pos[2], &b)) dl->AddLine(a, b, col, 1.0f);
  }
}


// Position (x, y, z) of key `i` of /source/trajectory.
bool key_position(const json& scene, int i, double out[3]) {
  const json& k = scene["source"]["trajectory"][size_t(i)];
  const json pos = k.value("position_m", json::array());
  if (!pos.is_array() || pos.size() < 2) return false;
  for (size_t a = 0; a < 3; ++a) out[a] = a < pos.size() && pos[a].is_number() ? pos[a].get<double>() : 0.0;
  return true;
}

void add_diamond(ImDrawList* dl, ImVec2 c, float r, ImU32 col) {
  dl->AddQuadFilled(ImVec2(c.x, c.y - r), ImVec2(c.x + r, c.y), ImVec2(c.x, c.y + r), ImVec2(c.x - r, c.y), col);
  dl->AddQuad(ImVec2(c.x, c.y - r - 1), ImVec2(c.x + r + 1, c.y), ImVec2(c.x, c.y + r + 1), ImVec2(c.x - r - 1, c.y),
              IM_COL32(20, 20, 20, 255));
}

void draw_path(ImDrawList* dl, const ScreenMap& m, const std::vector<Pose7>& path, ImU32 col, float thickness) {
  ImVec2 prev;
  bool have_prev = false;
  for (const Pose7& p : path) {
    ImVec2 q;
    const bool ok = m.to_screen(p[0], p[1], p[2], &q);
    if (ok && have_prev) dl->AddLine(prev, q, col, thickness);
    prev = q;
    have_prev = ok;
  }
}

}  // namespace

bool liquid_planned_path(App& app) {
  LiquidUiState& ui = liquid_ui(app);
  TakeReader* r = app.take.reader();
  const json* keys = r && r->manifest().metrics.is_object() && r->manifest().metrics.contains("trajectory")
                         ? &r->manifest().metrics["trajectory"]
                         : nullptr;
  if (!keys || !keys->is_array() || keys->empty()) {
    ui.plan_dir.clear();
    ui.plan_keys = json();
    ui.plan_path.clear();
    return false;
  }
  if (ui.plan_dir == app.take.dir() && ui.plan_keys == *keys) return !ui.plan_path.empty();
  ui.plan_dir = app.take.dir();
  ui.plan_keys = *keys;
  ui.plan_path.clear();
  // The engine's own curve: the take's scene with the planned keys, compiled.
  LiquidSceneGeometry g;
  std::string err;
  liquid_update_scene_dirs(app);
  if (liquid_scene_geometry(liquid_adopt_trajectory(r->manifest().scene, *keys), &g, &err)) ui.plan_path = g.source_path;
  else app.log.error("planned trajectory: " + err);
  return !ui.plan_path.empty();
}

void liquid_viewport_overlay(App& app, float x, float y, int w, int h) {
  const LiquidViewTransform& view = liquid_last_view();
  if (!view.valid || app.renderer.drawer_name() != "liquid" || w <= 0 || h <= 0) return;
  liquid_gizmos(app, view, x, y, w, h);
}

void liquid_gizmos(App& app, const LiquidViewTransform& view, float x, float y, int w, int h) {
  if (!view.valid || w <= 0 || h <= 0) return;
  LiquidUiState& ui = liquid_ui(app);
  const bool have_geo = liquid_doc_geometry(app);
  const ScreenMap m{view, x, y, float(w), float(h)};
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->PushClipRect(ImVec2(x, y), ImVec2(x + w, y + h), true);
  const json& scene = app.doc.scene();
  const ImGuiIO& io = ImGui::GetIO();
  const bool hovered_view = io.MousePos.x >= x && io.MousePos.x < x + w && io.MousePos.y >= y && io.MousePos.y < y + h &&
                            // The viewport's own button turns active on the same click.
                            ImGui::IsWindowHovered(ImGuiHoveredFlags_AllowWhenBlockedByActiveItem);

  struct HandleSpot {
    LiquidUiState::Handle kind;
    ContainerRole role;
    bool size;
    ImVec2 at;
    int key = -1;
  };
  std::vector<HandleSpot> spots;

  // The shown take's plan: its curve and keys (not editable: "Use plan" makes
  // them the scene's keys).
  if (liquid_planned_path(app)) {
    draw_path(dl, m, ui.plan_path, kPlanColor, 2.0f);
    for (size_t i = 0; i < ui.plan_keys.size(); ++i) {
      const json pos = ui.plan_keys[i].value("position_m", json::array());
      if (!pos.is_array() || pos.size() < 2) continue;
      ImVec2 c;
      if (!m.to_screen(pos[0].get<double>(), pos[1].get<double>(), pos.size() > 2 ? pos[2].get<double>() : 0.0, &c))
        continue;
      dl->AddCircleFilled(c, 4.0f, kPlanColor);
      ui_mark_rect("liquid_plan_key_" + std::to_string(i), c.x - 4, c.y - 4, c.x + 4, c.y + 4);
    }
  }
  // The document's hand-drawn keys: their curve and a handle per key.
  const int nkeys = int(liquid_key_times(scene).size());
  if (nkeys > 0) {
    if (have_geo) draw_path(dl, m, ui.geo.source_path, kKeyColor, 1.0f);
    for (int i = 0; i < nkeys; ++i) {
      double p[3];
      ImVec2 c;
      if (!key_position(scene, i, p) || !m.to_screen(p[0], p[1], p[2], &c)) continue;
      add_diamond(dl, c, kHandlePx - 1, i == ui.selected_key ? IM_COL32(255, 215, 100, 255) : kKeyColor);
      ui_mark_rect("liquid_key_pose_" + std::to_string(i), c.x - kHandlePx, c.y - kHandlePx, c.x + kHandlePx,
                   c.y + kHandlePx);
      spots.push_back({LiquidUiState::Handle::KeyPose, "source", false, c, i});
      // The selected key's tilt: a lever along the container's axis (local +y
      // turned by the tilt), dragged around the key.
      if (i != ui.selected_key) continue;
      const double tilt = scene["source"]["trajectory"][size_t(i)].value("tilt_deg", 0.0) * 3.14159265358979 / 180.0;
      const double len = 1.2 * placement(scene, "source", have_geo ? &ui.geo.source : nullptr).height;
      ImVec2 tip;
      if (!m.to_screen(p[0] + len * std::sin(tilt), p[1] + len * std::cos(tilt), p[2], &tip)) continue;
      dl->AddLine(c, tip, IM_COL32(255, 215, 100, 200), 1.5f);
      dl->AddCircleFilled(tip, kHandlePx - 2, IM_COL32(255, 215, 100, 255));
      ui_mark_rect("liquid_key_tilt", tip.x - kHandlePx, tip.y - kHandlePx, tip.x + kHandlePx, tip.y + kHandlePx);
      spots.insert(spots.begin(), HandleSpot{LiquidUiState::Handle::KeyTilt, "source", false, tip, i});
    }
  }

  // A moving target (target.velocity_mps): its origin's path over the run.
  if (scene.contains("target") && scene["target"].is_object() && scene["target"].contains("velocity_mps")) {
    const Placement t = placement(scene, "target", nullptr);
    const json v = scene["target"]["velocity_mps"];
    double vel[3] = {0, 0, 0};
    for (size_t a = 0; a < 3 && v.is_array() && a < v.size(); ++a) vel[a] = v[a].is_number() ? v[a].get<double>() : 0.0;
    const double T = liquid_duration_s(scene);
    ImVec2 a, b;
    if ((vel[0] != 0 || vel[1] != 0 || vel[2] != 0) && m.to_screen(t.pos[0], t.pos[1], t.pos[2], &a) &&
        m.to_screen(t.pos[0] + vel[0] * T, t.pos[1] + vel[1] * T, t.pos[2] + vel[2] * T, &b)) {
      dl->AddLine(a, b, IM_COL32(120, 230, 120, 160), 1.5f);
      dl->AddCircleFilled(b, 3.5f, IM_COL32(120, 230, 120, 200));
    }
  }

  for (ContainerRole role : {"source", "target"}) {
    const bool is_source = std::string(role) == "source";
    const LiquidContainerGeometry* g = have_geo ? (is_source ? &ui.geo.source : &ui.geo.target) : nullptr;
    const Placement p = placement(scene, role, g);
    if (!p.present) continue;
    const ImU32 col = is_source ? IM_COL32(235, 200, 90, 230) : IM_COL32(120, 230, 120, 230);
    if (have_geo && view.dim == 2) draw_outline(dl, m, p, is_source ? ui.source_section : ui.target_section, col);
    ImVec2 origin, corner;
    double cx, cy;
    local_to_world(p, p.radius + p.wall, p.height, &cx, &cy);
    if (!m.to_screen(p.pos[0], p.pos[1], p.pos[2], &origin) || !m.to_screen(cx, cy, p.pos[2], &corner)) continue;
    dl->AddCircleFilled(origin, kHandlePx, col);
    dl->AddCircle(origin, kHandlePx + 1, IM_COL32(20, 20, 20, 255));
    const std::string name = std::string("liquid_") + role;
    ui_mark_rect(name + "_move", origin.x - kHandlePx, origin.y - kHandlePx, origin.x + kHandlePx, origin.y + kHandlePx);
    spots.push_back({is_source ? LiquidUiState::Handle::MoveSource : LiquidUiState::Handle::MoveTarget, role, false, origin});
    if (p.mesh) continue;
    dl->AddRectFilled(ImVec2(corner.x - kHandlePx, corner.y - kHandlePx), ImVec2(corner.x + kHandlePx, corner.y + kHandlePx), col);
    ui_mark_rect(name + "_size", corner.x - kHandlePx, corner.y - kHandlePx, corner.x + kHandlePx, corner.y + kHandlePx);
    spots.push_back({is_source ? LiquidUiState::Handle::SizeSource : LiquidUiState::Handle::SizeTarget, role, true, corner});
  }
  dl->PopClipRect();

  // Start a drag on a handle (key handles first: a key often sits on the
  // source's origin); the viewport's own drag would orbit the 3D camera
  // meanwhile, so the camera is held where it was.
  if (ui.drag == LiquidUiState::Handle::None && hovered_view && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    for (const HandleSpot& s : spots) {
      if (std::hypot(io.MousePos.x - s.at.x, io.MousePos.y - s.at.y) > kHandlePx + 3) continue;
      json start = scene;
      std::string err;
      if (s.size && !liquid_container_is_inline(start, s.role) &&
          !liquid_inline_container(&start, s.role, app.doc.has_path() ? app.doc.path().parent_path() : std::filesystem::current_path(), &err)) {
        app.set_status(err, true);
        break;
      }
      double z = placement(start, s.role, nullptr).pos[2];
      if (s.key >= 0) {
        double p[3];
        if (key_position(start, s.key, p)) z = p[2];
      }
      double wx, wy;
      if (!m.to_plane(io.MousePos, z, &wx, &wy)) break;
      ui.drag = s.kind;
      ui.drag_key_index = s.key;
      if (s.key >= 0) ui.selected_key = s.key;
      ui.drag_z = z;
      ui.drag_scene = std::move(start);
      ui.drag_start[0] = wx;
      ui.drag_start[1] = wy;
      ui.drag_key = liquid_next_merge_key();
      ui.camera_at_drag = app.viewport.camera;
      break;
    }
  }
  if (ui.drag == LiquidUiState::Handle::None) return;
  app.viewport.camera = ui.camera_at_drag;
  const bool key = ui.drag == LiquidUiState::Handle::KeyPose || ui.drag == LiquidUiState::Handle::KeyTilt;
  const bool source = key || ui.drag == LiquidUiState::Handle::MoveSource || ui.drag == LiquidUiState::Handle::SizeSource;
  const bool size = ui.drag == LiquidUiState::Handle::SizeSource || ui.drag == LiquidUiState::Handle::SizeTarget;
  ContainerRole role = source ? "source" : "target";
  const Placement p0 = placement(ui.drag_scene, role, nullptr);
  double wx, wy;
  if (m.to_plane(io.MousePos, ui.drag_z, &wx, &wy)) {
    const double dx = wx - ui.drag_start[0], dy = wy - ui.drag_start[1];
    json next;
    std::string what;
    if (ui.drag == LiquidUiState::Handle::KeyTilt) {
      // The angle of (mouse - key) from +y, positive toward +x.
      double kp[3];
      if (key_position(ui.drag_scene, ui.drag_key_index, kp)) {
        const double deg = std::atan2(wx - kp[0], wy - kp[1]) * 180.0 / 3.14159265358979;
        next = liquid_set_key_tilt(ui.drag_scene, ui.drag_key_index, std::round(10.0 * deg) / 10.0);
      } else {
        next = ui.drag_scene;
      }
      what = "Tilt key pose " + std::to_string(ui.drag_key_index);
    } else if (key) {
      next = liquid_move_key_position(ui.drag_scene, ui.drag_key_index, dx, dy);
      what = "Move key pose " + std::to_string(ui.drag_key_index);
    } else if (size) {
      // The drag in the container's frame (undo the tilt).
      const double c = std::cos(p0.tilt_rad), s = std::sin(p0.tilt_rad);
      const double lx = c * dx - s * dy, ly = s * dx + c * dy;
      next = liquid_resize_container(ui.drag_scene, role, std::max(0.005, p0.radius + lx), std::max(0.01, p0.height + ly));
      what = std::string("Size ") + role;
    } else {
      next = liquid_move_container(ui.drag_scene, role, dx, dy);
      what = std::string("Move ") + role;
    }
    if (next != app.doc.scene()) app.doc.edit(what, std::move(next), ui.drag_key);
  }
  if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    ui.drag = LiquidUiState::Handle::None;
    ui.drag_key_index = -1;
    ui.drag_scene = json();
  }
}

}  // namespace pliant::editor
