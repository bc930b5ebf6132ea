// The keyframes of a smoke scene's "control" section as the editor sees them:
// list, add, delete, move, and each target as a painted grid. Every function
// returns a NEW scene (the caller passes it to Document::edit, one undo step).
// Keyframe "slot" -1 is the initial density ("control.initial_density", a list
// of targets that the canvas replaces by one painted target).
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pliant/geom/painted_grid.h"

namespace pliant::editor {

inline constexpr int kInitialDensitySlot = -1;

struct KeyframeInfo {
  int index = 0;  // position in control.keyframes
  int frame = 0;  // 1..T
  std::string type;
};

bool is_smoke_scene(const nlohmann::json& scene);
// 2D smoke: grid.resolution has two entries; false for malformed scenes.
bool is_smoke_2d(const nlohmann::json& scene);
bool has_control(const nlohmann::json& scene);
// grid.resolution [nx, ny] (0, 0 when missing).
std::array<int, 2> smoke_resolution(const nlohmann::json& scene);
int smoke_frames(const nlohmann::json& scene);  // time.frames (0 when missing)
std::vector<KeyframeInfo> list_keyframes(const nlohmann::json& scene);
// Index of the keyframe at `frame`, or -2 when none.
int keyframe_at_frame(const nlohmann::json& scene, int frame);

// A control section with the defaults the solve panel shows (ADMM, r 1e-5, a
// circle of initial density) when the scene has none.
nlohmann::json default_control_section();
// Adds an empty painted keyframe (3D scenes: a sphere target) at `frame` (clamped to 1..T; a keyframe already
// there is kept); *index gets its position. Keyframes stay sorted by frame.
nlohmann::json with_keyframe_added(const nlohmann::json& scene, int frame, int* index);
nlohmann::json with_keyframe_removed(const nlohmann::json& scene, int index);
// Moves keyframe `index` to `frame` (clamped; refused when another keyframe is
// there: returns the scene unchanged); *new_index gets its sorted position.
nlohmann::json with_keyframe_moved(const nlohmann::json& scene, int index, int frame, int* new_index);
// The scene with slot's target replaced by `grid` as a painted target.
nlohmann::json with_painted_slot(const nlohmann::json& scene, int slot, const geom::PaintedGrid& grid);
// The scene with slot's target replaced by any target JSON (image import).
nlohmann::json with_slot_target(const nlohmann::json& scene, int slot, const nlohmann::json& target);

// The JSON target of a slot (null when missing): initial density -> its first entry
// when there is exactly one, else a "union" described by the whole list.
nlohmann::json slot_target(const nlohmann::json& scene, int slot);
// Rasterises the slot's target onto the scene grid (any target type, through the
// engine's control_compile); painted targets of the grid's size decode exactly.
// On failure returns an empty grid and sets *error.
geom::PaintedGrid rasterize_slot(const nlohmann::json& scene, const std::filesystem::path& scene_dir,
                                 int slot, std::string* error);

// Any-dimensional raster of a slot through control_compile (3D scenes: the slice
// view). dims gets {nx, ny, nz} (nz = 1 in 2D). Empty + *error on failure.
std::vector<float> rasterize_slot_density(const nlohmann::json& scene, const std::filesystem::path& scene_dir,
                                          int slot, std::array<int, 3>* dims, std::string* error);

}  // namespace pliant::editor
