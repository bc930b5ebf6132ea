// Edits of liquid scene documents as pure JSON -> JSON functions (the panels
// hand the result to Document::edit, one undo step per user action), so they
// are unit tested without a UI. Scene format: engine/liquid/README.md.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pliant::editor {

// "source" or "target".
using ContainerRole = const char*;

// Length of the run: time.frames * time.dt_s (defaults as in the engine).
double liquid_duration_s(const nlohmann::json& scene);
int liquid_dim(const nlohmann::json& scene);

// Key poses of the hand-drawn source trajectory (/source/trajectory).
std::vector<double> liquid_key_times(const nlohmann::json& scene);
// Inserts a key at time_s (kept sorted; key times stay strictly increasing),
// its pose interpolated linearly between the neighbouring keys (or the
// source's static pose). *index = the new key's index. Returns the scene
// unchanged (and *index = -1) when a key already sits within 1e-3 s.
nlohmann::json liquid_add_key(const nlohmann::json& scene, double time_s, int* index);
nlohmann::json liquid_delete_key(const nlohmann::json& scene, int index);
// Moves key `index` to time_s, clamped strictly between its neighbours.
nlohmann::json liquid_move_key(const nlohmann::json& scene, int index, double time_s);

// Moves key `index`'s position by (dx, dy) metres (x-y plane; z and tilt kept).
nlohmann::json liquid_move_key_position(const nlohmann::json& scene, int index, double dx, double dy);
// Sets key `index`'s tilt (degrees, positive pours toward +x).
nlohmann::json liquid_set_key_tilt(const nlohmann::json& scene, int index, double tilt_deg);
// Makes a planned trajectory (a take's metrics "trajectory": [{time_s,
// position_m, tilt_deg}]) the scene's hand-drawn one and sets the planner to
// "none", so the plan can be edited key by key. Unchanged when `keys` is not a
// non-empty array or the scene has no source.
nlohmann::json liquid_adopt_trajectory(const nlohmann::json& scene, const nlohmann::json& keys);

// Moves a container by (dx, dy) metres; the source's key poses move with it.
nlohmann::json liquid_move_container(const nlohmann::json& scene, ContainerRole role, double dx, double dy);
// Sets the cavity radius and height of an inline container (no-op when the
// container is a file path: inline it first).
nlohmann::json liquid_resize_container(const nlohmann::json& scene, ContainerRole role, double radius_m,
                                       double height_m);
bool liquid_container_is_inline(const nlohmann::json& scene, ContainerRole role);
// Replaces a container path by the file's object ("comment" dropped), so the
// scene is self-contained and its sizes editable. Relative paths resolve
// against scene_dir. false + *err when the file cannot be read.
bool liquid_inline_container(nlohmann::json* scene, ContainerRole role, const std::filesystem::path& scene_dir,
                             std::string* err);

// Makes a closed triangle mesh file (.obj/.stl/.ply, engine: {"shape": "mesh",
// "file": ...}) the container of `role` (created at the origin when missing);
// `file` is stored as given (the caller makes it relative to the scene).
nlohmann::json liquid_set_mesh_container(const nlohmann::json& scene, ContainerRole role, const std::string& file);
// True for the mesh file extensions the engine's container loader takes.
bool liquid_is_mesh_file(const std::filesystem::path& path);

// Container files (*.json) in a folder, sorted by name.
std::vector<std::filesystem::path> liquid_container_library(const std::filesystem::path& dir);

}  // namespace pliant::editor
