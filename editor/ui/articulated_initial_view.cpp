// An articulated scene with no take yet shows its model at the initial state (the
// kind's viewport_frame hook): compiled from the document once per revision and drawn
// through the take's own drawer from the record a run writes as frame 0
// (articulated_frame_record), so bodies, contacts and the energy readout are what
// Simulate's first frame will show. The compile is the one the model summary uses.
#include "pliant/core/scene.h"
#include "pliant/core/take.h"
#include "render/articulated_drawer.h"
#include "ui/app.h"
#include "ui/articulated_panels.h"

#ifdef PLIANT_HAVE_ARTICULATED
#include "pliant/articulated/articulated.h"
#endif

namespace pliant::editor {

bool articulated_initial_frame(App& app) {
#ifndef PLIANT_HAVE_ARTICULATED
  (void)app;
  return false;
#else
  if (!app.take.dir().empty()) return false;  // a take (even an empty one) is shown instead
  ArticulatedUiState& st = app.kind_ui.get<ArticulatedUiState>("articulated");
  const bool same_doc = st.initial_doc == app.doc.id();
  // Uploaded already and nothing else uploaded since: the renderer still shows it.
  if (same_doc && st.initial_revision == app.doc.revision() && st.initial_uploads == app.viewport.uploads)
    return st.initial_ok;
  st.initial_doc = app.doc.id();
  st.initial_revision = app.doc.revision();
  st.initial_ok = false;
  if (const auto a = articulated_document_compiled(app, nullptr)) {
    try {
      articulated::SimWorkspace ws;
      const Record rec = articulated::articulated_frame_record(a->model, a->options, a->initial, 0, ws);
      articulated_drawer_set_scene_dir(articulated_document_scene(app).dir);
      if (!same_doc) app.renderer.reset_framing();
      app.renderer.set_frame(rec, &app.doc.scene());
      if (!same_doc) app.viewport.camera.reset();
      st.initial_ok = true;
    } catch (const std::exception&) {
    }
  }
  // A compile error (the inspector shows it): "No take yet" here.
  if (!st.initial_ok && app.renderer.has_frame()) app.renderer.clear_frame();
  st.initial_uploads = ++app.viewport.uploads;
  return st.initial_ok;
#endif
}

}  // namespace pliant::editor
