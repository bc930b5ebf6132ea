// 3D smoke keyframes: the selected slot (a keyframe or the initial density) as a
// volume painted one slice at a time, in the XY, XZ or YZ orientation
// (doc/volume_slice.h), with the 2D canvas tools (doc/paint_ops on the slice,
// written back into the volume: one Document::edit per stroke), the
// previous/next keyframes' same slice as onion skin, and the ray-marched volume
// beside it (keyframe_slices_volume.cpp). Mesh keyframes get a gizmo: drag the
// centre to move in the slice plane, the square handle to scale, the round one
// (XY slices) to rotate about z; one undo step per drag, and the slice shows the
// engine's voxelisation of the new placement afterwards. Painting on any non-painted slot
// bakes its voxelisation into a painted volume (stored inline, bit-exact).
#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "ui/app.h"
#include "ui/keyframe_canvas.h"
#include "ui/keyframe_slices.h"
#include "ui/panel_window.h"

namespace pliant::editor {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const char* kTools3d[] = {"Brush", "Eraser", "Fill", "Ellipse", "Rectangle"};

fs::path scene_dir(const App& app) {
  return app.doc.has_path() ? app.doc.path().parent_path() : fs::current_path();
}

std::string slot_label(const json& scene, int slot) {
  if (slot == kInitialDensitySlot) return "Initial density";
  for (const auto& k : list_keyframes(scene))
    if (k.index == slot) return "Keyframe " + std::to_string(k.frame) + " (" + k.type + ")";
  return "Keyframe ?";
}

// Re-rasterises the slot and its neighbours when the document or the slot changed.
void refresh_volume(App& app) {
  KeyframeCanvasState& s = app.canvas;
  const json& scene = app.doc.scene();
  keep_canvas_slot_valid(s, scene);
  if (s.volume_revision == app.doc.revision() && s.volume_slot == s.slot) return;
  if (s.volume_slot != s.slot && is_mesh_slot(scene, s.slot)) s.tool = CanvasTool::Gizmo;  // opens with its gizmo
  s.volume_revision = app.doc.revision();
  s.volume_slot = s.slot;
  const fs::path dir = scene_dir(app);
  s.vol = rasterize_slot_volume(scene, dir, s.slot, &s.error);
  s.volume_dims = s.vol.cells() ? s.vol.n : std::array<int, 3>{0, 0, 0};
  s.volume.resize(s.vol.cells());
  for (size_t c = 0; c < s.vol.cells(); ++c) s.volume[c] = s.vol.value[c] / 255.0f;
  int p, n;
  keyframe_neighbours(scene, s.slot, &p, &n);
  std::string ignored;
  s.vol_prev = p != -99 ? rasterize_slot_volume(scene, dir, p, &ignored) : geom::PaintedGrid{};
  s.vol_next = n != -99 ? rasterize_slot_volume(scene, dir, n, &ignored) : geom::PaintedGrid{};
  if (s.vol.cells()) {
    int* idx[3] = {&s.slice_x, &s.slice_y, &s.slice};  // by normal axis x, y, z
    for (int a = 0; a < 3; ++a)
      if (*idx[a] < 0 || *idx[a] >= s.vol.n[a]) *idx[a] = s.vol.n[a] / 2;
  }
  ++s.volume_version;
}

void commit_volume(App& app, const geom::PaintedGrid& v, const std::string& what) {
  KeyframeCanvasState& s = app.canvas;
  const std::string label = what + " (" + slot_label(app.doc.scene(), s.slot) + ", " +
                            slice_normal_name(s.slice_axis) + " " + std::to_string(current_slice(s)) + ")";
  app.doc.edit(label, with_painted_volume_slot(app.doc.scene(), s.slot, v));
  app.set_status(label);
}

// The mesh's footprint half size in slice cells (the target's "size" is a fraction
// of the smallest domain extent, or metres in "size_m").
double mesh_half_cells(const json& scene, int slot, const MeshTransform& t) {
  const json target = slot_target(scene, slot);
  const auto n = smoke_resolution_3d(scene);
  const int min_n = std::min({n[0], n[1], n[2]});
  double size_cells = 0.6 * min_n;
  if (target.value("size", json()).is_number()) size_cells = target["size"].get<double>() * min_n;
  const double h = scene.contains("grid") ? scene["grid"].value("cell_size_m", 0.0) : 0.0;
  if (target.value("size_m", json()).is_number() && h > 0) size_cells = target["size_m"].get<double>() / h;
  return std::max(1.0, 0.5 * size_cells * t.scale);
}

struct GizmoPoints {
  ImVec2 centre, scale_handle, rotate_handle, corners[4];
};

// The footprint square is drawn turned by the in-slice angle of the placement
// (gizmo_footprint_deg; exactly rotation_deg on XY for z-only scenes).
GizmoPoints gizmo_points(const MeshTransform& t, double half, const std::array<int, 3>& n, SliceAxis axis, ImVec2 p0,
                         ImVec2 p1, float cell) {
  auto to_screen = [&](double cx, double cy) { return ImVec2(p0.x + float(cx) * cell, p1.y - float(cy) * cell); };
  const auto c = mesh_centre_in_slice(t, n, axis);
  const double cx = c[0], cy = c[1];
  const double deg = gizmo_footprint_deg(t, axis);
  const double a = deg * 3.14159265358979323846 / 180.0, ca = std::cos(a), sa = std::sin(a);
  auto rot = [&](double x, double y) { return to_screen(cx + ca * x - sa * y, cy + sa * x + ca * y); };
  GizmoPoints g;
  g.centre = to_screen(cx, cy);
  g.scale_handle = rot(half, -half);
  g.rotate_handle = rot(0, half + std::max(1.5, 0.35 * half));
  const double xs[4] = {-half, half, half, -half}, ys[4] = {-half, -half, half, half};
  for (int i = 0; i < 4; ++i) g.corners[i] = rot(xs[i], ys[i]);
  return g;
}

float dist(ImVec2 a, ImVec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

// Slot, onion skin, whole-slot edits; orientation, slice slider, strength; tools; the mesh fields.
void draw_toolbar(App& app, bool mesh) {
  KeyframeCanvasState& s = app.canvas;
  const json& scene = app.doc.scene();
  ImGui::SetNextItemWidth(190);
  if (ImGui::BeginCombo("##slot3d", slot_label(scene, s.slot).c_str())) {
    if (ImGui::Selectable("Initial density", s.slot == kInitialDensitySlot)) s.slot = kInitialDensitySlot;
    ui_mark("slot_initial");
    for (const auto& k : list_keyframes(scene)) {
      std::string l = "Keyframe " + std::to_string(k.frame) + " (" + k.type + ")##" + std::to_string(k.index);
      if (ImGui::Selectable(l.c_str(), s.slot == k.index)) s.slot = k.index;
      ui_mark("slot_" + std::to_string(k.frame));
    }
    ImGui::EndCombo();
  }
  ui_mark("slice_slot");
  ImGui::SameLine();
  ImGui::Checkbox("onion", &s.onion);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("previous keyframe's slice in blue, next in orange");
  ImGui::SameLine();
  if (ImGui::Button("Clear slice") && s.vol.cells()) {
    geom::PaintedGrid v = s.vol;
    const auto wh = slice_size(v.n, s.slice_axis);
    set_volume_slice(v, s.slice_axis, current_slice(s), make_painted_grid(wh[0], wh[1]));
    commit_volume(app, v, "Clear slice");
  }
  ui_mark("slice_clear");
  ImGui::SameLine();
  if (ImGui::Button("Clear all") && s.vol.cells())
    commit_volume(app, make_painted_volume(s.vol.n[0], s.vol.n[1], s.vol.n[2]), "Clear");
  ui_mark("slice_clear_all");
  // Row 2: orientation (front XY, top XZ, right side YZ), its own slice slider,
  // and the strength of the painting tools.
  for (SliceAxis a : {SliceAxis::XY, SliceAxis::XZ, SliceAxis::YZ}) {
    if (a != SliceAxis::XY) ImGui::SameLine();
    if (ImGui::RadioButton(slice_axis_name(a), s.slice_axis == a)) s.slice_axis = a;
    ui_mark(std::string("slice_axis_") + slice_axis_name(a));
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(a == SliceAxis::XY   ? "front view (from +z): x right, y up"
                        : a == SliceAxis::XZ ? "top view (from +y): x right, z towards the bottom"
                                             : "side view (from +x): z towards the left, y up");
  }
  if (s.vol.cells()) {
    ImGui::SameLine();
    ImGui::SetNextItemWidth(150);
    const std::string n = slice_normal_name(s.slice_axis);
    ImGui::SliderInt((n + " slice").c_str(), &current_slice(s), 0, slice_count(s.vol.n, s.slice_axis) - 1);
    ui_mark("slice_" + n);
  }
  ImGui::SameLine();
  draw_strength_slider(s);
  // Row 3: tools (Gizmo for mesh keyframes) and their options.
  if (!mesh && s.tool == CanvasTool::Gizmo) s.tool = CanvasTool::Brush;
  if (s.tool == CanvasTool::Move || s.tool == CanvasTool::Text) s.tool = CanvasTool::Brush;
  if (mesh) {
    if (ImGui::RadioButton("Gizmo", s.tool == CanvasTool::Gizmo)) s.tool = CanvasTool::Gizmo;
    ui_mark("tool_Gizmo");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("drag the centre to move, the square to scale, the circle to rotate about the slice's normal");
    ImGui::SameLine();
  }
  for (int t = 0; t < 5; ++t) {
    if (t || mesh) ImGui::SameLine();
    if (ImGui::RadioButton(kTools3d[t], s.tool == CanvasTool(t))) s.tool = CanvasTool(t);
    ui_mark(std::string("tool_") + kTools3d[t]);
    if (mesh && ImGui::IsItemHovered()) ImGui::SetTooltip("painting bakes the voxelised mesh into a painted volume");
  }
  ImGui::SameLine();
  ImGui::SetNextItemWidth(100);
  ImGui::SliderFloat("size", &s.radius_cells, 0.5f, 32.0f, "%.1f cells", ImGuiSliderFlags_Logarithmic);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(70);
  ImGui::SliderFloat("hardness", &s.hardness, 0.0f, 1.0f, "%.2f");
  if (mesh) {
    // The transform as numbers; a drag of a field previews in gizmo_now and is one
    // undo step on release.
    const MeshTransform t = s.gizmo != GizmoHandle::None ? s.gizmo_now : mesh_transform(scene, s.slot);
    float c[3] = {float(t.center[0]), float(t.center[1]), float(t.center[2])};
    float sc = float(t.scale), rot = float(t.rotation_deg);
    bool changed = false;
    ImGui::SetNextItemWidth(200);
    changed |= ImGui::DragFloat3("center", c, 0.005f, -1.0f, 2.0f, "%.3f");
    const bool done1 = ImGui::IsItemDeactivatedAfterEdit();
    ui_mark("mesh_center");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(70);
    changed |= ImGui::DragFloat("scale", &sc, 0.01f, 0.02f, 50.0f, "%.2f");
    const bool done2 = ImGui::IsItemDeactivatedAfterEdit();
    ImGui::SameLine();
    ImGui::SetNextItemWidth(70);
    changed |= ImGui::DragFloat("rotation", &rot, 1.0f, -180.0f, 180.0f, "%.0f deg");
    const bool done3 = ImGui::IsItemDeactivatedAfterEdit();
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("degrees about the axis [%.3g, %.3g, %.3g] (right-handed); the gizmo's circle turns about the slice's normal",
                        t.rotation_axis[0], t.rotation_axis[1], t.rotation_axis[2]);
    if (changed && (s.gizmo == GizmoHandle::None || s.gizmo == GizmoHandle::Fields)) {
      s.gizmo = GizmoHandle::Fields;
      s.gizmo_now = t;
      s.gizmo_now.center = {c[0], c[1], c[2]};
      s.gizmo_now.scale = std::max(0.02f, sc);
      s.gizmo_now.rotation_deg = rot;
    }
    if ((done1 || done2 || done3) && s.gizmo == GizmoHandle::Fields) {
      s.gizmo = GizmoHandle::None;
      const std::string label = "Mesh transform (" + slot_label(scene, s.slot) + ")";
      app.doc.edit(label, with_mesh_transform(scene, s.slot, s.gizmo_now));
      app.set_status(label);
    }
  }
  if (!s.error.empty()) ImGui::TextColored(kWarnColor, "%s", s.error.c_str());
}

}  // namespace

void draw_keyframe_slices(App& app) {
  KeyframeCanvasState& s = app.canvas;
  const json& scene = app.doc.scene();
  if (!has_control(scene)) {
    ImGui::TextDisabled("No keyframe control in this scene (Jobs > Keyframe solve > Add keyframe control)");
    return;
  }
  refresh_volume(app);
  const bool mesh = is_mesh_slot(scene, s.slot);
  draw_toolbar(app, mesh);
  const auto n = s.vol.n;
  if (s.vol.cells() == 0) return;
  const SliceAxis axis = s.slice_axis;
  const int k = current_slice(s);
  const auto wh = slice_size(n, axis);
  const int nx = wh[0], ny = wh[1];  // the slice's cells (u right, v up)

  // Slice on the left, volume on the right, both as tall as fits.
  ImVec2 avail = ImGui::GetContentRegionAvail();
  avail.x = std::max(avail.x, 32.0f);
  avail.y = std::max(avail.y, 16.0f);
  const float cell = std::max(1.0f, std::min(0.5f * avail.x / nx, avail.y / ny));
  const ImVec2 size(cell * nx, cell * ny);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const ImVec2 p0(origin.x + 0.5f * (0.5f * avail.x - size.x), origin.y);
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  ImGui::SetCursorScreenPos(p0);
  ImGui::InvisibleButton("slice_view", size, ImGuiButtonFlags_MouseButtonLeft);
  ui_mark("slice_view");
  const ImGuiIO& io = ImGui::GetIO();
  const double mx = (io.MousePos.x - p0.x) / cell, my = (p1.y - io.MousePos.y) / cell;  // cells, +y up

  // Mesh gizmo: move, scale and rotate (about the slice's normal) on every orientation.
  const bool gizmo_tool = mesh && s.tool == CanvasTool::Gizmo;
  const MeshTransform committed = mesh ? mesh_transform(scene, s.slot) : MeshTransform{};
  const MeshTransform& shown_t = s.gizmo != GizmoHandle::None ? s.gizmo_now : committed;
  const double half = mesh ? mesh_half_cells(scene, s.slot, shown_t) : 0.0;
  if (gizmo_tool && ImGui::IsItemActivated()) {
    const GizmoPoints g = gizmo_points(committed, mesh_half_cells(scene, s.slot, committed), n, axis, p0, p1, cell);
    const float pick = std::max(8.0f, 0.6f * cell);
    s.gizmo = dist(io.MousePos, g.scale_handle) < pick                   ? GizmoHandle::Scale
              : dist(io.MousePos, g.rotate_handle) < pick ? GizmoHandle::Rotate
                                                           : GizmoHandle::Move;
    s.gizmo_start = s.gizmo_now = committed;
    s.start_x = mx;
    s.start_y = my;
  } else if (s.gizmo != GizmoHandle::None && s.gizmo != GizmoHandle::Fields && ImGui::IsItemActive()) {
    switch (s.gizmo) {
      case GizmoHandle::Move: s.gizmo_now = gizmo_move(s.gizmo_start, mx - s.start_x, my - s.start_y, n, axis); break;
      case GizmoHandle::Scale: s.gizmo_now = gizmo_scale(s.gizmo_start, s.start_x, s.start_y, mx, my, n, axis); break;
      case GizmoHandle::Rotate: s.gizmo_now = gizmo_rotate(s.gizmo_start, s.start_x, s.start_y, mx, my, n, axis); break;
      default: break;
    }
  }
  if (s.gizmo != GizmoHandle::None && s.gizmo != GizmoHandle::Fields && ImGui::IsItemDeactivated()) {
    const char* what = s.gizmo == GizmoHandle::Move ? "Move mesh" : s.gizmo == GizmoHandle::Scale ? "Scale mesh" : "Rotate mesh";
    s.gizmo = GizmoHandle::None;
    const std::string label = std::string(what) + " (" + slot_label(scene, s.slot) + ")";
    if (s.gizmo_now.center != s.gizmo_start.center || s.gizmo_now.scale != s.gizmo_start.scale ||
        s.gizmo_now.rotation_deg != s.gizmo_start.rotation_deg ||
        s.gizmo_now.rotation_axis != s.gizmo_start.rotation_axis) {
      app.doc.edit(label, with_mesh_transform(scene, s.slot, s.gizmo_now));
      app.set_status(label);
    }
  }

  // Painting on the slice: the 2D tools on a copy of slice k.
  const Brush brush{s.radius_cells, s.hardness, s.tool == CanvasTool::Eraser, s.strength};
  const uint8_t shape_value = strength_byte(s.strength);
  if (!gizmo_tool) {
    if (ImGui::IsItemActivated()) {
      s.stroking = true;
      s.working = volume_slice(s.vol, axis, k);
      s.start_x = s.last_x = mx;
      s.start_y = s.last_y = my;
      if (s.tool == CanvasTool::Brush || s.tool == CanvasTool::Eraser) paint_dab(s.working, mx, my, brush);
      ++s.volume_version;
    } else if (s.stroking && ImGui::IsItemActive()) {
      const bool moved = mx != s.last_x || my != s.last_y;
      if ((s.tool == CanvasTool::Brush || s.tool == CanvasTool::Eraser) && moved) {
        paint_segment(s.working, s.last_x, s.last_y, mx, my, brush);
      } else if ((s.tool == CanvasTool::Ellipse || s.tool == CanvasTool::Rectangle) && moved) {
        s.working = volume_slice(s.vol, axis, k);
        if (s.tool == CanvasTool::Ellipse) fill_ellipse(s.working, s.start_x, s.start_y, mx, my, shape_value);
        else fill_rectangle(s.working, s.start_x, s.start_y, mx, my, shape_value);
      }
      if (moved) ++s.volume_version;
      s.last_x = mx;
      s.last_y = my;
    }
    if (s.stroking && ImGui::IsItemDeactivated()) {
      s.stroking = false;
      geom::PaintedGrid v = s.vol;
      if (s.tool == CanvasTool::Fill) {
        geom::PaintedGrid sl = volume_slice(v, axis, k);
        fill_region(sl, int(std::floor(s.start_x)), int(std::floor(s.start_y)), shape_value);
        set_volume_slice(v, axis, k, sl);
      } else {
        set_volume_slice(v, axis, k, s.working);
      }
      const char* what[] = {"Brush stroke", "Eraser stroke", "Fill", "Ellipse", "Rectangle"};
      commit_volume(app, v, what[std::clamp(int(s.tool), 0, 4)]);
      refresh_volume(app);
    }
  }

  ImDrawList* dl = ImGui::GetWindowDrawList();
  // The slice composite (the stroke in progress while painting) over the onion skin.
  if (app.has_gl()) {
    const std::array<uint64_t, 2> key{s.volume_version, (uint64_t(k) * 3 + uint64_t(axis)) * 2 + uint64_t(s.onion)};
    if (key != s.slice_key || !s.slice_texture) {
      const geom::PaintedGrid shown = s.stroking ? s.working : volume_slice(s.vol, axis, k);
      geom::PaintedGrid prev, next;
      if (s.onion && s.vol_prev.n == n) prev = volume_slice(s.vol_prev, axis, k);
      if (s.onion && s.vol_next.n == n) next = volume_slice(s.vol_next, axis, k);
      upload_composite_texture(&s.slice_texture, shown, prev.cells() ? &prev : nullptr,
                               next.cells() ? &next : nullptr);
      s.slice_key = key;
    }
    dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(s.slice_texture)), p0, p1, ImVec2(0, 1),
                 ImVec2(1, 0));
  }
  dl->AddRect(p0, p1, IM_COL32(190, 195, 210, 200));
  if (ImGui::IsItemHovered() && !gizmo_tool && (s.tool == CanvasTool::Brush || s.tool == CanvasTool::Eraser))
    dl->AddCircle(io.MousePos, s.radius_cells * cell, IM_COL32(255, 200, 80, 200), 32);
  if (mesh) {
    const GizmoPoints g = gizmo_points(shown_t, half, n, axis, p0, p1, cell);
    const ImU32 col = gizmo_tool ? IM_COL32(90, 200, 255, 230) : IM_COL32(90, 200, 255, 110);
    dl->AddPolyline(g.corners, 4, col, ImDrawFlags_Closed, 1.5f);
    dl->AddCircleFilled(g.centre, 5.0f, col);
    dl->AddRectFilled(ImVec2(g.scale_handle.x - 5, g.scale_handle.y - 5),
                      ImVec2(g.scale_handle.x + 5, g.scale_handle.y + 5), col);
    dl->AddLine(g.centre, g.rotate_handle, col, 1.0f);
    dl->AddCircle(g.rotate_handle, 6.0f, col, 16, 2.0f);
  }
  const std::string caption = slot_label(scene, s.slot) + "  " + slice_normal_name(axis) + " " + std::to_string(k) +
                              "/" + std::to_string(slice_count(n, axis)) + "  " + std::to_string(n[0]) + "x" +
                              std::to_string(n[1]) + "x" + std::to_string(n[2]);
  dl->AddText(ImVec2(p0.x + 6, p0.y + 4), IM_COL32(220, 220, 230, 255), caption.c_str());
  if (axis != SliceAxis::XY) {  // which world axes the slice's edges are
    const char* right = axis == SliceAxis::XZ ? "+x" : "-z";
    const char* up = axis == SliceAxis::XZ ? "-z" : "+y";
    auto label = [&](ImVec2 at, const char* t) {  // on a dark box: readable over painted density
      const ImVec2 ts = ImGui::CalcTextSize(t);
      dl->AddRectFilled(ImVec2(at.x - 2, at.y - 1), ImVec2(at.x + ts.x + 2, at.y + ts.y + 1), IM_COL32(20, 22, 30, 200));
      dl->AddText(at, IM_COL32(220, 220, 230, 255), t);
    };
    const ImVec2 ts = ImGui::CalcTextSize("-z");
    label(ImVec2(p1.x - ts.x - 4, p1.y - ts.y - 3), right);
    label(ImVec2(p0.x + 4, p0.y + 4 + ts.y + 4), up);
  }

  // The volume view to the right of the slice.
  if (!s.volume_view) s.volume_view = std::make_shared<KeyframeVolumeView>();
  const float vx = origin.x + 0.5f * avail.x + 4.0f;
  const int vw = int(0.5f * avail.x - 4.0f), vh = int(std::max(size.y, std::min(avail.y, 0.5f * avail.x)));
  geom::PaintedGrid shown_vol;
  const geom::PaintedGrid* vol = &s.vol;
  if (s.stroking) {
    shown_vol = s.vol;
    set_volume_slice(shown_vol, axis, k, s.working);
    vol = &shown_vol;
  }
  draw_keyframe_volume(*s.volume_view, app, *vol, s.volume_version, axis, k, vx, origin.y, vw, vh);
}

}  // namespace pliant::editor
