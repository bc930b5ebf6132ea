// Container geometry of liquid scenes for the editor, from the liquid engine's
// own compile step (so the editor draws exactly the walls the solver sees).
// Registers itself as the liquid drawer's resolver (render/liquid_drawer.h).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pliant/core/take.h"
#include "render/liquid_drawer.h"

namespace pliant::editor {

// Folders that relative container paths are tried against (the open scene's
// folder, the take's scene folder); assets/scenes of the source tree comes last.
void liquid_set_scene_dirs(std::vector<std::filesystem::path> dirs);

// Compiles `scene` (a liquid scene document) and fills *out; false + *err when
// it does not compile or the liquid module is not built.
bool liquid_scene_geometry(const nlohmann::json& scene, LiquidSceneGeometry* out, std::string* err);

// The scene's state before the first step as a take frame record (particles of
// the initial liquid region, speed, source_pose / target_pose at t = 0,
// fractions): what the placement view draws before any run. false + *err when
// the scene does not compile.
bool liquid_initial_frame(const nlohmann::json& scene, Record* out, std::string* err);

}  // namespace pliant::editor
