// Liquid pouring scenes (issue 7): typed inspector widgets (containers from the
// library or edited inline, liquid, planner, simulation settings) and the
// jobs panel's Plan section with the in-target / spilled fractions over time.
// Gizmos: liquid_gizmos.cpp; key poses on the timeline: liquid_timeline.cpp.
#include <imgui.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>

#include "doc/liquid_scene_edit.h"
#include "ui/app.h"
#include "ui/json_widgets.h"
#include "ui/liquid_scene_geometry.h"
#include "ui/liquid_ui.h"
#include "ui/panel_window.h"

namespace pliant::editor {

using nlohmann::json;
namespace fs = std::filesystem;

LiquidUiState& liquid_ui(App& app) { return app.kind_ui.get<LiquidUiState>("liquid"); }

uint64_t liquid_next_merge_key() {
  static std::atomic<uint64_t> counter{0};
  return 0x4c49510000000000ull + (++counter);  // "LIQ" + drag number
}

void liquid_update_scene_dirs(App& app) {
  std::vector<fs::path> dirs;
  if (app.doc.has_path()) dirs.push_back(app.doc.path().parent_path());
  if (TakeReader* r = app.take.reader(); r && !r->manifest().scene_file.empty())
    dirs.push_back(fs::path(r->manifest().scene_file).parent_path());
  liquid_set_scene_dirs(std::move(dirs));
}

bool liquid_doc_geometry(App& app) {
  LiquidUiState& ui = liquid_ui(app);
  if (ui.geo_doc == app.doc.id() && ui.geo_revision == app.doc.revision()) return ui.geo_ok;
  ui.geo_doc = app.doc.id();
  ui.geo_revision = app.doc.revision();
  liquid_update_scene_dirs(app);
  std::string err;
  ui.geo_ok = liquid_scene_geometry(app.doc.scene(), &ui.geo, &err);
  ui.source_section.clear();
  ui.target_section.clear();
  if (ui.geo_ok && ui.geo.dim == 2) {
    if (ui.geo.has_source)
      ui.source_section = sdf_section_lines(ui.geo.source.wall_sdf, ui.geo.source.lo, ui.geo.source.hi, ui.geo.source.step);
    if (ui.geo.has_target)
      ui.target_section = sdf_section_lines(ui.geo.target.wall_sdf, ui.geo.target.lo, ui.geo.target.hi, ui.geo.target.step);
  }
  return ui.geo_ok;
}

namespace {

fs::path library_dir() {
#ifdef PLIANT_SOURCE_DIR
  return fs::path(PLIANT_SOURCE_DIR) / "assets" / "containers";
#else
  return "assets/containers";
#endif
}

// Container: a library file (copied inline, so the scene is self-contained and
// runs from wherever the job saves it) or the inline shape's own fields.
void container_section(App& app, ContainerRole role) {
  Document& doc = app.doc;
  const std::string base = std::string("/") + role;
  const json& scene = doc.scene();
  if (!scene.contains(role) || !scene[role].is_object()) {
    ImGui::TextDisabled("no %s", role);
    return;
  }
  ImGui::PushID(role);
  const json& c = scene[role].value("container", json());
  std::string current = c.is_string() ? fs::path(c.get<std::string>()).filename().string()
                        : c.is_object() ? "inline " + c.value("shape", std::string("?"))
                                        : "(none)";
  if (ImGui::BeginCombo("container", current.c_str())) {
    for (const fs::path& f : liquid_container_library(library_dir())) {
      if (!ImGui::Selectable(f.stem().string().c_str())) continue;
      json next = scene;
      next[role]["container"] = f.string();
      std::string err;
      if (liquid_inline_container(&next, role, "/", &err)) doc.edit(std::string("Container ") + f.stem().string(), next);
      else app.set_status(err, true);
    }
    ImGui::EndCombo();
  }
  ui_mark_field(base + "/container");
  if (c.is_string()) {
    ImGui::SameLine();
    if (ImGui::SmallButton("Edit inline")) {
      json next = scene;
      std::string err;
      if (liquid_inline_container(&next, role, doc.has_path() ? doc.path().parent_path() : fs::current_path(), &err))
        doc.edit("Inline container", next);
      else app.set_status(err, true);
    }
    ui_mark(base + "/inline");
  } else if (c.is_object() && c.value("shape", std::string()) == "mesh") {
    // A closed triangle mesh, sized by its file (and scale).
    const std::string p = base + "/container";
    ImGui::TextDisabled("mesh %s", fs::path(c.value("file", std::string())).filename().string().c_str());
    json_double(doc, "scale", p + "/scale", 1.0, 0.005f, 1e-3, 1e3, "%.3f");
  } else if (c.is_object()) {
    const std::string p = base + "/container";
    json_choice(doc, "shape", p + "/shape", "cylinder", {"cylinder", "oval", "box", "cup", "bottle"});
    json_double(doc, "radius (m)", p + "/radius_m", 0.05, 0.001f, 0.005, 1.0);
    json_double(doc, "height (m)", p + "/height_m", 0.12, 0.001f, 0.01, 2.0);
    json_double(doc, "wall (m)", p + "/wall_m", 0.02, 0.0005f, 0.001, 0.2);
    const std::string shape = c.value("shape", std::string("cylinder"));
    if (shape == "oval" || shape == "box") json_double(doc, "depth (m)", p + "/depth_m", 0.05, 0.001f, 0.005, 1.0);
    if (shape == "bottle") {
      json_double(doc, "neck radius (m)", p + "/neck_radius_m", 0.02, 0.001f, 0.003, 1.0);
      json_double(doc, "body height (m)", p + "/body_height_m", 0.12, 0.001f, 0.01, 2.0);
    }
  }
  json_vec(doc, "position (m)", base + "/position_m", liquid_dim(scene), 0.002f);
  if (std::string(role) == "source") json_double(doc, "tilt (deg)", base + "/tilt_deg", 0, 0.5f, -180, 180, "%.1f");
  else json_vec(doc, "velocity (m/s)", base + "/velocity_mps", liquid_dim(scene), 0.002f);
  ImGui::PopID();
}

void draw_inspector(App& app) {
  Document& doc = app.doc;
  const int dim = liquid_dim(doc.scene());
  liquid_update_scene_dirs(app);
  ImGui::Text("Liquid scene, %dD", dim);
  if (ImGui::CollapsingHeader("Source container", ImGuiTreeNodeFlags_DefaultOpen)) container_section(app, "source");
  if (ImGui::CollapsingHeader("Target container", ImGuiTreeNodeFlags_DefaultOpen)) container_section(app, "target");
  if (ImGui::CollapsingHeader("Liquid", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_double(doc, "fill", "/liquid/fill_fraction", 0.6, 0.005f, 0.0, 1.0, "%.2f");
    json_double(doc, "viscosity (Pa s)", "/liquid/viscosity_pa_s", 0.0, 0.0005f, 0.0, 100.0, "%.4g");
    json_double(doc, "density (kg/m3)", "/liquid/density_kg_per_m3", 1000, 1.0f, 1.0, 20000.0, "%.0f");
    json_int(doc, "particles per cell axis", "/liquid/particles_per_axis", 2, 1, 4);
    // Particle count follows from the cell size: show what it gives.
    const json& d = doc.scene().value("domain", json::object());
    const double h = d.value("cell_size_m", 0.02) / std::max(1, doc.scene().value("liquid", json::object()).value("particles_per_axis", 2));
    ImGui::TextDisabled("particle spacing %.1f mm", 1000 * h);
    json_int(doc, "seed", "/liquid/seed", 1, 0, 1 << 30);
  }
  if (ImGui::CollapsingHeader("Planner", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_choice(doc, "mode", "/planner/mode", "none", {"none", "correction", "simplified", "feedback"});
    const std::string mode = doc.scene().value("planner", json::object()).value("mode", std::string("none"));
    json_double(doc, "pour time (s)", "/planner/pour_time_s", 1.5, 0.01f, 0.05, 60.0, "%.2f");
    json_double(doc, "max tilt (deg)", "/planner/max_tilt_deg", 137.5, 0.5f, 10.0, 180.0, "%.1f");
    json_int(doc, "key poses", "/planner/keys", 6, 1, 30);
    if (mode == "correction") json_int(doc, "iterations", "/planner/iterations", 10, 1, 100);
    if (mode == "simplified") {
      json_int(doc, "generations", "/planner/generations", 100, 1, 10000);
      json_int(doc, "population", "/planner/population", 12, 2, 200);
      json_int(doc, "refine rounds", "/planner/refine_iterations", 3, 0, 50);
      json_bool(doc, "fit discharge Cd", "/planner/fit_discharge", true);
    }
    if (mode == "feedback") {
      json_double(doc, "interval (s)", "/planner/interval_s", 0.1, 0.005f, 0.01, 2.0, "%.3f");
      json_int(doc, "horizon", "/planner/horizon", 4, 1, 50);
    }
    if (mode != "none") json_int(doc, "planner seed", "/planner/seed", 1, 0, 1 << 30);
    else ImGui::TextDisabled("hand-drawn: key poses on the timeline");
  }
  if (ImGui::CollapsingHeader("Simulation")) {
    json_double(doc, "cell size (m)", "/domain/cell_size_m", 0.02, 0.0005f, 0.001, 1.0, "%.4f");
    json_vec(doc, "domain min (m)", "/domain/min_m", dim, 0.005f);
    json_vec(doc, "domain max (m)", "/domain/max_m", dim, 0.005f);
    json_int(doc, "frames", "/time/frames", 100, 1, 100000);
    json_double(doc, "dt (s)", "/time/dt_s", 0.02, 0.0005f, 0.001, 1.0, "%.4f");
    json_double(doc, "CFL (cells)", "/time/cfl", 1.0, 0.01f, 0.1, 10.0, "%.2f");
    json_int(doc, "max substeps", "/time/max_substeps", 64, 1, 10000);
    json_double(doc, "FLIP ratio", "/liquid/flip_ratio", 0.95, 0.005f, 0.0, 1.0, "%.2f");
    json_double(doc, "pressure tolerance", "/pressure/tolerance", 1e-5, 1e-7f, 1e-10, 1e-1, "%.1e");
  }
}

// Fractions per frame of the shown take, read incrementally as frames arrive.
void update_series(App& app, LiquidUiState& ui) {
  TakeReader* r = app.take.reader();
  if (!r) return;
  if (ui.series_dir != app.take.dir() || r->frame_count() < ui.series_frames) {
    ui.series_dir = app.take.dir();
    ui.series_frames = 0;
    ui.in_target.clear();
    ui.spilled.clear();
    ui.in_source.clear();
  }
  for (; ui.series_frames < r->frame_count(); ++ui.series_frames) {
    const Record rec = r->read_frame_at(ui.series_frames);
    const Field* f = rec.find("fractions");
    const bool ok = f && f->data.size() == 3;
    ui.in_target.push_back(ok ? f->data[0] : 0.0f);
    ui.spilled.push_back(ok ? f->data[1] : 0.0f);
    ui.in_source.push_back(ok ? f->data[2] : 0.0f);
  }
}

void draw_jobs(App& app) {
  Document& doc = app.doc;
  LiquidUiState& ui = liquid_ui(app);
  ImGui::TextUnformatted("Pouring");
  json_choice(doc, "planner", "/planner/mode", "none", {"none", "correction", "simplified", "feedback"});
  ui_mark("liquid_planner");
  const std::string mode = doc.scene().value("planner", json::object()).value("mode", std::string("none"));
  const bool busy = app.newest_job() && !app.newest_job()->snapshot().ended();
  if (busy) ImGui::BeginDisabled();
  if (ImGui::Button(mode == "none" ? "Simulate" : "Plan")) app.cmd_run();
  if (busy) ImGui::EndDisabled();
  ui_mark("liquid_plan");

  update_series(app, ui);
  if (!ui.in_target.empty()) {
    const int n = int(ui.in_target.size());
    // PlotLines takes no negative width (ImGui 1.86): the panel's width.
    const ImVec2 plot_size(std::max(60.0f, ImGui::GetContentRegionAvail().x), 48.0f);
    char label[96];
    std::snprintf(label, sizeof label, "in target %.1f%%", 100.0f * ui.in_target.back());
    ImGui::PlotLines("##in_target", ui.in_target.data(), n, 0, label, 0.0f, 1.0f, plot_size);
    ui_mark("liquid_fraction_plot");
    std::snprintf(label, sizeof label, "spilled %.1f%%", 100.0f * ui.spilled.back());
    ImGui::PlotLines("##spilled", ui.spilled.data(), n, 0, label, 0.0f, 1.0f, plot_size);
  }
  if (TakeReader* r = app.take.reader(); r && r->manifest().metrics.is_object() &&
                                         r->manifest().metrics.contains("fraction_in_target")) {
    const json& m = r->manifest().metrics;
    ImGui::Text("final: %.1f%% in target, %.1f%% spilled, %.1f%% left", 100 * m.value("fraction_in_target", 0.0),
                100 * m.value("fraction_spilled", 0.0), 100 * m.value("fraction_in_source", 0.0));
    ui_mark("liquid_final");
    if (m.contains("plan_s")) ImGui::TextDisabled("plan %.1f s", m.value("plan_s", 0.0));
  }
  ImGui::Separator();
}

// A dropped container file (a JSON object with "shape", not a scene) becomes
// the chosen container, inlined; a mesh file (.obj/.stl/.ply) a mesh container
// (one undo step each). Scenes and takes are left to the generic handling.
bool on_drop(App& app, const std::string& path) {
  const fs::path p(path);
  ContainerRole role = liquid_ui(app).drop_to_target ? "target" : "source";
  // A closed triangle mesh (engine: {"shape": "mesh", "file": ...}, relative
  // to the scene's folder when it has one).
  if (liquid_is_mesh_file(p)) {
    std::string file = fs::absolute(p).lexically_normal().string();
    if (app.doc.has_path()) {
      const fs::path rel = fs::absolute(p).lexically_normal().lexically_relative(
          fs::absolute(app.doc.path()).parent_path().lexically_normal());
      if (!rel.empty()) file = rel.generic_string();
    }
    app.doc.edit(std::string("Drop ") + role + " mesh container", liquid_set_mesh_container(app.doc.scene(), role, file));
    app.set_status(std::string("Mesh container ") + p.filename().string() + " -> " + role);
    return true;
  }
  if (p.extension() != ".json") return false;
  std::ifstream in(p);
  if (!in) return false;
  const json j = json::parse(in, nullptr, /*allow_exceptions=*/false, /*ignore_comments=*/true);
  if (j.is_discarded() || !j.is_object() || j.contains("pliant") || !j.contains("shape")) return false;
  json next = app.doc.scene();
  if (!next.contains(role) || !next[role].is_object()) {
    json zero = json::array();
    for (int i = 0; i < liquid_dim(next); ++i) zero.push_back(0.0);
    next[role] = {{"position_m", zero}};
  }
  next[role]["container"] = fs::absolute(p).string();
  std::string err;
  if (!liquid_inline_container(&next, role, "/", &err)) {
    app.set_status(err, true);
    return true;
  }
  app.doc.edit(std::string("Drop ") + role + " container", std::move(next));
  app.set_status(std::string("Container ") + p.filename().string() + " -> " + role);
  return true;
}

}  // namespace

// Viewport toolbar: where a dropped container file goes; "Place" shows the
// placement view over a result; "Use plan" makes the shown take's planned
// key poses the scene's hand-drawn ones (planner none), to edit them.
void liquid_viewport_toolbar(App& app) {
  LiquidUiState& ui = liquid_ui(app);
  ImGui::TextDisabled("drop container on:");
  ImGui::SameLine();
  if (ImGui::RadioButton("source", !ui.drop_to_target)) ui.drop_to_target = false;
  ui_mark("liquid_drop_source");
  ImGui::SameLine();
  if (ImGui::RadioButton("target", ui.drop_to_target)) ui.drop_to_target = true;
  ui_mark("liquid_drop_target");
  if (app.take.frame_count() > 0) {
    ImGui::SameLine();
    if (ImGui::Checkbox("Place", &ui.place_mode)) app.viewport.drawn_state.clear();
    ui_mark("liquid_place");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("show the scene's start (containers, liquid, key poses) instead of the take");
  }
  if (liquid_planned_path(app)) {
    ImGui::SameLine();
    if (ImGui::SmallButton("Use plan")) {
      const json next = liquid_adopt_trajectory(app.doc.scene(), ui.plan_keys);
      if (next != app.doc.scene()) {
        app.doc.edit("Use planned trajectory", next);
        app.set_status("The planned key poses are the scene's now (planner: none)");
      }
    }
    ui_mark("liquid_use_plan");
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("make the planned key poses (magenta) the scene's trajectory, planner none, to edit them");
  }
}

const KindPanels& liquid_panels() {
  static const KindPanels p = [] {
    KindPanels k;
    k.kind = "liquid";
    k.inspector = &draw_inspector;
    k.typed_keys = {"dim", "domain", "time", "liquid", "source", "target", "planner", "pressure"};
    k.jobs = &draw_jobs;
    k.viewport_toolbar = &liquid_viewport_toolbar;
    k.viewport_editor = &liquid_placement_view;
    k.viewport_overlay = &liquid_viewport_overlay;
    k.on_drop = &on_drop;
    k.timeline = &liquid_timeline;
    return k;
  }();
  return p;
}

}  // namespace pliant::editor
