// One function per panel; each reads the App's document/jobs/take and sends
// changes back through App commands or the document's undoable edits.
#pragma once

namespace pliant::editor {

class App;

struct PanelRect {
  float x, y, w, h;
};

// Fixed layout for any window size (ImGui 1.86 from Debian has no docking).
struct Layout {
  PanelRect inspector, viewport, timeline, jobs, log;
};
Layout compute_layout(float width, float height, float menu_h);

void draw_menu_bar(App& app);
void draw_file_dialog(App& app);
void draw_recovery_prompt(App& app);
void draw_inspector_panel(App& app, const PanelRect& r);
void draw_viewport_panel(App& app, const PanelRect& r);
void draw_jobs_panel(App& app, const PanelRect& r);
void draw_timeline_panel(App& app, const PanelRect& r);
void draw_log_panel(App& app, const PanelRect& r);

}  // namespace pliant::editor
