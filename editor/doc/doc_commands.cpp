#include "doc/doc_commands.h"

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/smoke.h"

namespace pliant::editor {

namespace fs = std::filesystem;

nlohmann::json builtin_scene_template() {
  return nlohmann::json::parse(R"({
    "pliant": 1, "kind": "smoke", "name": "New plume",
    "grid": {"resolution": [48, 64], "cell_size_m": 0.02, "boundary": "closed"},
    "time": {"dt_s": 0.02, "frames": 60, "substeps": 1},
    "advection": "semi_lagrangian",
    "buoyancy_m_per_s2": 2.0,
    "pressure": {"solver": "mgpcg", "tolerance": 1e-6, "max_iterations": 200},
    "sources": [{"shape": "sphere", "center_m": [0.48, 0.16], "radius_m": 0.07,
                 "density_per_s": 4.0, "velocity_m_per_s": [0.0, 0.4],
                 "start_s": 0.0, "end_s": 1.5}],
    "forces": [], "initial_density": [],
    "output": {"velocity": true, "every": 1}
  })");
}

fs::path default_scene_path() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::vector<fs::path> candidates;
  if (!ec) {
    for (fs::path d = exe.parent_path(); !d.empty() && d != d.root_path(); d = d.parent_path())
      candidates.push_back(d / "assets/scenes/plume_2d.json");
  }
#ifdef PLIANT_SOURCE_DIR
  candidates.push_back(fs::path(PLIANT_SOURCE_DIR) / "assets/scenes/plume_2d.json");
#endif
  for (const auto& c : candidates)
    if (fs::exists(c, ec)) return c;
  return {};
}

void new_document(Document& doc) {
  nlohmann::json scene = builtin_scene_template();
  fs::path def = default_scene_path();
  if (!def.empty()) {
    try {
      scene = load_scene(def).doc;
    } catch (const std::exception&) {
    }
  }
  doc.reset(scene, {});
  doc.take_dir.clear();
}

std::string open_document(Document& doc, const fs::path& path) {
  try {
    Scene s = load_scene(path);
    doc.reset(s.doc, fs::absolute(path).lexically_normal());
    doc.take_dir.clear();
    return "";
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return path.string() + ": " + e.what();
  }
}

std::string save_document_as(Document& doc, const fs::path& path) {
  try {
    save_json_atomic(path, doc.scene());
    doc.mark_saved(fs::absolute(path).lexically_normal());
    return "";
  } catch (const std::exception& e) {
    return path.string() + ": cannot save: " + e.what();
  }
}

std::string save_document(Document& doc) {
  if (!doc.has_path()) return "the document has no file yet: use Save As";
  return save_document_as(doc, doc.path());
}

std::string validate_scene(const nlohmann::json& scene, const fs::path& path) {
  std::string label = path.empty() ? "untitled.json" : path.string();
  try {
    Scene s = parse_scene(scene.dump(), label, path.empty() ? fs::path(".") : path.parent_path());
    if (s.kind == "smoke") smoke::smoke_compile(s);
    return "";
  } catch (const std::exception& e) {
    return e.what();
  }
}

}  // namespace pliant::editor
