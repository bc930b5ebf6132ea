// Scene parameters: typed widgets for the smoke fields, add/remove for sources
// and forces, a generic JSON tree for everything else, and the validation
// error of the current scene in red.
#include <imgui.h>

#include <set>
#include <string>

#include "ui/app.h"
#include "ui/json_widgets.h"
#include "ui/kind_panels.h"
#include "ui/panel_window.h"

namespace pliant::editor {

namespace {

using nlohmann::json;

int scene_dim(const json& s) {
  const json* r = s.contains("grid") && s["grid"].is_object() && s["grid"].contains("resolution")
                      ? &s["grid"]["resolution"]
                      : nullptr;
  return r && r->is_array() && r->size() == 3 ? 3 : 2;
}

void draw_resolution(Document& doc, int dim) {
  const json& s = doc.scene();
  int n[3] = {64, 64, 64};
  const json* r = nullptr;
  if (s.contains("grid") && s["grid"].is_object() && s["grid"].contains("resolution"))
    r = &s["grid"]["resolution"];
  if (r && r->is_array())
    for (int i = 0; i < dim && i < static_cast<int>(r->size()); ++i)
      if ((*r)[i].is_number_integer()) n[i] = (*r)[i].get<int>();
  if (ImGui::DragScalarN("resolution", ImGuiDataType_S32, n, dim, 0.25f)) {
    uint64_t key = ImGui::GetID("resolution");
    doc.set("/grid/resolution", json(std::vector<int>(n, n + dim)), key);
  }
  ui_mark_field("/grid/resolution");
}

void draw_sources(Document& doc, int dim) {
  const json& s = doc.scene();
  size_t count = s.contains("sources") && s["sources"].is_array() ? s["sources"].size() : 0;
  int remove = -1;
  for (size_t i = 0; i < count; ++i) {
    std::string p = "/sources/" + std::to_string(i);
    ImGui::PushID(static_cast<int>(i));
    bool open = ImGui::TreeNodeEx("source", ImGuiTreeNodeFlags_DefaultOpen, "source %zu", i);
    ImGui::SameLine();
    if (ImGui::SmallButton("Remove")) remove = static_cast<int>(i);
    ui_mark(p + "/remove");
    if (open) {
      json_choice(doc, "shape", p + "/shape", "sphere", {"sphere", "box"});
      const json& src = doc.scene()["sources"][i];
      json_vec(doc, "center_m", p + "/center_m", dim);
      if (src.value("shape", std::string("sphere")) == "box")
        json_vec(doc, "half_size_m", p + "/half_size_m", dim);
      else
        json_double(doc, "radius_m", p + "/radius_m", 0.05, 0.001f, 0.0, 100.0);
      json_double(doc, "density_per_s", p + "/density_per_s", 1.0, 0.01f);
      json_vec(doc, "velocity_m_per_s", p + "/velocity_m_per_s", dim);
      json_double(doc, "start_s", p + "/start_s", 0.0, 0.01f);
      json_double(doc, "end_s", p + "/end_s", 1.0, 0.01f);
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  if (remove >= 0) {
    json next = doc.scene();
    next["sources"].erase(static_cast<size_t>(remove));
    doc.edit("Remove source", next);
  }
  if (ImGui::Button("Add source")) {
    json next = doc.scene();
    json src = {{"shape", "sphere"},
                {"center_m", std::vector<double>(dim, 0.25)},
                {"radius_m", 0.05},
                {"density_per_s", 1.0},
                {"velocity_m_per_s", std::vector<double>(dim, 0.0)},
                {"start_s", 0.0},
                {"end_s", 1.0}};
    if (!next.contains("sources") || !next["sources"].is_array()) next["sources"] = json::array();
    next["sources"].push_back(src);
    doc.edit("Add source", next);
  }
  ui_mark("Add source");
}

void draw_forces(Document& doc, int dim) {
  const json& s = doc.scene();
  size_t count = s.contains("forces") && s["forces"].is_array() ? s["forces"].size() : 0;
  int remove = -1;
  for (size_t i = 0; i < count; ++i) {
    std::string p = "/forces/" + std::to_string(i);
    ImGui::PushID(1000 + static_cast<int>(i));
    bool open = ImGui::TreeNodeEx("force", ImGuiTreeNodeFlags_DefaultOpen, "force %zu", i);
    ImGui::SameLine();
    if (ImGui::SmallButton("Remove")) remove = static_cast<int>(i);
    ui_mark(p + "/remove");
    if (open) {
      json_choice(doc, "type", p + "/type", "uniform", {"uniform", "vortex"});
      const json& f = doc.scene()["forces"][i];
      if (f.value("type", std::string("uniform")) == "vortex") {
        json_vec(doc, "center_m", p + "/center_m", dim);
        json_double(doc, "radius_m", p + "/radius_m", 0.1, 0.001f, 0.0, 100.0);
        json_double(doc, "strength_per_s", p + "/strength_per_s", 1.0, 0.01f);
      } else {
        json_vec(doc, "acceleration_m_per_s2", p + "/acceleration_m_per_s2", dim);
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  if (remove >= 0) {
    json next = doc.scene();
    next["forces"].erase(static_cast<size_t>(remove));
    doc.edit("Remove force", next);
  }
  if (ImGui::Button("Add force")) {
    json next = doc.scene();
    if (!next.contains("forces") || !next["forces"].is_array()) next["forces"] = json::array();
    std::vector<double> a(dim, 0.0);
    next["forces"].push_back({{"type", "uniform"}, {"acceleration_m_per_s2", a}});
    doc.edit("Add force", next);
  }
  ui_mark("Add force");
}

void draw_smoke(Document& doc) {
  int dim = scene_dim(doc.scene());
  if (ImGui::CollapsingHeader("Grid", ImGuiTreeNodeFlags_DefaultOpen)) {
    draw_resolution(doc, dim);
    json_double(doc, "cell_size_m", "/grid/cell_size_m", 0.01, 0.0005f, 1e-5, 10.0);
    json_choice(doc, "boundary", "/grid/boundary", "closed", {"closed", "periodic"});
  }
  if (ImGui::CollapsingHeader("Time", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_double(doc, "dt_s", "/time/dt_s", 0.02, 0.001f, 1e-5, 10.0);
    json_int(doc, "frames", "/time/frames", 100, 1, 100000);
    json_int(doc, "substeps", "/time/substeps", 1, 1, 1000);
  }
  if (ImGui::CollapsingHeader("Physics", ImGuiTreeNodeFlags_DefaultOpen)) {
    json_choice(doc, "advection", "/advection", "semi_lagrangian", {"semi_lagrangian", "upwind"});
    json_double(doc, "buoyancy_m_per_s2", "/buoyancy_m_per_s2", 1.0, 0.01f);
    json_choice(doc, "pressure solver", "/pressure/solver", "mgpcg", {"mgpcg", "jacobi_pcg"});
    json_double(doc, "tolerance", "/pressure/tolerance", 1e-6, 1e-7f, 0.0, 1.0, "%.2e");
    json_int(doc, "max_iterations", "/pressure/max_iterations", 200, 1, 100000);
  }
  if (ImGui::CollapsingHeader("Sources", ImGuiTreeNodeFlags_DefaultOpen)) draw_sources(doc, dim);
  if (ImGui::CollapsingHeader("Forces", ImGuiTreeNodeFlags_DefaultOpen)) draw_forces(doc, dim);
}

}  // namespace

void draw_inspector_panel(App& app, const PanelRect& r) {
  if (!begin_panel("Inspector", r)) {
    ImGui::End();
    return;
  }
  Document& doc = app.doc;
  const std::string& err = app.scene_error();
  if (!err.empty()) {
    ImGui::PushTextWrapPos(0);
    ImGui::TextColored(kErrorColor, "%s", err.c_str());
    ImGui::PopTextWrapPos();
    ui_mark("scene_error");
  } else {
    ImGui::TextColored(ImVec4(0.5f, 0.85f, 0.5f, 1), "scene is valid");
  }
  ImGui::PushItemWidth(-140);
  json_text(doc, "name", "/name");
  const json& s = doc.scene();
  std::string kind = s.is_object() ? s.value("kind", std::string()) : std::string();
  ImGui::Text("kind: %s", kind.c_str());
  static const std::set<std::string> kTyped = {"pliant", "kind", "name", "grid", "time",
                                               "advection", "buoyancy_m_per_s2", "pressure",
                                               "sources", "forces"};
  const KindPanels* kp = kind_panels(kind);
  if (kind == "smoke") draw_smoke(doc);
  else if (kp && kp->inspector) kp->inspector(app);
  auto typed = [&](const std::string& key) {
    if (kind == "smoke") return kTyped.count(key) > 0;
    if (kp && kp->inspector) for (const auto& k : kp->typed_keys) if (k == key) return true;
    return false;
  };
  if (ImGui::CollapsingHeader("Other fields", ImGuiTreeNodeFlags_DefaultOpen) && doc.scene().is_object()) {
    const json& s2 = doc.scene();
    std::vector<std::string> keys;
    for (auto it = s2.begin(); it != s2.end(); ++it)
      if (!typed(it.key())) keys.push_back(it.key());
    for (const auto& k : keys)
      if (k != "pliant" && k != "kind") json_tree(doc, k, "/" + k);
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace pliant::editor
