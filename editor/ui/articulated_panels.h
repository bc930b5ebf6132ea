// Articulated scenes in the editor (issue 6): typed inspector, Simulate and
// "Compare integrators" (one job per integrator on scene variants, their total
// energy over time plotted together with a drift legend), viewport toolbar
// (contacts, follow, force scale) and overlay, timeline readout, model drops.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ui/kind_panels.h"

namespace pliant::editor {

class App;
class JobProcess;
}  // namespace pliant::editor
namespace pliant {
class TakeReader;
struct Scene;
}
namespace pliant::articulated {
struct ArticulatedScene;
}
namespace pliant::editor {

// One run of "Compare integrators": its job, take and the energy read so far.
struct IntegratorRun {
  std::string integrator;
  std::filesystem::path take;
  JobProcess* job = nullptr;  // owned by app.jobs
  std::shared_ptr<TakeReader> reader;
  size_t frames_read = 0;
  std::vector<float> time_s, total, kinetic, potential;
  bool finite = true;
  // 100 * max |E(t) - E(0)| / energy scale, the scale being the largest of the
  // kinetic energy's maximum and the potential energy's range over the run
  // (both equal the energy exchanged by a conservative swing); -1 before 2 frames.
  double drift_percent() const;
};

struct ArticulatedSelection;  // ui/articulated_select.h

struct ArticulatedUiState : KindUiState {
  bool compare_pick[5] = {true, true, false, true, true};  // pbad2, pbad3, pbad4, euler, rk4
  std::vector<IntegratorRun> runs;                  // the newest comparison
  std::string compare_error;
  // Model summary cache (per document revision).
  uint64_t summary_doc = 0, summary_revision = ~uint64_t(0);
  std::string summary;
  // The body picked in the viewport (ui/articulated_select.cpp): UI state, not
  // saved and not undoable. Its index in the shown take's model (0: none) and its
  // name (a take with another model keeps the body of that name, if any).
  int selected_body = 0;
  std::string selected_name;
  std::shared_ptr<ArticulatedSelection> selection;  // what the inspector shows
  // The document compiled by the engine (articulated_document_compiled), per revision.
  uint64_t compiled_doc = 0, compiled_revision = ~uint64_t(0);
  std::shared_ptr<const articulated::ArticulatedScene> compiled;  // null on a compile error
  std::string compile_error;
  // The initial-state view (no take yet): the document and revision it was built
  // for and the viewport upload count after it (another upload means redraw it).
  uint64_t initial_doc = 0, initial_revision = ~uint64_t(0);
  uint64_t initial_uploads = ~uint64_t(0);
  bool initial_ok = false;
};

// Integrators "Compare integrators" can run, in the order of compare_pick.
const std::vector<std::string>& articulated_integrators();

// Starts one job per picked integrator on variants of the document's scene
// (integrator replaced, relative model path made absolute), writing each variant
// beside its take "<take base>-<integrator>". false + status on failure.
bool articulated_compare_integrators(App& app, const std::vector<std::string>& integrators);
// Reads new frames' energy of every comparison run (called each UI frame by the jobs panel).
void articulated_poll_compare(App& app);
// The comparison's total energy over time on one scale, with a legend (drift %, job
// state) whose entries open that run's take (articulated_energy_plot.cpp).
void articulated_draw_energy_plot(App& app);

// Simulate: `pliant run` on the document like Run (F5), except that a relative
// model path is made absolute first when the scene has to be copied beside the
// take (an unsaved document), where the relative path would no longer resolve.
bool articulated_simulate(App& app);

// The drawer's geometry source (render/articulated_drawer.h): compiles an
// articulated scene (model paths relative to `dir`) with the engine into the
// geoms, body count, mass and floating flag the drawer draws from. false + *err
// on an invalid scene or in a build without the articulated engine.
struct ArticulatedGeometry;
bool articulated_scene_geometry(const nlohmann::json& scene, const std::filesystem::path& dir,
                                ArticulatedGeometry* out, std::string* err);

// The document as the engine compiles it: its JSON, model paths relative to the
// scene file's folder (the working folder for an unsaved document).
Scene articulated_document_scene(const App& app);

// The document compiled by the engine once per revision, shared by the model
// summary and the initial-state view; null with the message in *err on a compile
// error. Only in builds with the articulated engine.
std::shared_ptr<const articulated::ArticulatedScene> articulated_document_compiled(App& app, std::string* err);

// The kind's viewport_frame hook (articulated_initial_view.cpp): with no take shown,
// uploads the model at its initial state; true while it shows that frame.
bool articulated_initial_frame(App& app);

// A dropped model file (.xml MJCF, or a .json that is a model, not a scene) on
// an articulated document becomes its "model" (path relative to the scene's
// folder); one undo step. Returns false when the drop is not for us.
bool articulated_on_drop(App& app, const std::string& path);

}  // namespace pliant::editor
