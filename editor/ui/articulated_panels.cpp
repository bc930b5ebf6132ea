// The articulated kind's parts of the shared panels: typed inspector, jobs
// (Simulate, Compare integrators; its plot: articulated_energy_plot.cpp), viewport toolbar and
// overlay, timeline readout; the geometry source the drawer compiles takes with.
#include "ui/articulated_panels.h"

#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include "pliant/core/scene.h"
#include "pliant/core/take.h"
#include "render/articulated_drawer.h"
#include "ui/app.h"
#include "ui/articulated_select.h"
#include "ui/json_widgets.h"
#include "ui/panel_window.h"
#include "ui/ui_mark.h"

#ifdef PLIANT_HAVE_ARTICULATED
#include "pliant/articulated/articulated.h"
#endif

namespace pliant::editor {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

ArticulatedUiState& ui_state(App& app) { return app.kind_ui.get<ArticulatedUiState>("articulated"); }

Scene make_scene(const json& doc, const fs::path& dir) {
  Scene s;
  s.file = "scene";
  s.dir = dir.empty() ? fs::path(".") : dir;
  s.kind = "articulated";
  s.doc = doc;
  return s;
}

#ifdef PLIANT_HAVE_ARTICULATED

// A mesh geom's triangles as float / uint32 arrays (render/ does not see engine types).
std::shared_ptr<const ArticulatedMesh> mesh_view(const articulated::MeshShape& shape) {
  auto out = std::make_shared<ArticulatedMesh>();
  out->xyz.reserve(3 * shape.vertices.size());
  double r2 = 0;
  for (const auto& v : shape.vertices) {
    for (int i = 0; i < 3; ++i) out->xyz.push_back(float(v[i]));
    r2 = std::max(r2, v.squaredNorm());
  }
  out->radius = float(std::sqrt(r2));
  out->triangles.reserve(3 * shape.triangles.size());
  for (const auto& t : shape.triangles)
    for (int i : t) out->triangles.push_back(uint32_t(i));
  return out;
}

bool compile_geometry(const json& scene, const fs::path& dir, ArticulatedGeometry* out, std::string* err) {
  *out = ArticulatedGeometry{};
  try {
    const articulated::ArticulatedScene a = articulated::articulated_compile(make_scene(scene, dir));
    const articulated::Model& m = a.model;
    out->bodies = static_cast<int>(m.bodies.size()) - 1;
    out->gravity = m.gravity.norm();
    for (size_t b = 1; b < m.bodies.size(); ++b) {
      out->total_mass += m.bodies[b].mass;
      if (m.bodies[b].parent != 0) continue;
      for (int j : m.bodies[b].joints) {
        const auto t = m.joints[j].type;
        if (t == articulated::JointType::Free || t == articulated::JointType::Slide) out->floating = true;
      }
    }
    for (const articulated::Geom& g : m.geoms) {
      ArticulatedGeom v;
      v.shape = g.type == articulated::GeomType::Plane     ? ArticulatedGeom::Plane
                : g.type == articulated::GeomType::Sphere  ? ArticulatedGeom::Sphere
                : g.type == articulated::GeomType::Capsule ? ArticulatedGeom::Capsule
                : g.type == articulated::GeomType::Mesh    ? ArticulatedGeom::Mesh
                                                           : ArticulatedGeom::Box;
      if (v.shape == ArticulatedGeom::Mesh) {
        if (!g.mesh) continue;  // nothing to draw (the compile refuses empty meshes)
        v.mesh = mesh_view(*g.mesh);
      }
      v.body = g.body;
      v.pos = {float(g.pos.x()), float(g.pos.y()), float(g.pos.z())};
      v.quat = {float(g.quat.w()), float(g.quat.x()), float(g.quat.y()), float(g.quat.z())};
      v.size = {float(g.size.x()), float(g.size.y()), float(g.size.z())};
      out->geoms.push_back(v);
    }
    return true;
  } catch (const std::exception& e) {
    *err = e.what();
    return false;
  }
}

#endif

// Registered at start-up: render/ does not link the engine module.
const bool kGeometryRegistered = [] {
  articulated_drawer_set_geometry_source(&articulated_scene_geometry);
  return true;
}();

fs::path document_folder(const App& app) {
  std::error_code ec;
  return app.doc.has_path() ? fs::absolute(app.doc.path(), ec).parent_path() : fs::current_path(ec);
}

// Relative model paths of the shown take resolve against its scene file's folder.
void point_drawer_at_take(App& app) {
  TakeReader* rd = app.take.reader();
  fs::path dir = document_folder(app);
  if (rd && !rd->manifest().scene_file.empty()) {
    std::error_code ec;
    dir = fs::absolute(fs::path(rd->manifest().scene_file), ec).parent_path();
  }
  articulated_drawer_set_scene_dir(dir);
}

// "10 bodies, nq 20, nv 20, 0 actuators" (or the compile error), per revision.
const std::string& model_summary(App& app) {
  ArticulatedUiState& st = ui_state(app);
  if (st.summary_doc == app.doc.id() && st.summary_revision == app.doc.revision()) return st.summary;
  st.summary_doc = app.doc.id();
  st.summary_revision = app.doc.revision();
#ifdef PLIANT_HAVE_ARTICULATED
  std::string err;
  const auto compiled = articulated_document_compiled(app, &err);
  if (compiled) {
    const articulated::ArticulatedScene& a = *compiled;
    const articulated::Model& m = a.model;
    double mass = 0;
    for (const auto& b : m.bodies) mass += b.mass;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "%d bodies, %zu geoms, nq %d, nv %d, %zu actuators, %.3g kg, %zu contact points; %d frames",
                  int(m.bodies.size()) - 1, m.geoms.size(), m.nq, m.nv, m.actuators.size(), mass,
                  articulated::contact_points(m).size(), a.mpc ? a.steps + 1 : a.frames);
    st.summary = buf;
    if (!m.ignored_attributes.empty())
      st.summary += "; " + std::to_string(m.ignored_attributes.size()) +
                    " MuJoCo solver parameters ignored (first: " + m.ignored_attributes.front() + ")";
  } else {
    st.summary = "model: " + err;
  }
#else
  st.summary = "this editor was built without the articulated engine";
#endif
  return st.summary;
}

bool has_key(const json& s, const char* k) { return s.is_object() && s.contains(k); }

bool is_mjcf_model(const json& s) {
  if (!has_key(s, "model") || !s["model"].is_string()) return false;
  std::string ext = fs::path(s["model"].get<std::string>()).extension().string();
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return ext == ".xml";
}

void tooltip(const char* text) {
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

void draw_inspector(App& app) {
  Document& doc = app.doc;
  point_drawer_at_take(app);
  draw_selected_body(app);
  if (ImGui::CollapsingHeader("Model", ImGuiTreeNodeFlags_DefaultOpen)) {
    const json& s = doc.scene();
    if (has_key(s, "model") && s["model"].is_object()) {
      ImGui::TextDisabled("inline model");
      json_tree(doc, "model", "/model");
    } else {
      json_text(doc, "model file", "/model");
      tooltip("MJCF (.xml) or Pliant JSON model (.json), relative to the scene's folder; "
              "dropping a model file on the window sets it");
    }
    if (is_mjcf_model(s)) {
      json_bool(doc, "ignore MuJoCo solver params", "/mjcf/ignore_solver_params", false);
      tooltip("MuJoCo's constraint-solver parameters (geom / pair solref, solimp, solmix; joint solref / "
              "solimp of limits and friction; option impratio, cone) have no counterpart in Pliant's "
              "penalties (contact stiffness below): off, such a model is refused; on, it loads and they "
              "are listed");
      json_choice(doc, "mesh inertia", "/mjcf/mesh_inertia", "exact", {"exact", "mujoco-2.2.2"});
      tooltip("mesh geoms' mass and inertia: the enclosed solid's (exact), or what libmujoco 2.2.2 "
              "compiles (its mass from the equivalent inertia box, larger for most shapes) to match "
              "MuJoCo side by side");
      json_choice(doc, "curved contact", "/mjcf/curved_contact", "exact", {"exact", "tessellated"});
      tooltip("cylinders and ellipsoids against planes: at their exact surface (exact: the deepest point "
              "of the shape, so a cylinder rolls smoothly), or through the points of their tessellation "
              "(a 32-gon for a cylinder); against other obstacles and bodies the tessellation either way");
    }
    if (ImGui::SmallButton("Inline chain")) {
      doc.set("/model", json{{"chain", {{"links", 10}, {"link_length", 0.1}, {"radius", 0.01}}}});
    }
    ui_mark("inline_chain");
    tooltip("replace the model by a generated chain of capsules (edit links, length, radius)");
    ImGui::PushTextWrapPos(0);
    ImGui::TextDisabled("%s", model_summary(app).c_str());
    ImGui::PopTextWrapPos();
  }
  if (ImGui::CollapsingHeader("Simulation", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_choice(doc, "integrator", "/integrator", "pbad3", articulated_integrators());
    tooltip("pbad2/pbad3: position-based collocation of 2nd/3rd order (implicit, one LM solve per step; "
            "pbad2 slows spinning bodies, dw/dt = -dt w^3, pbad3 by -dt^3 w^5); "
            "pbad4: 5-frame stencil, least damping on smooth motion (unstable in whips); "
            "euler: semi-implicit Euler; rk4: Runge-Kutta 4");
    json_double(doc, "dt", "/dt", 0.01, 0.0005f, 1e-6, 1.0, "%.4g");
    json_double(doc, "duration_s", "/duration_s", 5.0, 0.05f, 0.0, 1e6, "%.3g");
    json_int(doc, "write_every", "/write_every", 1, 1, 1000000);
    tooltip("write every n-th step as a take frame");
  }
  if (ImGui::CollapsingHeader("Contact", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_bool(doc, "enabled", "/contact/enabled", true);
    json_double(doc, "stiffness", "/contact/stiffness", 1e5, 100.0f, 1e-6, 1e12, "%.4g");
    tooltip("penalty k: normal force k * depth (N/m)");
    json_double(doc, "damping", "/contact/damping", 0.0, 0.1f, 0.0, 1e12, "%.4g");
    json_choice(doc, "friction", "/contact/friction", "coulomb", {"none", "coulomb", "ck"});
    tooltip("coulomb: dry friction (smoothed); ck: the dissertation's tangential model, -C_k f_n v_t");
    const json& s = doc.scene();
    const std::string friction = has_key(s, "contact") && s["contact"].is_object()
                                     ? s["contact"].value("friction", std::string("coulomb"))
                                     : "coulomb";
    if (friction == "coulomb") json_double(doc, "mu", "/contact/mu", 0.5, 0.01f, 0.0, 100.0, "%.3g");
    if (friction == "ck") json_double(doc, "C_k", "/contact/ck", 10.0, 0.1f, 0.0, 1e6, "%.3g");
    if (friction == "coulomb")
      json_double(doc, "slip_eps", "/contact/slip_eps", 1e-7, 1e-8f, 1e-12, 1.0, "%.2e");
  }
  if (ImGui::CollapsingHeader("Solver")) {
    json_choice(doc, "method", "/solver/method", "lm", {"lm", "lbfgs"});
    tooltip("PBAD step solver: Levenberg-Marquardt (O(N) tree solve) or preconditioned L-BFGS");
    json_int(doc, "max_iterations", "/solver/max_iterations", 50, 1, 10000);
    json_double(doc, "tolerance", "/solver/tolerance", 1e-7, 1e-8f, 1e-16, 1.0, "%.2e");
    json_choice(doc, "hessian", "/solver/hessian", "exact", {"exact", "gauss_newton"});
  }
  const json& s = doc.scene();
  if (has_key(s, "mpc") && s["mpc"].is_object()) {
    if (ImGui::CollapsingHeader("MPC (CEM)", ImGuiTreeNodeFlags_DefaultOpen)) {
      json_int(doc, "horizon", "/mpc/horizon", 10, 1, 1000);
      tooltip("planning horizon in control steps");
      json_int(doc, "substeps", "/mpc/substeps", 2, 1, 1000);
      tooltip("simulation steps per control step");
      json_int(doc, "samples", "/mpc/samples", 32, 2, 100000);
      json_int(doc, "elites", "/mpc/elites", 6, 1, 100000);
      json_int(doc, "iterations", "/mpc/iterations", 2, 1, 100);
      json_double(doc, "noise", "/mpc/noise", 0.6, 0.01f, 0.0, 10.0, "%.3g");
      json_int(doc, "seed", "/mpc/seed", 1, 0, 1 << 30);
      json_double(doc, "ctrl_cost", "/mpc/ctrl_cost", 1e-3, 1e-4f, 0.0, 1e6, "%.3g");
      json_double(doc, "upright_weight", "/mpc/upright_weight", 0.0, 0.5f, 0.0, 1e6, "%.3g");
      json_double(doc, "height_weight", "/mpc/height_weight", 0.0, 0.5f, 0.0, 1e6, "%.3g");
      if (ImGui::SmallButton("Remove MPC")) {
        json next = s;
        next.erase("mpc");
        doc.edit("Remove MPC", next);
      }
      ui_mark("remove_mpc");
    }
  } else {
    if (ImGui::SmallButton("Add MPC (CEM)"))
      doc.set("/mpc", json{{"horizon", 10}, {"substeps", 2}, {"samples", 32}, {"elites", 6}, {"iterations", 2},
                           {"noise", 0.6}, {"seed", 1}});
    ui_mark("add_mpc");
    tooltip("plan the actuators with cross-entropy MPC (the model needs motors)");
  }
}

void draw_jobs(App& app) {
  ArticulatedUiState& st = ui_state(app);
  point_drawer_at_take(app);
  const bool valid = app.scene_error().empty();
  if (!valid) ImGui::BeginDisabled();
  if (ImGui::Button("Simulate")) articulated_simulate(app);
  ui_mark("Simulate");
  tooltip("run the scene with its integrator and dt (like Run)");
  ImGui::SameLine();
  if (ImGui::Button("Compare integrators")) {
    std::vector<std::string> picked;
    for (size_t i = 0; i < articulated_integrators().size(); ++i)
      if (st.compare_pick[i]) picked.push_back(articulated_integrators()[i]);
    articulated_compare_integrators(app, picked);
  }
  ui_mark("compare_integrators");
  tooltip("run the scene once per ticked integrator (same dt) and plot their energies together");
  if (!valid) ImGui::EndDisabled();
  for (size_t i = 0; i < articulated_integrators().size(); ++i) {
    if (i % 3) ImGui::SameLine();  // PBAD schemes on one row, the explicit ones below (narrow panels)
    ImGui::Checkbox(articulated_integrators()[i].c_str(), &st.compare_pick[i]);
    ui_mark("pick_" + articulated_integrators()[i]);
  }
  if (!st.compare_error.empty()) ImGui::TextColored(kErrorColor, "%s", st.compare_error.c_str());
  articulated_poll_compare(app);
  articulated_draw_energy_plot(app);

  const json& s = app.doc.scene();
  if (has_key(s, "mpc")) ImGui::TextDisabled("MPC scene: the take is the executed, planned trajectory");
  if (TakeReader* rd = app.take.reader()) {
    const json& m = rd->manifest().metrics;
    if (m.is_object() && m.contains("distance_m") && m["distance_m"].is_number())
      ImGui::Text("moved %.3g m forward", m["distance_m"].get<double>());
    if (app.take.frame_count() > 1) {
      if (ImGui::SmallButton("Play from start")) {
        app.take.set_frame(0);
        app.take.playing = true;
      }
      ui_mark("play_from_start");
    }
  }
  ImGui::Separator();
}

void draw_toolbar(App& app) {
  point_drawer_at_take(app);
  articulated_selection(app);  // the highlight follows the selection before the frame uploads
  ArticulatedDrawOptions& o = articulated_draw_options();
  bool changed = ImGui::Checkbox("contacts", &o.show_contacts);
  ui_mark("show_contacts");
  ImGui::SameLine();
  changed |= ImGui::Checkbox("follow", &o.follow);
  ui_mark("follow");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("keep a free-moving model's root in view (the ground moves)");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(110);
  changed |= ImGui::SliderFloat("force scale", &o.force_scale, 0.05f, 20.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("contact force arrows: at 1 the model's weight is 0.25 x the view (impacts saturate at 0.4)");
  // Upload the frame again so the drawer applies the new options.
  if (changed) app.viewport.shown_frame = -1;
}

void draw_overlay(App& app, float x, float y, int w, int h) {
  if (!app.renderer.has_frame() || app.renderer.drawer_name() != "articulated") return;
  articulated_viewport_pick(app, x, y, w, h);
  const ArticulatedFrameInfo& info = articulated_last_frame_info();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  char text[200];
  std::snprintf(text, sizeof text, "%d bodies  %d contacts  max |f| %.3g N", info.bodies, info.contacts,
                info.max_force);
  dl->AddText(ImVec2(x + 10, y + 8), IM_COL32(220, 220, 230, 255), text);
  if (info.has_energy) {
    std::snprintf(text, sizeof text, "E %.5g J  (kinetic %.4g, potential %.4g)", info.energy[2], info.energy[0],
                  info.energy[1]);
    dl->AddText(ImVec2(x + 10, y + 26), IM_COL32(220, 220, 230, 255), text);
  }
  if (!info.model_error.empty())
    dl->AddText(ImVec2(x + 10, y + 44), IM_COL32(255, 110, 90, 255), ("model: " + info.model_error).c_str());
  if (app.take.dir().empty())
    dl->AddText(ImVec2(x + 10, y + h - 24), IM_COL32(255, 210, 120, 255),
                "initial state (no take yet): Simulate or Run (F5)");
}

void draw_timeline(App& app) {
  TakeReader* rd = app.take.reader();
  if (!rd || app.take.frame_count() == 0) return;
  const Manifest& man = rd->manifest();
  double dt = 0;
  int every = 1;
  if (man.scene.is_object()) {
    dt = man.scene.value("dt", 0.0);
    every = man.scene.value("write_every", 1);
  }
  if (dt > 0)
    ImGui::Text("t = %.3f s", app.take.frame * dt * std::max(every, 1));
  else
    ImGui::Text("frame %d", app.take.frame);
  const json& m = man.metrics;
  if (m.is_object() && !m.empty()) {
    ImGui::SameLine();
    std::string line;
    for (const char* k : {"distance_m", "energy_drift", "energy_change", "lm_iterations_per_step", "wall_s"})
      if (m.contains(k) && m[k].is_number()) {
        char b[64];
        std::snprintf(b, sizeof b, "%s %.4g   ", k, m[k].get<double>());
        line += b;
      }
    ImGui::TextDisabled("%s", line.c_str());
  }
}

}  // namespace

Scene articulated_document_scene(const App& app) { return make_scene(app.doc.scene(), document_folder(app)); }

#ifdef PLIANT_HAVE_ARTICULATED
std::shared_ptr<const articulated::ArticulatedScene> articulated_document_compiled(App& app, std::string* err) {
  ArticulatedUiState& st = ui_state(app);
  if (st.compiled_doc != app.doc.id() || st.compiled_revision != app.doc.revision()) {
    st.compiled_doc = app.doc.id();
    st.compiled_revision = app.doc.revision();
    st.compiled.reset();
    st.compile_error.clear();
    try {
      st.compiled = std::make_shared<const articulated::ArticulatedScene>(
          articulated::articulated_compile(articulated_document_scene(app)));
    } catch (const std::exception& e) {
      st.compile_error = e.what();
    }
  }
  if (err) *err = st.compile_error;
  return st.compiled;
}
#endif

bool articulated_scene_geometry(const json& scene, const fs::path& dir, ArticulatedGeometry* out,
                                std::string* err) {
#ifdef PLIANT_HAVE_ARTICULATED
  return compile_geometry(scene, dir, out, err);
#else
  (void)scene, (void)dir, (void)out;
  *err = "this editor was built without the articulated engine";
  return false;
#endif
}

bool articulated_on_drop(App& app, const std::string& path) {
  const json& s = app.doc.scene();
  if (!s.is_object() || s.value("kind", std::string()) != "articulated") return false;
  const fs::path p(path);
  const std::string ext = p.extension().string();
  if (ext != ".xml" && ext != ".json") return false;
  if (ext == ".json") {
    // A scene (with "kind") opens as a document; a model file is ours.
    try {
      std::ifstream in(p);
      const json j = json::parse(in);
      if (j.is_object() && j.contains("kind")) return false;
    } catch (const std::exception&) {
      return false;
    }
  }
  std::error_code ec;
  fs::path model = fs::absolute(p, ec);
  if (app.doc.has_path()) {
    const fs::path rel = fs::relative(model, document_folder(app), ec);
    if (!ec && !rel.empty()) model = rel;
  }
  json next = s;
  next["model"] = model.generic_string();
  bool reset_initial = false, ignored_params = false;
#ifdef PLIANT_HAVE_ARTICULATED
  auto loads = [&](const json& scene, std::string* err) {
    try {
      articulated::articulated_compile(make_scene(scene, document_folder(app)));
      return true;
    } catch (const std::exception& e) {
      *err = e.what();
      return false;
    }
  };
  // The old model's initial qpos/qvel rarely fit a new one, and gym-style MJCF
  // carries solref/solimp Pliant cannot honour: try without the initial state,
  // then ignoring solver parameters (the checkbox shows it), in that order.
  std::string err, unused;
  bool loaded = loads(next, &err);
  json bare = next;
  bare.erase("initial");
  if (!loaded && next.contains("initial") && loads(bare, &unused)) {
    next = bare;
    reset_initial = true;
    loaded = true;
  }
  const bool ignoring_before = s.contains("mjcf") && s["mjcf"].is_object() &&
                               s["mjcf"].value("ignore_solver_params", false);
  if (!loaded && ext == ".xml" && !ignoring_before) {
    for (json* v : {&next, &bare}) {
      json lenient = *v;
      lenient["mjcf"]["ignore_solver_params"] = true;
      if (loads(lenient, &unused)) {
        reset_initial = v == &bare && next.contains("initial");
        next = std::move(lenient);
        ignored_params = true;
        loaded = true;
        break;
      }
    }
  }
  if (!loaded) {
    app.set_status("Model not loaded: " + err, true);
    app.log.error(app.status());
    return true;  // ours, but rejected: the document is unchanged
  }
#endif
  app.doc.edit("Set model " + p.filename().string(), next);
  app.set_status("Model " + model.generic_string() + (reset_initial ? " (initial state reset to the model's)" : "") +
                 (ignored_params ? " ignoring its MuJoCo solver parameters (solref, solimp and the like; "
                                   "untick \"ignore MuJoCo solver params\" to refuse it)"
                                 : ""));
  if (ignored_params) {
    app.log.warn(app.status());
  } else {
    app.log.info(app.status());
  }
  return true;
}

const KindPanels& articulated_panels() {
  static const KindPanels p = [] {
    KindPanels k;
    k.kind = "articulated";
    k.inspector = &draw_inspector;
    k.typed_keys = {"name", "model", "mjcf", "integrator", "dt", "duration_s", "write_every", "contact", "solver", "mpc"};
    k.jobs = &draw_jobs;
    k.viewport_toolbar = &draw_toolbar;
    k.viewport_frame = &articulated_initial_frame;
    k.viewport_overlay = &draw_overlay;
    k.timeline = &draw_timeline;
    k.on_drop = &articulated_on_drop;
    return k;
  }();
  return p;
}

}  // namespace pliant::editor
