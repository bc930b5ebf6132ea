// Keyframe canvas (2D smoke): toolbar (slot, tools, brush size and hardness,
// text, import, clear, onion skin) and the paintable grid. The composite shows
// the slot in white over the previous keyframe (blue) and the next (orange).
#include "ui/keyframe_canvas.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "pliant/geom/coverage_image.h"
#include "pliant/geom/raster_grid.h"
#include "ui/app.h"
#include "ui/keyframe_slices.h"
#include "ui/panel_window.h"

namespace pliant::editor {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const char* kToolNames[] = {"Brush", "Eraser", "Fill", "Ellipse", "Rectangle", "Move", "Text"};

fs::path scene_dir(const App& app) {
  return app.doc.has_path() ? app.doc.path().parent_path() : fs::current_path();
}

std::string slot_label(int slot, const json& scene) {
  if (slot == kInitialDensitySlot) return "Initial density";
  for (const auto& k : list_keyframes(scene))
    if (k.index == slot) return "Keyframe " + std::to_string(k.frame);
  return "Keyframe ?";
}

}  // namespace

void upload_composite_texture(unsigned* texture, const geom::PaintedGrid& g, const geom::PaintedGrid* onion_prev,
                              const geom::PaintedGrid* onion_next) {
  const int w = g.n[0], h = g.n[1];
  std::vector<uint8_t> rgba(size_t(w) * h * 4);
  const bool prev = onion_prev && onion_prev->cells() == g.cells();
  const bool next = onion_next && onion_next->cells() == g.cells();
  for (size_t c = 0; c < g.cells(); ++c) {
    float r = 0.10f, gr = 0.11f, b = 0.14f;
    if (prev) {
      const float a = 0.35f * onion_prev->value[c] / 255.0f;
      r += a * (0.3f - r), gr += a * (0.55f - gr), b += a * (1.0f - b);
    }
    if (next) {
      const float a = 0.35f * onion_next->value[c] / 255.0f;
      r += a * (1.0f - r), gr += a * (0.6f - gr), b += a * (0.2f - b);
    }
    const float v = g.value[c] / 255.0f;
    r += v * (1 - r), gr += v * (1 - gr), b += v * (1 - b);
    rgba[c * 4 + 0] = uint8_t(std::lround(r * 255));
    rgba[c * 4 + 1] = uint8_t(std::lround(gr * 255));
    rgba[c * 4 + 2] = uint8_t(std::lround(b * 255));
    rgba[c * 4 + 3] = 255;
  }
  if (!*texture) glGenTextures(1, texture);
  glBindTexture(GL_TEXTURE_2D, *texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glBindTexture(GL_TEXTURE_2D, 0);
}

// The neighbouring slots in frame order (initial density first).
void keyframe_neighbours(const json& scene, int slot, int* prev, int* next) {
  std::vector<int> order{kInitialDensitySlot};
  auto ks = list_keyframes(scene);
  std::stable_sort(ks.begin(), ks.end(), [](const auto& a, const auto& b) { return a.frame < b.frame; });
  for (const auto& k : ks) order.push_back(k.index);
  *prev = *next = -99;
  for (size_t i = 0; i < order.size(); ++i)
    if (order[i] == slot) {
      if (i > 0) *prev = order[i - 1];
      if (i + 1 < order.size()) *next = order[i + 1];
    }
}


int canvas_current_frame(App& app) {
  if (app.take.frame_count() > 0) return app.take.frame;
  return app.canvas.edit_frame;
}

void keep_canvas_slot_valid(KeyframeCanvasState& s, const json& scene) {
  if (s.slot != kInitialDensitySlot) {
    bool found = false;
    for (const auto& k : list_keyframes(scene)) found |= k.index == s.slot;
    if (!found) s.slot = kInitialDensitySlot;
  }
}

void refresh_canvas_cache(App& app) {
  KeyframeCanvasState& s = app.canvas;
  const json& scene = app.doc.scene();
  keep_canvas_slot_valid(s, scene);
  if (s.cached_revision == app.doc.revision() && s.cached_slot == s.slot) return;
  s.cached_revision = app.doc.revision();
  s.cached_slot = s.slot;
  const fs::path dir = scene_dir(app);
  s.grid = rasterize_slot(scene, dir, s.slot, &s.error);
  int p, n;
  keyframe_neighbours(scene, s.slot, &p, &n);
  std::string ignored;
  s.onion_prev = p != -99 ? rasterize_slot(scene, dir, p, &ignored) : geom::PaintedGrid{};
  s.onion_next = n != -99 ? rasterize_slot(scene, dir, n, &ignored) : geom::PaintedGrid{};
  if (!s.stroking) s.working = s.grid;
}

void commit_canvas(App& app, const geom::PaintedGrid& g, const std::string& what) {
  KeyframeCanvasState& s = app.canvas;
  const std::string label = what + " (" + slot_label(s.slot, app.doc.scene()) + ")";
  app.doc.edit(label, with_painted_slot(app.doc.scene(), s.slot, g));
  app.set_status(label);
}

bool stamp_canvas_text(App& app, geom::PaintedGrid& g, double x, double y) {
  KeyframeCanvasState& s = app.canvas;
  try {
    fs::path font = s.font[0] ? fs::path(s.font) : geom::default_font_path(scene_dir(app));
    geom::CoverageImage img = geom::render_text(s.text, font, font.string(), 128);
    stamp_coverage(g, img, x, y, std::max(1.0, double(s.text_height) * g.n[1]));
    return true;
  } catch (const std::exception& e) {
    app.set_status(std::string("Text: ") + e.what(), true);
    app.log.error(app.status());
    return false;
  }
}

bool import_image_keyframe(App& app, const std::string& path, bool new_keyframe) {
  const json& scene = app.doc.scene();
  const auto res = smoke_resolution(scene);
  if (res[0] <= 0) {
    app.set_status("Image import needs a 2D smoke scene", true);
    app.log.error(app.status());
    return false;
  }
  geom::CoverageImage img;
  try {
    img = geom::load_coverage_image(path, path, geom::ImageChannel::Luma);
  } catch (const std::exception& e) {
    app.set_status(std::string("Import failed: ") + e.what(), true);
    app.log.error(app.status());
    return false;
  }
  json s = scene;
  if (new_keyframe || !has_control(s)) {
    int idx = 0;
    s = with_keyframe_added(s, std::max(1, canvas_current_frame(app)), &idx);
    app.canvas.slot = idx;
  }
  geom::PaintedGrid g = make_painted_grid(res[0], res[1]);
  // Fit 80% of the grid, keeping the image's aspect ratio.
  const double h = std::min(0.8 * res[1], 0.8 * res[0] * img.height / std::max(1, img.width));
  stamp_coverage(g, img, 0.5 * res[0], 0.5 * res[1], h);
  s = with_painted_slot(s, app.canvas.slot, g);
  const std::string label = "Import image " + fs::path(path).filename().string() + " (" +
                            slot_label(app.canvas.slot, s) + ")";
  app.doc.edit(label, std::move(s));
  app.set_status(label);
  app.log.info(label);
  app.viewport.show_canvas = true;
  return true;
}

bool import_mesh_keyframe(App& app, const std::string& path) {
  const json& scene = app.doc.scene();
  const json& r = is_smoke_scene(scene) && scene.contains("grid") ? scene["grid"].value("resolution", json())
                                                                  : json();
  if (!r.is_array() || r.size() != 3) {
    app.set_status("Mesh import needs a 3D smoke scene (grid.resolution with 3 entries)", true);
    app.log.error(app.status());
    return false;
  }
  // Relative to the scene when it has a file (portable scenes), else absolute.
  fs::path file = fs::absolute(path);
  if (app.doc.has_path()) file = fs::relative(file, app.doc.path().parent_path());
  json target = {{"type", "mesh"}, {"file", file.string()}, {"center", {0.5, 0.5, 0.5}}, {"size", 0.5}};
  json s = scene;
  if (!s.contains("control") || !s["control"].is_object()) {
    s["control"] = default_control_section();
    s["control"]["initial_density"] =
        json::array({{{"type", "sphere"}, {"center", {0.5, 0.3, 0.5}}, {"radius", 0.15}}});
  }
  int frame = std::clamp(canvas_current_frame(app), 1, std::max(1, smoke_frames(s)));
  int idx = keyframe_at_frame(s, frame);
  if (idx < 0) {
    s["control"]["keyframes"].push_back({{"frame", frame}, {"target", target}});
    idx = int(s["control"]["keyframes"].size()) - 1;
    auto& ks = s["control"]["keyframes"];
    std::stable_sort(ks.begin(), ks.end(),
                     [](const json& a, const json& b) { return a.value("frame", 0) < b.value("frame", 0); });
    idx = keyframe_at_frame(s, frame);
  } else {
    s["control"]["keyframes"][idx]["target"] = target;
  }
  const std::string label = "Import mesh " + fs::path(path).filename().string() + " (keyframe " +
                            std::to_string(frame) + ")";
  app.doc.edit(label, std::move(s));
  app.canvas.slot = idx;
  app.set_status(label);
  app.log.info(label);
  return true;
}

void release_canvas_gl(KeyframeCanvasState& s) {
  if (s.texture) glDeleteTextures(1, &s.texture);
  if (s.slice_texture) glDeleteTextures(1, &s.slice_texture);
  s.texture = s.slice_texture = 0;
  if (s.volume_view) release_volume_view(*s.volume_view);
  s.volume_view.reset();
}

void draw_strength_slider(KeyframeCanvasState& s) {
  ImGui::SetNextItemWidth(70);
  ImGui::SliderFloat("strength", &s.strength, 0.0f, 1.0f, "%.2f");
  ui_mark("tool_strength");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("density the tools paint: the brush raises cells to it, Fill / Ellipse / Rectangle "
                      "set cells to it, the eraser removes this fraction");
}

void draw_keyframe_canvas(App& app) {
  KeyframeCanvasState& s = app.canvas;
  const json& scene = app.doc.scene();
  refresh_canvas_cache(app);

  // Row 1 (after the Result/Keyframes switch): slot, onion skin, whole-keyframe edits.
  ImGui::SetNextItemWidth(150);
  if (ImGui::BeginCombo("##slot", slot_label(s.slot, scene).c_str())) {
    if (ImGui::Selectable("Initial density", s.slot == kInitialDensitySlot)) s.slot = kInitialDensitySlot;
    ui_mark("slot_initial");
    for (const auto& k : list_keyframes(scene)) {
      std::string l = "Keyframe " + std::to_string(k.frame) + "##" + std::to_string(k.index);
      if (ImGui::Selectable(l.c_str(), s.slot == k.index)) s.slot = k.index;
      ui_mark("slot_" + std::to_string(k.frame));
    }
    ImGui::EndCombo();
  }
  ui_mark("canvas_slot");
  ImGui::SameLine();
  ImGui::Checkbox("onion", &s.onion);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("previous keyframe in blue, next in orange");
  ImGui::SameLine();
  if (ImGui::Button("Clear")) commit_canvas(app, make_painted_grid(s.grid.n[0], s.grid.n[1]), "Clear");
  ui_mark("canvas_clear");
  ImGui::SameLine();
  if (ImGui::Button("Grow")) commit_canvas(app, transform_grid(s.grid, 0, 0, 1.1), "Scale 110%");
  ImGui::SameLine();
  if (ImGui::Button("Shrink")) commit_canvas(app, transform_grid(s.grid, 0, 0, 1.0 / 1.1), "Scale 91%");
  // Row 2: tools and the brush.
  for (int t = 0; t < 7; ++t) {
    if (t) ImGui::SameLine();
    if (ImGui::RadioButton(kToolNames[t], s.tool == CanvasTool(t))) s.tool = CanvasTool(t);
    ui_mark(std::string("tool_") + kToolNames[t]);
  }
  // Row 2: tool options.
  ImGui::SetNextItemWidth(110);
  ImGui::SliderFloat("size", &s.radius_cells, 0.5f, 32.0f, "%.1f cells", ImGuiSliderFlags_Logarithmic);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(80);
  ImGui::SliderFloat("hardness", &s.hardness, 0.0f, 1.0f, "%.2f");
  ImGui::SameLine();
  draw_strength_slider(s);
  ImGui::SameLine();
  if (s.tool == CanvasTool::Text) {
    ImGui::SetNextItemWidth(70);
    ImGui::InputText("text", s.text, sizeof s.text);
    ui_mark("canvas_text");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(70);
    ImGui::SliderFloat("height", &s.text_height, 0.05f, 1.0f, "%.2f");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("letter height as a fraction of the domain; click the canvas to place");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(90);
    ImGui::InputTextWithHint("font", "DejaVu Sans Bold (shipped)", s.font, sizeof s.font);
  } else {
    ImGui::SetNextItemWidth(150);
    ImGui::InputTextWithHint("##import", "image file, or drop one", s.import_path,
                             sizeof s.import_path);
    ui_mark("canvas_import_path");
    ImGui::SameLine();
    if (ImGui::Button("Import")) import_image_keyframe(app, s.import_path, false);
    ui_mark("canvas_import");
  }
  if (!s.error.empty()) ImGui::TextColored(kWarnColor, "%s", s.error.c_str());

  const int nx = s.grid.n[0], ny = s.grid.n[1];
  if (nx <= 0 || ny <= 0 || s.grid.cells() == 0) {
    ImGui::TextDisabled("No grid to paint on (set grid.resolution)");
    return;
  }
  // The canvas rectangle: the grid's aspect fitted into the remaining region.
  ImVec2 avail = ImGui::GetContentRegionAvail();
  avail.x = std::max(avail.x, 16.0f);
  avail.y = std::max(avail.y, 16.0f);
  const float cell = std::min(avail.x / nx, avail.y / ny);
  const ImVec2 size(cell * nx, cell * ny);
  ImVec2 p0 = ImGui::GetCursorScreenPos();
  p0.x += 0.5f * (avail.x - size.x);
  ImGui::SetCursorScreenPos(p0);
  ImGui::InvisibleButton("keyframe_canvas", size, ImGuiButtonFlags_MouseButtonLeft);
  ui_mark("keyframe_canvas");
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  const ImGuiIO& io = ImGui::GetIO();
  const double mx = (io.MousePos.x - p0.x) / cell, my = (p1.y - io.MousePos.y) / cell;  // cells, +y up

  const Brush brush{s.radius_cells, s.hardness, s.tool == CanvasTool::Eraser, s.strength};
  const uint8_t shape_value = strength_byte(s.strength);
  if (ImGui::IsItemActivated()) {
    s.stroking = true;
    s.working = s.grid;
    s.start_x = s.last_x = mx;
    s.start_y = s.last_y = my;
    if (s.tool == CanvasTool::Brush || s.tool == CanvasTool::Eraser) paint_dab(s.working, mx, my, brush);
  } else if (s.stroking && ImGui::IsItemActive()) {
    switch (s.tool) {
      case CanvasTool::Brush:
      case CanvasTool::Eraser:
        if (mx != s.last_x || my != s.last_y) paint_segment(s.working, s.last_x, s.last_y, mx, my, brush);
        break;
      case CanvasTool::Ellipse:
        s.working = s.grid;
        fill_ellipse(s.working, s.start_x, s.start_y, mx, my, shape_value);
        break;
      case CanvasTool::Rectangle:
        s.working = s.grid;
        fill_rectangle(s.working, s.start_x, s.start_y, mx, my, shape_value);
        break;
      case CanvasTool::Move:
        s.working = transform_grid(s.grid, mx - s.start_x, my - s.start_y, 1.0);
        break;
      default:
        break;
    }
    s.last_x = mx;
    s.last_y = my;
  }
  if (s.stroking && ImGui::IsItemDeactivated()) {
    s.stroking = false;
    switch (s.tool) {
      case CanvasTool::Brush: commit_canvas(app, s.working, "Brush stroke"); break;
      case CanvasTool::Eraser: commit_canvas(app, s.working, "Eraser stroke"); break;
      case CanvasTool::Ellipse: commit_canvas(app, s.working, "Ellipse"); break;
      case CanvasTool::Rectangle: commit_canvas(app, s.working, "Rectangle"); break;
      case CanvasTool::Move: commit_canvas(app, s.working, "Move"); break;
      case CanvasTool::Fill: {
        geom::PaintedGrid g = s.grid;
        fill_region(g, int(std::floor(s.start_x)), int(std::floor(s.start_y)), shape_value);
        commit_canvas(app, g, "Fill");
        break;
      }
      case CanvasTool::Text: {
        geom::PaintedGrid g = s.grid;
        if (stamp_canvas_text(app, g, s.start_x, s.start_y)) commit_canvas(app, g, std::string("Text \"") + s.text + "\"");
        break;
      }
      case CanvasTool::Gizmo:  // 3D mesh keyframes only (keyframe_slices.cpp)
        break;
    }
  }
  if (ImGui::IsItemHovered() && s.tool == CanvasTool::Move && io.MouseWheel != 0)
    commit_canvas(app, transform_grid(s.grid, 0, 0, io.MouseWheel > 0 ? 1.1 : 1.0 / 1.1), "Scale");

  ImDrawList* dl = ImGui::GetWindowDrawList();
  if (app.has_gl()) {
    refresh_canvas_cache(app);  // a stroke committed above changed the document
    const std::array<uint64_t, 3> key{app.doc.revision(), uint64_t(int64_t(s.slot)), uint64_t(s.onion)};
    if (s.stroking || key != s.texture_key || !s.texture) {
      upload_composite_texture(&s.texture, s.stroking ? s.working : s.grid, s.onion ? &s.onion_prev : nullptr,
                               s.onion ? &s.onion_next : nullptr);
      // After a stroke the working copy was shown: upload the committed grid next frame.
      s.texture_key = s.stroking ? std::array<uint64_t, 3>{~0ull, 0, 0} : key;
    }
    // Row 0 of the grid is the bottom: flip v.
    dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(s.texture)), p0, p1, ImVec2(0, 1),
                 ImVec2(1, 0));
  }
  dl->AddRect(p0, p1, IM_COL32(190, 195, 210, 200));
  if (ImGui::IsItemHovered() && (s.tool == CanvasTool::Brush || s.tool == CanvasTool::Eraser))
    dl->AddCircle(io.MousePos, s.radius_cells * cell, IM_COL32(255, 200, 80, 200), 32);
  std::string caption = slot_label(s.slot, scene) + "  " + std::to_string(nx) + "x" + std::to_string(ny) +
                        "  " + std::to_string(painted_cell_count(s.stroking ? s.working : s.grid)) + " cells painted";
  dl->AddText(ImVec2(p0.x + 6, p0.y + 4), IM_COL32(220, 220, 230, 255), caption.c_str());
}

}  // namespace pliant::editor
