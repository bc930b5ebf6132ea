// Document-side helpers for soft character scenes (issue 5): what the viewport
// draws from a scene (ground or water, start, goal, heading, jump height) read
// tolerantly from the JSON (a half-typed scene still draws), and the scene edits
// of the character workflow (pinned vertices = the partial-keyframe objective).
// No GL and no engine: the drawer, the panels and the unit tests share them.
#pragma once
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pliant::editor {

using SoftVec3 = std::array<double, 3>;

struct SoftSceneInfo {
  bool water = false;         // environment.type == "water"
  bool ground = true;         // a ground plane (default: not in water)
  double ground_y = 0;        // ground_height_m
  SoftVec3 start_offset{0, 0, 0};
  double dt_s = 1.0 / 30;
  int frames = 100;           // simulation.frames
  int horizon = 60;           // optimizer.horizon_frames (default min(frames, 60))
  bool has_position = false;
  SoftVec3 position_target{0, 0, 0};
  bool has_velocity = false;
  SoftVec3 velocity_target{0, 0, 0};
  bool has_heading = false;
  SoftVec3 heading_direction{1, 0, 0}, heading_axis{1, 0, 0};
  bool has_jump = false;
  double jump_height = 0;
  bool has_distance = false;
  double distance = 0;
  SoftVec3 distance_direction{1, 0, 0};
  struct Sphere {
    SoftVec3 center{0, 0, 0};
    double radius = 0;
  };
  std::vector<Sphere> spheres;  // environment.obstacles of type "sphere"
};

bool is_soft_scene(const nlohmann::json& scene);
// Never throws: missing or mistyped fields keep the engine's defaults.
SoftSceneInfo soft_scene_info(const nlohmann::json& scene);

// The goal the viewport frames besides the start: the position target, else
// start + velocity target x the take's duration, else start + distance.
// `start` is the character's centre at frame 0 (metres).
SoftVec3 soft_goal(const SoftSceneInfo& info, const SoftVec3& start);

// One pinned vertex of the partial-keyframe objective.
struct SoftPin {
  int entry = -1;   // index in /objectives/keyframes/frames
  int frame = 0;
  int vertex = 0;
  SoftVec3 offset{0, 0, 0};
};
std::vector<SoftPin> soft_pins(const nlohmann::json& scene);
// The pins at `frame`.
std::vector<SoftPin> soft_pins_at(const nlohmann::json& scene, int frame);

// Scene with `vertex` pinned at `frame` to rest + start offset + `offset` (metres):
// joins an entry of the same frame and offset, else adds one; creates the
// keyframes objective (weight 10) when missing. Pinning an already pinned
// vertex at that frame moves it to the new offset.
nlohmann::json soft_with_pin(const nlohmann::json& scene, int frame, int vertex, const SoftVec3& offset);
// Scene without the pin of `vertex` at `frame` (empty entries are removed).
nlohmann::json soft_without_pin(const nlohmann::json& scene, int frame, int vertex);

}  // namespace pliant::editor
