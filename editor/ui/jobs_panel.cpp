// Run button and one row per job: state, progress bar, stage, ETA, objective
// curve, Cancel. A failed job's message is shown in red.
#include <imgui.h>

#include <algorithm>
#include <string>

#include "ui/app.h"
#include "ui/kind_panels.h"
#include "ui/panel_window.h"
#include "ui/smoke_panels.h"

namespace pliant::editor {

void draw_jobs_panel(App& app, const PanelRect& r) {
  if (!begin_panel("Jobs", r)) {
    ImGui::End();
    return;
  }
  draw_smoke_solve_panel(app);
  if (const KindPanels* kp = kind_panels(scene_kind(app)); kp && kp->jobs) kp->jobs(app);
  bool valid = app.scene_error().empty();
  if (!valid) ImGui::BeginDisabled();
  if (ImGui::Button("Run (F5)")) app.cmd_run();
  if (!valid) ImGui::EndDisabled();
  ui_mark("Run");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(80);
  if (ImGui::InputInt("threads", &app.job_threads)) app.job_threads = std::max(0, app.job_threads);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("--threads for new jobs (0: all cores)");
  if (!valid) ImGui::TextColored(kErrorColor, "fix the scene first (see the inspector)");
  if (!app.status().empty()) {
    ImGui::PushTextWrapPos(0);
    if (app.status_is_error()) ImGui::TextColored(kErrorColor, "%s", app.status().c_str());
    else ImGui::TextUnformatted(app.status().c_str());
    ImGui::PopTextWrapPos();
    ui_mark("status");
  }
  ImGui::Separator();
  ImGui::BeginChild("job_list");
  for (size_t i = app.jobs.size(); i-- > 0;) {
    JobProcess& job = *app.jobs[i];
    JobStatus st = job.snapshot();
    ImGui::PushID(job.id);
    bool newest = i + 1 == app.jobs.size();
    std::string head = "Job " + std::to_string(job.id) + " - " + job_state_name(st.state);
    bool selected = app.take.dir() == job.spec().take;
    if (ImGui::Selectable(head.c_str(), selected)) app.cmd_open_take(job.spec().take);
    float frac = 0;
    std::string overlay;
    if (st.of > 0) {
      frac = static_cast<float>(st.iter) / st.of;
      overlay = st.stage + " " + std::to_string(st.iter) + "/" + std::to_string(st.of);
    } else if (st.frames_expected > 0) {
      frac = static_cast<float>(st.frames_seen) / st.frames_expected;
      overlay = std::to_string(st.frames_seen) + "/" + std::to_string(st.frames_expected) + " frames";
    }
    if (st.state == JobState::Done) frac = 1;
    ImGui::ProgressBar(frac, ImVec2(-1, 0), overlay.empty() ? nullptr : overlay.c_str());
    if (newest) ui_mark("job_progress");
    if (st.eta_s >= 0 && !st.ended()) ImGui::Text("ETA %.0f s", st.eta_s);
    if (!st.objective.empty()) {
      char ov[64];
      std::snprintf(ov, sizeof ov, "objective %.3g", st.objective.back());
      ImGui::SetNextItemWidth(-1);  // PlotLines takes the item width when its size.x is 0
      ImGui::PlotLines("##objective", st.objective.data(), static_cast<int>(st.objective.size()), 0,
                       ov, FLT_MAX, FLT_MAX, ImVec2(0, 48));
    }
    if (st.state == JobState::Failed) {
      ImGui::PushTextWrapPos(0);
      ImGui::TextColored(kErrorColor, "%s", st.error.c_str());
      ImGui::PopTextWrapPos();
    } else if (!st.last_message.empty()) {
      ImGui::TextDisabled("%s", st.last_message.c_str());
    }
    if (!st.ended()) {
      if (ImGui::Button("Cancel")) app.cmd_cancel(i);
      if (newest) ui_mark("Cancel");
    }
    ImGui::Separator();
    ImGui::PopID();
  }
  ImGui::EndChild();
  ImGui::End();
}

}  // namespace pliant::editor
