// Soft character scenes (issue 5, "Editor: character workflow"): the inspector's
// typed widgets (mesh, lattice, modes, material, ground or water, objectives
// with weights, optimizer, frames, dt), the Optimize section of the jobs panel
// with the live objective plot, the realtime playback line and pin markers
// under the timeline, and the hand-over of take data (frame 0's triangles, the
// COM trail) to the soft drawer. The Character edit mode is in
// soft_character_view.cpp, the gizmos in soft_gizmos.cpp.
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

#include "doc/soft_scene.h"
#include "render/soft_drawer.h"
#include "ui/app.h"
#include "ui/json_widgets.h"
#include "ui/panel_window.h"
#include "ui/soft_ui.h"

#ifdef PLIANT_HAVE_SOFT
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"
#endif

namespace pliant::editor {

using nlohmann::json;
namespace fs = std::filesystem;

SoftUi::~SoftUi() = default;  // GL names are freed with the context (GLVND no-ops without one)

SoftUi& soft_ui(App& app) { return app.kind_ui.get<SoftUi>("soft"); }

bool soft_character_shown(App& app) {
  const SoftUi& ui = soft_ui(app);
  return !ui.gl_failed && (ui.character_mode || app.take.dir().empty());
}

namespace {

bool has_object(const json& s, const char* a, const char* b = nullptr) {
  if (!s.is_object() || !s.contains(a) || !s[a].is_object()) return false;
  return !b || (s[a].contains(b) && s[a][b].is_object());
}

// An objective term with a checkbox that adds it (with defaults) or removes it.
bool objective_toggle(Document& doc, const char* name, const json& defaults, const char* help) {
  const json& s = doc.scene();
  bool on = has_object(s, "objectives", name);
  const bool was = on;
  if (ImGui::Checkbox(name, &on)) {
    json next = s;
    if (!next.contains("objectives") || !next["objectives"].is_object()) next["objectives"] = json::object();
    if (on) next["objectives"][name] = defaults;
    else next["objectives"].erase(name);
    doc.edit(std::string(on ? "Add " : "Remove ") + name + " objective", std::move(next));
  }
  ui_mark(std::string("objective_") + name);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", help);
  return was && on;
}

void draw_objectives(App& app) {
  Document& doc = app.doc;
  const std::string o = "/objectives/";
  ImGui::PushID("objectives");
  if (objective_toggle(doc, "velocity", {{"target_m_per_s", {0.2, 0, 0}}, {"weight", 10}},
                       "walk or swim at this centre-of-mass velocity")) {
    json_vec(doc, "target_m_per_s", o + "velocity/target_m_per_s", 3);
    json_double(doc, "weight##velocity", o + "velocity/weight", 1, 0.05f, 0, 1e6);
  }
  if (objective_toggle(doc, "position", {{"target_m", {0.5, 0.1, 0}}, {"weight", 1}},
                       "reach this point at the end of the horizon (drag the green handle)")) {
    json_vec(doc, "target_m", o + "position/target_m", 3);
    json_double(doc, "weight##position", o + "position/weight", 1, 0.05f, 0, 1e6);
  }
  if (objective_toggle(doc, "heading", {{"body_axis", {1, 0, 0}}, {"direction", {1, 0, 0}}, {"weight", 1}},
                       "keep a body axis pointing along a direction (drag the blue arrow)")) {
    json_vec(doc, "body_axis", o + "heading/body_axis", 3);
    json_vec(doc, "direction", o + "heading/direction", 3);
    json_double(doc, "weight##heading", o + "heading/weight", 1, 0.05f, 0, 1e6);
  }
  if (objective_toggle(doc, "upright", {{"body_axis", {0, 1, 0}}, {"weight", 10}},
                       "keep a body axis (the one pointing up at rest) pointing up over the horizon: "
                       "heading holds one axis, so a swimmer may roll about it; the take reports "
                       "final_tilt_deg / max_tilt_deg")) {
    json_vec(doc, "body_axis##upright", o + "upright/body_axis", 3);
    json_double(doc, "weight##upright", o + "upright/weight", 1, 0.05f, 0, 1e6);
  }
  if (objective_toggle(doc, "course", {{"direction", {1, 0, 0}}, {"weight", 10}},
                       "keep the centre of mass on the straight line along a direction")) {
    json_vec(doc, "direction##course", o + "course/direction", 3);
    json_double(doc, "weight##course", o + "course/weight", 10, 0.05f, 0, 1e6);
  }
  // Defaults when added: spider_walk.json's weight 5 (engine/soft/README.md: larger
  // weights and a periodicity weight were worse there); absent keys show the engine's.
  if (objective_toggle(doc, "steady",
                       {{"body_axis", {1, 0, 0}}, {"direction", {1, 0, 0}}, {"periods", 1}, {"weight", 5},
                        {"periodicity_weight", 0}},
                       "hold a steady straight gait at the end of the horizon: over its last controller "
                       "periods, penalize the body axis' yaw rate and the centre of mass velocity across "
                       "the direction (the replay after the horizon repeats the last period, so a gait "
                       "still turning there keeps turning)")) {
    json_vec(doc, "body_axis##steady", o + "steady/body_axis", 3);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("the body axis whose yaw rate (about +y) is held at zero");
    json_vec(doc, "direction##steady", o + "steady/direction", 3);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("ground direction: the COM velocity across it is held at zero");
    json_int(doc, "periods##steady", o + "steady/periods", 1, 1, 100);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("controller periods at the end of the horizon the term covers (with periodicity, twice "
                        "that must fit in optimizer.horizon_frames)");
    json_double(doc, "weight##steady", o + "steady/weight", 1, 0.05f, 0, 1e6);
    json_double(doc, "periodicity_weight##steady", o + "steady/periodicity_weight", 0, 0.05f, 0, 1e6);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("also penalize the change of the horizontal COM velocity and of the yaw rate from the "
                        "window before (0: off)");
  }
  if (objective_toggle(doc, "jump", {{"height_m", 0.1}, {"weight", 100}},
                       "raise the centre of mass by this height (drag the pink handle)")) {
    json_double(doc, "height_m", o + "jump/height_m", 0.1, 0.002f, 0, 1e3);
    json_double(doc, "weight##jump", o + "jump/weight", 1, 0.05f, 0, 1e6);
  }
  if (objective_toggle(doc, "distance", {{"distance_m", 0.5}, {"direction", {1, 0, 0}}, {"weight", 1}},
                       "travel this far along a direction")) {
    json_double(doc, "distance_m", o + "distance/distance_m", 0.5, 0.01f, -1e4, 1e4);
    json_vec(doc, "direction##distance", o + "distance/direction", 3);
    json_double(doc, "weight##distance", o + "distance/weight", 1, 0.05f, 0, 1e6);
  }
  if (objective_toggle(doc, "shuffle", {{"weight", 1}}, "penalize feet sliding on the ground"))
    json_double(doc, "weight##shuffle", o + "shuffle/weight", 1, 0.05f, 0, 1e6);
  if (objective_toggle(doc, "effort", {{"weight", 1e-3}}, "penalize control effort"))
    json_double(doc, "weight##effort", o + "effort/weight", 1e-3, 1e-4f, 0, 1e6, "%.2e");
  if (objective_toggle(doc, "keyframes", {{"weight", 10}, {"frames", json::array()}},
                       "pinned surface vertices at frames (Character mode: click a vertex)")) {
    json_double(doc, "weight##keyframes", o + "keyframes/weight", 10, 0.05f, 0, 1e6);
    const std::vector<SoftPin> pins = soft_pins(doc.scene());
    int remove = -1;
    for (size_t i = 0; i < pins.size(); ++i) {
      const SoftPin& p = pins[i];
      ImGui::PushID(int(i));
      ImGui::Text("frame %d  vertex %d  offset (%.3f, %.3f, %.3f)", p.frame, p.vertex, p.offset[0], p.offset[1],
                  p.offset[2]);
      ImGui::SameLine();
      if (ImGui::SmallButton("Unpin")) remove = int(i);
      ui_mark("unpin_" + std::to_string(i));
      ImGui::PopID();
    }
    if (remove >= 0)
      doc.edit("Unpin vertex " + std::to_string(pins[size_t(remove)].vertex),
               soft_without_pin(doc.scene(), pins[size_t(remove)].frame, pins[size_t(remove)].vertex));
    if (pins.empty()) ImGui::TextDisabled("no pins: Character mode, click a vertex");
  }
  ImGui::PopID();
}

void draw_soft_inspector(App& app) {
  Document& doc = app.doc;
  if (ImGui::CollapsingHeader("Character", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_text(doc, "mesh", "/character/mesh");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("OBJ, PLY, STL, glTF, FBX or DAE, relative to the scene file");
    json_double(doc, "scale", "/character/scale", 1.0, 0.01f, 1e-6, 1e6);
    json_int(doc, "lattice resolution", "/character/resolution", 8, 2, 64);
    json_int(doc, "modes", "/character/modes", 10, 1, 60);
    json_choice(doc, "basis", "/character/basis", "linear", {"linear", "pod", "rotation_strain"});
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("linear modes; POD of simulated poses; or rotation-strain coordinates (large bends)");
    json_int(doc, "modal derivatives", "/character/modal_derivatives", 0, 0, 8);
    json_bool(doc, "cubature", "/character/cubature", true);
  }
  if (ImGui::CollapsingHeader("Material", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_double(doc, "density_kg_per_m3", "/material/density_kg_per_m3", 1000, 10.0f, 1, 1e5);
    json_double(doc, "young_pa", "/material/young_pa", 1e5, 1000.0f, 1, 1e12, "%.3g");
    json_double(doc, "poisson", "/material/poisson", 0.3, 0.005f, 0, 0.49);
  }
  if (ImGui::CollapsingHeader("Environment", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_choice(doc, "type", "/environment/type", "ground", {"ground", "water"});
    const bool water = soft_scene_info(doc.scene()).water;
    if (water) {
      json_double(doc, "fluid_density", "/environment/fluid_density_kg_per_m3", 1000, 10.0f, 0, 1e5);
      json_double(doc, "drag_coefficient", "/environment/drag_coefficient", 1, 0.01f, 0, 100);
      json_double(doc, "skin_coefficient", "/environment/skin_coefficient", 0.02, 0.001f, 0, 100);
    } else {
      json_double(doc, "friction", "/environment/friction", 0.8, 0.01f, 0, 10);
      json_double(doc, "ground_height_m", "/environment/ground_height_m", 0, 0.005f, -1e3, 1e3);
    }
  }
  if (ImGui::CollapsingHeader("Simulation", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_double(doc, "dt_s", "/simulation/dt_s", 1.0 / 30, 0.001f, 1e-5, 0.2);
    json_int(doc, "frames", "/simulation/frames", 100, 1, 100000);
    json_vec(doc, "start_offset_m", "/simulation/start_offset_m", 3);
  }
  if (ImGui::CollapsingHeader("Controller", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_int(doc, "controlled modes", "/controller/modes", 4, 0, 60);
    json_int(doc, "kernels", "/controller/kernels", 4, 1, 64);
    json_double(doc, "period_s", "/controller/period_s", 0.5, 0.01f, 1e-3, 1e3);
    json_double(doc, "max_activation_rel", "/controller/max_activation_rel", 0.8, 0.01f, 1e-3, 10);
  }
  if (ImGui::CollapsingHeader("Objectives", ImGuiTreeNodeFlags_DefaultOpen)) draw_objectives(app);
  if (ImGui::CollapsingHeader("Optimizer", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_choice(doc, "method", "/optimizer/method", "hybrid", {"hybrid", "lm", "lbfgs", "spacetime", "none"});
    json_int(doc, "iterations", "/optimizer/iterations", 20, 0, 100000);
    json_int(doc, "horizon_frames", "/optimizer/horizon_frames", 60, 1, 100000);
    json_double(doc, "fd_step", "/optimizer/fd_step", 1e-3, 1e-5f, 1e-12, 1, "%.1e");
    json_double(doc, "tolerance", "/optimizer/tolerance", 1e-6, 1e-7f, 0, 1, "%.1e");
    // Pure L-BFGS's variant (soft_compile.cpp; soft_worm_crawl.json pins it).
    const json& sc = doc.scene();
    const json* opt = sc.is_object() && sc.contains("optimizer") ? &sc["optimizer"] : nullptr;
    if (opt && opt->is_object() && opt->value("method", std::string("hybrid")) == "lbfgs") {
      json_choice(doc, "lbfgs_line_search", "/optimizer/lbfgs_line_search", "armijo",
                  {"armijo", "wolfe", "strong_wolfe", "bracketing", "nocedal_wright"});
      json_int(doc, "lbfgs_memory", "/optimizer/lbfgs_memory", 8, 1, 1000);
      json_double(doc, "lbfgs_initial_step (0: raw gradient)", "/optimizer/lbfgs_initial_step", 1.0, 0.01f, 0, 1e12);
      json_int(doc, "lbfgs_restarts", "/optimizer/lbfgs_restarts", 0, 0, 1000);
    }
  }
}

// Frame 0's triangles and vertices and the COM of every frame of a soft take,
// for the drawer; only new frames are read as the take grows. Returns true when
// the data changed (the viewport then uploads its frame again: it may have been
// drawn as points before the triangles were known).
bool sync_take_data(App& app, TakeReader* rd, const std::string& dir, size_t n, SoftUi::TakeSync& sync) {
  if (!rd || rd->manifest().kind != "soft" || n == 0) return false;
  if (sync.dir != dir) {
    sync = SoftUi::TakeSync{};
    sync.dir = dir;
  }
  if (sync.frames == n) return false;
  try {
    for (size_t i = sync.frames; i < n; ++i) {
      const Record r = rd->read_frame_at(i);
      if (i == 0) {
        const Field* v = r.find("vertices");
        const Field* t = r.find("triangles");
        if (v) sync.data.rest_vertices = v->data;
        if (t)
          for (float x : t->data) sync.data.triangles.push_back(uint32_t(std::max(0.0f, x)));
      }
      const Field* c = r.find("com");
      if (!c || c->data.size() != 3 || r.index < 0) break;
      const std::array<float, 3> com{c->data[0], c->data[1], c->data[2]};
      if (size_t(r.index) >= sync.data.com.size()) sync.data.com.resize(size_t(r.index) + 1, com);
      sync.data.com[size_t(r.index)] = com;
    }
  } catch (const std::exception& e) {
    app.log.error(std::string("soft take: ") + e.what());
  }
  sync.frames = n;
  soft_drawer_set_take_data(soft_scene_key(rd->manifest().scene), sync.data);
  return true;
}

void sync_takes(App& app) {
  SoftUi& ui = soft_ui(app);
  const bool first = ui.shown.frames == 0 || ui.shown.dir != app.take.dir().string();
  if (sync_take_data(app, app.take.reader(), app.take.dir().string(), size_t(app.take.frame_count()), ui.shown)) {
    app.viewport.shown_frame = -1;  // upload again with the triangles and trail
    if (first) app.renderer.reset_framing();  // frame again now that the start and the goal are known
  }
  if (app.compare.enabled && app.compare.reader &&
      sync_take_data(app, app.compare.reader.get(), app.compare.dir.string(), app.compare.reader->frame_count(),
                     ui.compared))
    app.compare.shown_frame = -1;
}

void draw_soft_jobs(App& app) {
  sync_takes(app);
  if (!ImGui::CollapsingHeader("Character optimization", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::PushID("soft_jobs");
  const SoftSceneInfo info = soft_scene_info(app.doc.scene());
  const json& opt = app.doc.scene().contains("optimizer") ? app.doc.scene()["optimizer"] : json::object();
  ImGui::TextDisabled("%s, %d iterations over %d frames; then %d frames (%.1f s)",
                      opt.is_object() ? opt.value("method", std::string("hybrid")).c_str() : "hybrid",
                      opt.is_object() ? opt.value("iterations", 20) : 20, info.horizon, info.frames,
                      info.frames * info.dt_s);
  JobProcess* job = app.newest_job();
  const JobStatus st = job ? job->snapshot() : JobStatus{};
  const bool running = job && !st.ended();
  const bool valid = app.scene_error().empty();
  if (!valid || running) ImGui::BeginDisabled();
  if (ImGui::Button("Optimize")) app.cmd_run();
  if (!valid || running) ImGui::EndDisabled();
  ui_mark("soft_optimize");
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip("optimize the controller for the objectives, then simulate all frames (pliant run)");
  ImGui::SameLine();
  if (!running) ImGui::BeginDisabled();
  if (ImGui::Button("Cancel##soft")) app.cmd_cancel(app.jobs.size() - 1);
  if (!running) ImGui::EndDisabled();
  if (job && !st.objective.empty()) {
    std::vector<float> lg;
    for (float v : st.objective) lg.push_back(std::log10(std::max(v, 1e-30f)));
    char ov[96];
    std::snprintf(ov, sizeof ov, "objective %.4g (log), %zu iterations", double(st.objective.back()),
                  st.objective.size() - 1);
    ImGui::SetNextItemWidth(-1);
    ImGui::PlotLines("##soft_objective", lg.data(), int(lg.size()), 0, ov, FLT_MAX, FLT_MAX, ImVec2(0, 48));
    ui_mark("soft_objective_plot");
  }
  if (TakeReader* rd = app.take.reader(); rd && rd->manifest().kind == "soft") {
    const json& m = rd->manifest().metrics;
    if (m.is_object() && m.contains("objective_final")) {
      ImGui::Text("objective %.3g -> %.3g; travelled %.3f m; playback %.0f fps",
                  m.value("objective_initial", 0.0), m.value("objective_final", 0.0), m.value("distance_m", 0.0),
                  m.value("playback_fps", 0.0));
      ui_mark("soft_metrics");
    }
  }
  ImGui::Separator();
  ImGui::PopID();
}

// Under the frame slider: realtime playback (fps = 1 / dt of the take) and the
// frames with pinned vertices.
void draw_soft_timeline(App& app) {
  TakeView& t = app.take;
  double dt = soft_scene_info(app.doc.scene()).dt_s;
  if (TakeReader* rd = t.reader(); rd && rd->manifest().kind == "soft") dt = soft_scene_info(rd->manifest().scene).dt_s;
  const float realtime_fps = float(1.0 / std::max(dt, 1e-6));
  draw_soft_live_controls(app);
  if (soft_ui(app).live.on) return;  // the take's playback controls do not apply
  if (ImGui::SmallButton("Realtime")) t.fps = realtime_fps;
  ui_mark("soft_realtime");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("play the take at 1/dt = %.1f fps (the character's own speed)", realtime_fps);
  ImGui::SameLine();
  // What playback actually reaches: frames shown per second of wall time.
  static int last_frame = -1;
  static double speed = 0;
  static auto last = std::chrono::steady_clock::now();
  static int frames_seen = 0;
  if (t.frame != last_frame) {
    ++frames_seen;
    last_frame = t.frame;
  }
  const auto now = std::chrono::steady_clock::now();
  const double el = std::chrono::duration<double>(now - last).count();
  if (el > 0.5) {
    speed = frames_seen / el * dt;
    frames_seen = 0;
    last = now;
  }
  ImGui::TextDisabled("playback %.0f fps = %.2fx realtime (dt %.4f s)%s", t.fps, t.fps * dt, dt,
                      t.playing ? "" : ", paused");
  if (t.playing) {
    ImGui::SameLine();
    ImGui::TextDisabled("| shown %.2fx", speed);
  }
  const std::vector<SoftPin> pins = soft_pins(app.doc.scene());
  if (!pins.empty() && t.frame_count() > 1) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float w = ImGui::GetContentRegionAvail().x, h = 10;
    dl->AddRectFilled(p, ImVec2(p.x + w, p.y + h), IM_COL32(40, 40, 48, 255));
    for (const SoftPin& pin : pins) {
      const float x = p.x + w * (0.01f + 0.98f * float(pin.frame) / float(t.frame_count() - 1));
      dl->AddRectFilled(ImVec2(x - 2, p.y), ImVec2(x + 2, p.y + h), IM_COL32(255, 80, 80, 255));
    }
    ImGui::Dummy(ImVec2(w, h));
    ui_mark("soft_pin_strip");
  }
}

void draw_soft_toolbar(App& app) {
  SoftUi& ui = soft_ui(app);
  const bool no_take = app.take.dir().empty();
  bool shown = soft_character_shown(app);
  if (ImGui::Checkbox("Character", &shown)) ui.character_mode = no_take || shown;
  ui_mark("soft_character");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(no_take ? "lattice, mode sliders, vertex pins and objective gizmos (shown until a take exists)"
                              : "lattice, mode sliders, vertex pins and objective gizmos");
}

void draw_soft_overlay(App& app, float x, float y, int w, int h) {
  if (app.renderer.drawer_name() != "soft") return;
  Mat4 m;
  int dw = 0, dh = 0;
  if (!soft_drawer_primary_view(&m, &dw, &dh) || dw != w || dh != h) return;
  TakeReader* rd = app.take.reader();
  const SoftTakeData* data = rd ? soft_drawer_take_data(soft_scene_key(rd->manifest().scene)) : nullptr;
  if (!data || data->com.empty() || data->rest_vertices.size() < 3) {
    soft_live_drag(app, m, x, y, w, h);
    return;
  }
  // The body's extent at frame 0 sizes the handles.
  Vec3 lo{data->rest_vertices[0], data->rest_vertices[1], data->rest_vertices[2]}, hi = lo;
  for (size_t i = 0; i + 2 < data->rest_vertices.size(); i += 3)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], data->rest_vertices[i + a]);
      hi[a] = std::max(hi[a], data->rest_vertices[i + a]);
    }
  const float size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-3f});
  soft_gizmos(app, m, data->com[0], size, x, y, w, h);
  soft_live_drag(app, m, x, y, w, h);  // after the handles: a held handle keeps the mouse
}

}  // namespace

int soft_pin_frame(App& app) {
  const SoftSceneInfo info = soft_scene_info(app.doc.scene());
  return std::clamp(app.take.frame, 1, std::max(1, info.horizon));
}

// soft_preview_model: ui/soft_preview_build.cpp (compiled off the UI thread).

bool soft_on_drop(App& app, const fs::path& path) {
  if (!is_soft_scene(app.doc.scene())) return false;
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  static const char* kMesh[] = {".obj", ".ply", ".stl", ".gltf", ".glb", ".fbx", ".dae", ".off"};
  if (std::none_of(std::begin(kMesh), std::end(kMesh), [&](const char* e) { return ext == e; })) return false;
  std::string value = fs::absolute(path).lexically_normal().string();
  if (app.doc.has_path()) {
    const fs::path rel = fs::absolute(path).lexically_normal().lexically_relative(
        fs::absolute(app.doc.path()).parent_path().lexically_normal());
    if (!rel.empty()) value = rel.generic_string();
  }
  app.doc.set("/character/mesh", value);
  app.log.info("character mesh: " + value);
  return true;
}

const KindPanels& soft_panels() {
  static const KindPanels p = [] {
    KindPanels k;
    k.kind = "soft";
    k.inspector = &draw_soft_inspector;
    k.typed_keys = {"character", "material", "environment", "simulation", "controller", "objectives", "optimizer"};
    k.jobs = &draw_soft_jobs;
    k.viewport_toolbar = &draw_soft_toolbar;
    k.viewport_editor = &soft_character_view;
    k.viewport_overlay = &draw_soft_overlay;
    k.timeline = &draw_soft_timeline;
    k.viewport_frame = &soft_live_frame;
    k.on_drop = [](App& app, const std::string& path) { return soft_on_drop(app, path); };
    return k;
  }();
  return p;
}

}  // namespace pliant::editor
