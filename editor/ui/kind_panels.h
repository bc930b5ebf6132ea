// Per-kind parts of the shared panels. The inspector, viewport, jobs and
// timeline panels look up the document's scene kind here and call what the
// kind provides; a missing entry falls back to the shared, generic UI.
// Each kind fills its table in ui/<kind>_panels.cpp.
#pragma once
#include <imgui.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace pliant::editor {

class App;

struct KindPanels {
  std::string kind;  // scene "kind"
  // Inspector: typed widgets for the kind's fields (drawn after name/kind).
  void (*inspector)(App&) = nullptr;
  // Top-level scene keys the inspector draws itself; the rest go under "Other fields".
  std::vector<std::string> typed_keys;
  // Jobs panel: above the Run button (planner / optimizer settings, live plots).
  void (*jobs)(App&) = nullptr;
  // Viewport: extra toolbar widgets after the shared ones (same line).
  void (*viewport_toolbar)(App&) = nullptr;
  // Viewport: an edit mode that replaces the result view (return true when it
  // drew the viewport itself, e.g. a placement or lattice preview).
  bool (*viewport_editor)(App&) = nullptr;
  // Viewport: ImGui overlays over the drawn result (gizmos, labels, plots);
  // (x, y, w, h) is the image rectangle in screen pixels.
  void (*viewport_overlay)(App&, float x, float y, int w, int h) = nullptr;
  // Viewport: the kind shows a frame of its own instead of the take's (a live
  // simulation); called once per UI frame, return true when it did the upload.
  bool (*viewport_frame)(App&) = nullptr;
  // Timeline: under the frame slider (key poses, markers).
  void (*timeline)(App&) = nullptr;
  // A file dropped on the window while a scene of this kind is open (a mesh, a
  // model): return true when taken. Called before the generic handling, so a
  // kind may take .json model files that are not scenes.
  bool (*on_drop)(App&, const std::string& path) = nullptr;
};

// The table for `kind`, or null for kinds without one (smoke uses its own files).
const KindPanels* kind_panels(const std::string& kind);
// The document's scene kind ("" when the scene has none).
std::string scene_kind(const App& app);

const KindPanels& liquid_panels();
const KindPanels& soft_panels();
const KindPanels& articulated_panels();

// Per-kind UI state that is not part of the document (tool choice, selection,
// slider positions): one object per kind, created on first use.
struct KindUiState {
  virtual ~KindUiState() = default;
};
class KindUiStates {
 public:
  template <class T>
  T& get(const std::string& kind) {
    auto& p = states_[kind];
    if (!p || !dynamic_cast<T*>(p.get())) p = std::make_unique<T>();
    return static_cast<T&>(*p);
  }

 private:
  std::map<std::string, std::unique_ptr<KindUiState>> states_;
};

}  // namespace pliant::editor
