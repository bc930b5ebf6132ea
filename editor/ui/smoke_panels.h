// Smoke-specific parts of the shared panels (keyframe control). Other scene
// kinds add their own beside these; the shared panels dispatch on the kind.
#pragma once

namespace pliant::editor {

class App;

// Under the timeline slider: keyframe markers, + Key, Delete key, frame counter.
void draw_keyframe_markers(App& app);
// At the top of the jobs panel: resolution, frames, r, method, Solve, Cancel,
// Resume, objective and residual curves.
void draw_smoke_solve_panel(App& app);

}  // namespace pliant::editor
