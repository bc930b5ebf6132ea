// The Character mode's body, compiled off the UI thread: soft_preview_model()
// is called every frame the mode is shown; when the document's character or
// material changed it hands a copy of those sections to a worker
// (std::async) and returns at once, so the UI keeps drawing (the mode says
// "building lattice..." and shows the previous body meanwhile). One worker at
// a time: a result whose key is no longer the document's is dropped and the
// newest request is built next, so a newer edit supersedes an older one. The
// only state is the cache in SoftUi::preview.
#include <chrono>
#include <filesystem>
#include <functional>

#include "ui/app.h"
#include "ui/soft_ui.h"

#ifdef PLIANT_HAVE_SOFT
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"
#endif

namespace pliant::editor {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Compiles the preview document (worker thread: no App, no ImGui).
SoftPreviewBuild build_preview(uint64_t key, const std::string& text, const std::string& label, const fs::path& dir) {
  SoftPreviewBuild b;
  b.key = key;
#ifdef PLIANT_HAVE_SOFT
  try {
    const auto t0 = std::chrono::steady_clock::now();
    Scene scene = parse_scene(text, label, dir);
    auto m = std::make_shared<soft::SoftModel>(soft::soft_compile(scene));
    soft::soft_bind(*m);
    b.model = std::move(m);
    b.compile_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } catch (const std::exception& e) {
    b.error = e.what();
  }
#else
  (void)text;
  (void)label;
  (void)dir;
  b.error = "this editor was built without the soft module";
#endif
  return b;
}

}  // namespace

const SoftPreviewModel& soft_preview_model(App& app) {
  SoftUi& ui = soft_ui(app);
  SoftPreviewModel& pm = ui.preview;
  const json& s = app.doc.scene();
  json part = {{"character", s.contains("character") ? s["character"] : json()},
               {"material", s.contains("material") ? s["material"] : json()},
               {"dir", app.doc.has_path() ? app.doc.path().parent_path().string() : std::string()}};
  pm.wanted = std::hash<std::string>{}(part.dump()) | 1;

  // A finished build: installed when it is still what the document wants.
  if (pm.pending.valid() &&
      pm.pending.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    SoftPreviewBuild b = pm.pending.get();
    ++pm.builds;
    if (b.key == pm.wanted) {
      pm.key = b.key;
      pm.model = std::move(b.model);
      pm.error = std::move(b.error);
      pm.compile_s = b.compile_s;
      ui.amplitude_m.assign(pm.model ? size_t(pm.model->character.basis.r()) : 0, 0.0f);
    }
  }
  if (pm.pending.valid()) {
    ++pm.frames_while_building;
    return pm;
  }
  if (pm.key == pm.wanted) return pm;

  json doc = {{"pliant", 1}, {"kind", "soft"}, {"name", "preview"}};
  if (part["character"].is_object()) {
    doc["character"] = part["character"];
    doc["character"]["cubature"] = false;  // the preview needs modes only
  }
  if (part["material"].is_object()) doc["material"] = part["material"];
  doc["optimizer"] = {{"method", "none"}};
  const std::string label = app.doc.has_path() ? app.doc.path().string() : std::string("untitled.json");
  const fs::path dir = app.doc.has_path() ? app.doc.path().parent_path() : fs::path(".");
  pm.pending = std::async(std::launch::async, build_preview, pm.wanted, doc.dump(), label, dir);
  return pm;
}

}  // namespace pliant::editor
