// "Compare integrators"' plot: every run's total energy over time on one shared
// scale, with a legend (drift %, job state) whose entries open that run's take.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "doc/job_process.h"
#include "ui/app.h"
#include "ui/articulated_panels.h"
#include "ui/ui_mark.h"

namespace pliant::editor {

namespace {

// In the order of articulated_integrators(): pbad2, pbad3, pbad4, euler, rk4.
const ImU32 kRunColors[] = {IM_COL32(90, 160, 255, 255), IM_COL32(110, 220, 110, 255),
                            IM_COL32(200, 120, 255, 255), IM_COL32(255, 100, 90, 255),
                            IM_COL32(255, 185, 60, 255)};
static_assert(sizeof(kRunColors) / sizeof(kRunColors[0]) == 5, "one colour per integrator");

ImU32 run_color(const std::string& integrator) {
  const auto& names = articulated_integrators();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == integrator) return kRunColors[i];
  return IM_COL32(200, 200, 200, 255);
}

bool unstable(const IntegratorRun& r) { return !r.finite || r.drift_percent() > 200; }

}  // namespace

// Unstable runs are left out of the scale and clipped.

void articulated_draw_energy_plot(App& app) {
  ArticulatedUiState& st = app.kind_ui.get<ArticulatedUiState>("articulated");
  if (st.runs.empty()) return;
  float tmax = 0, lo = 1e30f, hi = -1e30f;
  bool any_stable = false;
  for (const auto& r : st.runs) any_stable = any_stable || (!unstable(r) && !r.total.empty());
  for (const auto& r : st.runs) {
    if (!r.time_s.empty()) tmax = std::max(tmax, r.time_s.back());
    if (any_stable && unstable(r)) continue;
    for (float v : r.total)
      if (std::isfinite(v)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
  }
  if (!(hi >= lo)) lo = 0, hi = 1;
  const float pad = std::max(0.05f * (hi - lo), 1e-6f * std::max(std::fabs(hi), 1.0f));
  lo -= pad;
  hi += pad;
  if (!(tmax > 0)) tmax = 1;

  ImGui::TextUnformatted("total energy (J) over time (s)");
  const float w = std::max(60.0f, ImGui::GetContentRegionAvail().x), h = 140.0f;
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("energy_plot", ImVec2(w, h));
  ui_mark("energy_plot");
  const ImVec2 p1(p0.x + w, p0.y + h);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(p0, p1, IM_COL32(25, 27, 32, 255));
  dl->AddRect(p0, p1, IM_COL32(90, 90, 100, 255));
  dl->PushClipRect(p0, p1, true);
  std::vector<ImVec2> pts;
  for (const auto& r : st.runs) {
    pts.clear();
    for (size_t i = 0; i < r.total.size(); ++i) {
      float v = r.total[i];
      if (!std::isfinite(v)) break;
      v = std::clamp(v, lo - (hi - lo), hi + (hi - lo));
      pts.emplace_back(p0.x + w * r.time_s[i] / tmax, p1.y - h * (v - lo) / (hi - lo));
    }
    if (pts.size() >= 2) dl->AddPolyline(pts.data(), int(pts.size()), run_color(r.integrator), 0, 1.5f);
  }
  dl->PopClipRect();
  char label[64];
  std::snprintf(label, sizeof label, "%.4g", hi);
  dl->AddText(ImVec2(p0.x + 3, p0.y + 2), IM_COL32(170, 170, 180, 255), label);
  std::snprintf(label, sizeof label, "%.4g", lo);
  dl->AddText(ImVec2(p0.x + 3, p1.y - 16), IM_COL32(170, 170, 180, 255), label);
  std::snprintf(label, sizeof label, "%.3g s", tmax);
  dl->AddText(ImVec2(p1.x - ImGui::CalcTextSize(label).x - 3, p1.y - 16), IM_COL32(170, 170, 180, 255), label);

  for (const auto& r : st.runs) {
    const ImVec2 c = ImGui::GetCursorScreenPos();
    const float lh = ImGui::GetTextLineHeight();
    dl->AddRectFilled(ImVec2(c.x, c.y + 0.3f * lh), ImVec2(c.x + 0.8f * lh, c.y + 0.8f * lh + 0.3f * lh),
                      run_color(r.integrator));
    ImGui::Dummy(ImVec2(lh, lh));
    ImGui::SameLine();
    const JobStatus js = r.job ? r.job->snapshot() : JobStatus{};
    char text[160];
    const double d = r.drift_percent();
    if (unstable(r))
      std::snprintf(text, sizeof text, "%-6s unstable (%s)", r.integrator.c_str(), job_state_name(js.state));
    else if (d < 0)
      std::snprintf(text, sizeof text, "%-6s (%s)", r.integrator.c_str(), job_state_name(js.state));
    else
      std::snprintf(text, sizeof text, "%-6s drift %.3g%%  %zu frames (%s)", r.integrator.c_str(), d,
                    r.total.size(), job_state_name(js.state));
    if (ImGui::Selectable(text, app.take.dir() == r.take)) app.cmd_open_take(r.take);
    ui_mark("legend_" + r.integrator);
    if (js.state == JobState::Failed && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", js.error.c_str());
  }
  ImGui::TextDisabled("drift = max|E - E0| / max(kinetic max, potential range)");
}


}  // namespace pliant::editor
