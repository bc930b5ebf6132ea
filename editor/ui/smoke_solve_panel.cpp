// Solve panel for smoke keyframe control: the parameters artists change most
// (grid resolution, frames, r, method, iterations), Solve / Cancel / Resume, and
// the convergence curves: the objective from the job's progress events, the ADMM
// primal and dual residuals from the take's checkpoints (the final metrics once done).
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>

#include "doc/smoke_keyframes.h"
#include "pliant/smoke/control.h"
#include "ui/app.h"
#include "ui/panel_window.h"
#include "ui/smoke_panels.h"

namespace pliant::editor {

using nlohmann::json;

namespace {

uint64_t merge_key(const std::string& pointer) { return std::hash<std::string>{}(pointer) | 1; }

struct ResidualCurves {
  std::string dir;
  size_t records = 0;
  std::vector<float> primal, dual;  // log10
};

std::vector<float> log10s(const std::vector<double>& v) {
  std::vector<float> out;
  for (double x : v) out.push_back(float(std::log10(std::max(x, 1e-30))));
  return out;
}

// Residual histories from the newest checkpoint of the shown take.
void refresh_residuals(App& app, ResidualCurves& c) {
  TakeReader* rd = app.take.reader();
  if (!rd) {
    c = {};
    return;
  }
  const std::string dir = app.take.dir().string();
  if (c.dir == dir && c.records == rd->record_count()) return;
  c.dir = dir;
  c.records = rd->record_count();
  const json& metrics = rd->manifest().metrics;
  if (metrics.is_object() && metrics.contains("primal_residual_history")) {
    c.primal = log10s(metrics["primal_residual_history"].get<std::vector<double>>());
    c.dual = log10s(metrics.value("dual_residual_history", std::vector<double>{}));
    return;
  }
  Record r;
  if (!rd->latest(RecordKind::Checkpoint, &r)) return;
  const Field* f = r.find("state");
  const Field* n = r.find("state_bytes");
  if (!f || !n || n->data.size() != 2) return;
  const size_t bytes = size_t(n->data[0]) * 4096 + size_t(n->data[1]);
  if (bytes > f->data.size() * 4) return;
  std::vector<uint8_t> b(bytes);
  std::memcpy(b.data(), f->data.data(), bytes);
  try {
    smoke::ControlState s = smoke::control_state_deserialize(b);
    c.primal = log10s(s.primal_residual_history);
    c.dual = log10s(s.dual_residual_history);
  } catch (const std::exception&) {
  }
}

void plot(const char* id, const std::vector<float>& v, const std::string& overlay) {
  if (v.empty()) return;
  ImGui::SetNextItemWidth(-1);
  ImGui::PlotLines(id, v.data(), int(v.size()), 0, overlay.c_str(), FLT_MAX, FLT_MAX, ImVec2(0, 40));
}

}  // namespace

void draw_smoke_solve_panel(App& app) {
  const json& scene = app.doc.scene();
  if (!is_smoke_scene(scene)) return;
  if (!ImGui::CollapsingHeader("Keyframe solve", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::PushID("smoke_solve");
  if (!has_control(scene)) {
    ImGui::TextWrapped("This scene simulates smoke forward. Add keyframe control to make the smoke take shapes.");
    if (ImGui::Button("Add keyframe control")) {
      json s = scene;
      s["control"] = default_control_section();
      int idx = 0;
      s = with_keyframe_added(s, smoke_frames(s), &idx);
      app.doc.edit("Add keyframe control", std::move(s));
      app.canvas.slot = idx;
      app.viewport.show_canvas = true;
    }
    ui_mark("add_control");
    ImGui::PopID();
    return;
  }
  const json c = scene["control"];  // a copy: the edits below replace the scene
  // Resolution and frames.
  auto res = smoke_resolution(scene);
  if (res[0] > 0) {
    int r2[2] = {res[0], res[1]};
    ImGui::SetNextItemWidth(120);
    if (ImGui::InputInt2("resolution", r2, ImGuiInputTextFlags_EnterReturnsTrue) && r2[0] >= 4 && r2[1] >= 4)
      app.doc.set("/grid/resolution", {r2[0], r2[1]});
    // The two input boxes only (not the label): scripts click at 0.25 and 0.75.
    ui_mark_rect("solve_resolution", ImGui::GetItemRectMin().x, ImGui::GetItemRectMin().y,
                 ImGui::GetItemRectMin().x + 120, ImGui::GetItemRectMax().y);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("cells along x and y; painted keyframes are resampled, so you can sketch coarse\n"
                        "and solve fine (the cell size stays: the domain grows or shrinks)");
  }
  int frames = smoke_frames(scene);
  ImGui::SetNextItemWidth(80);
  if (ImGui::InputInt("frames", &frames, 0, 0, ImGuiInputTextFlags_EnterReturnsTrue) && frames >= 1)
    app.doc.set("/time/frames", frames);
  ui_mark_rect("solve_frames", ImGui::GetItemRectMin().x, ImGui::GetItemRectMin().y,
               ImGui::GetItemRectMin().x + 80, ImGui::GetItemRectMax().y);
  // r: logarithmic slider on the exponent.
  float lr = float(std::log10(std::max(1e-12, c.value("r", 1e-5))));
  ImGui::SetNextItemWidth(120);
  if (ImGui::SliderFloat("log10 r", &lr, -9.0f, 1.0f, "%.1f"))
    app.doc.set("/control/r", std::pow(10.0, std::round(lr * 10.0) / 10.0), merge_key("/control/r"));
  ui_mark_rect("solve_r", ImGui::GetItemRectMin().x, ImGui::GetItemRectMin().y,
               ImGui::GetItemRectMin().x + 120, ImGui::GetItemRectMax().y);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("r weighs the control forces against matching the keyframes.\n"
                      "Small r: the smoke snaps to the keyframes (sharp shapes, strong, busy forces).\n"
                      "Large r: gentle forces and softer, more natural motion that only approaches the shapes.");
  const std::string method = c.value("method", std::string("admm"));
  if (ImGui::RadioButton("ADMM", method != "lbfgs") && method == "lbfgs") app.doc.set("/control/method", "admm");
  ui_mark("method_admm");
  ImGui::SameLine();
  if (ImGui::RadioButton("L-BFGS", method == "lbfgs") && method != "lbfgs") app.doc.set("/control/method", "lbfgs");
  ui_mark("method_lbfgs");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("ADMM: the paper's solver with a spacetime multigrid (coarse previews first).\n"
                      "L-BFGS: the discrete-adjoint baseline.");
  ImGui::SameLine();
  int iters = c.value("max_iterations", 50);
  ImGui::SetNextItemWidth(80);
  if (ImGui::InputInt("iterations", &iters, 0, 0, ImGuiInputTextFlags_EnterReturnsTrue) && iters >= 1)
    app.doc.set("/control/max_iterations", iters);
  ui_mark_rect("solve_iterations", ImGui::GetItemRectMin().x, ImGui::GetItemRectMin().y,
               ImGui::GetItemRectMin().x + 80, ImGui::GetItemRectMax().y);

  // Solve / Cancel / Resume.
  JobProcess* job = app.newest_job();
  JobStatus st = job ? job->snapshot() : JobStatus{};
  const bool running = job && !st.ended();
  const bool valid = app.scene_error().empty();
  if (!valid || running) ImGui::BeginDisabled();
  if (ImGui::Button("Solve")) app.cmd_run();
  if (!valid || running) ImGui::EndDisabled();
  ui_mark("Solve");
  ImGui::SameLine();
  if (!running) ImGui::BeginDisabled();
  if (ImGui::Button("Cancel solve")) app.cmd_cancel(app.jobs.size() - 1);
  if (!running) ImGui::EndDisabled();
  ui_mark("Cancel solve");
  ImGui::SameLine();
  const bool resumable = job && st.ended() && st.state != JobState::Done && valid;
  if (!resumable) ImGui::BeginDisabled();
  if (ImGui::Button("Resume")) app.cmd_resume();
  if (!resumable) ImGui::EndDisabled();
  ui_mark("Resume");
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip("continue a cancelled or failed solve from its last checkpoint");
  if (!valid) {
    ImGui::PushTextWrapPos(0);
    ImGui::TextColored(kErrorColor, "%s", app.scene_error().c_str());
    ImGui::PopTextWrapPos();
  }
  if (job && st.state == JobState::Failed) {
    ImGui::PushTextWrapPos(0);
    ImGui::TextColored(kErrorColor, "Solve failed: %s (the take is kept: %s)", st.error.c_str(),
                       job->spec().take.filename().c_str());
    ImGui::PopTextWrapPos();
  }

  // Curves.
  static ResidualCurves residuals;
  refresh_residuals(app, residuals);
  if (job && !st.objective.empty()) {
    std::vector<float> lg;
    for (float v : st.objective) lg.push_back(std::log10(std::max(v, 1e-30f)));
    char ov[96];
    std::snprintf(ov, sizeof ov, "objective %.4g (log)", st.objective.back());
    plot("##solve_objective", lg, ov);
  }
  if (!residuals.primal.empty()) {
    char ov[96];
    std::snprintf(ov, sizeof ov, "primal residual 1e%.1f", residuals.primal.back());
    plot("##solve_primal", residuals.primal, ov);
  }
  if (!residuals.dual.empty()) {
    char ov[96];
    std::snprintf(ov, sizeof ov, "dual residual 1e%.1f", residuals.dual.back());
    plot("##solve_dual", residuals.dual, ov);
  }
  if (app.viewport.showing_preview) ImGui::TextColored(kWarnColor, "%s", app.viewport.preview_label.c_str());
  ImGui::Separator();
  ImGui::PopID();
}

}  // namespace pliant::editor
