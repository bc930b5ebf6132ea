#include "ui/kind_panels.h"

#include "ui/app.h"

namespace pliant::editor {

const KindPanels* kind_panels(const std::string& kind) {
  for (const KindPanels* p : {&liquid_panels(), &soft_panels(), &articulated_panels()})
    if (p->kind == kind) return p;
  return nullptr;
}

std::string scene_kind(const App& app) {
  const nlohmann::json& s = app.doc.scene();
  return s.is_object() && s.contains("kind") && s["kind"].is_string() ? s["kind"].get<std::string>() : "";
}

}  // namespace pliant::editor
