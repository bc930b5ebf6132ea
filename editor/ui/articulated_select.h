// Selecting a body in the articulated viewport (click it; click empty space or
// Esc clears) and the inspector's "Selected body" section for the shown frame:
// name, mass, the body frame's world position, its joints (qpos recovered from
// the take's body poses, qvel by central differences of neighbouring frames,
// limits) and the contacts touching it (point, depth, force, the other side).
// Takes store body poses and contact point + force only, so the joint values
// come from inverse kinematics with the engine's forward kinematics and a
// contact's bodies from the distance of its point to the posed geoms.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

namespace pliant::editor {

class App;
struct ArticulatedSelectionSolver;  // the take's compiled model and solved frames

struct ArticulatedJointInfo {
  std::string name, type;  // type: hinge, slide, ball, free
  std::vector<double> qpos, qvel;
  bool limited = false;
  double range_min = 0, range_max = 0;  // rad (hinge, ball) or m (slide)
};
struct ArticulatedContactInfo {
  std::array<float, 3> point{0, 0, 0}, force{0, 0, 0};
  double magnitude = 0;  // N
  double depth = -1;     // m: |force| / stiffness (the take's force is k depth n); -1 unknown
  std::string other;     // the other body's name or "plane obstacle", ...
};
struct ArticulatedSelection {
  // What was computed (the cache key).
  std::string take_dir;
  int frame = -1, body = 0;
  size_t take_frames = 0;
  // The selected body at that frame.
  std::string body_name;
  double mass = 0;
  std::array<float, 3> world_pos{0, 0, 0};  // body frame origin (take body_pose)
  std::vector<ArticulatedJointInfo> joints;
  std::vector<ArticulatedContactInfo> contacts;
  double ik_residual = 0;  // pose residual of the recovered qpos (m)
  std::string error;
  std::shared_ptr<ArticulatedSelectionSolver> solver;
};

// Viewport overlay part: a left click (press and release without a drag) in
// the image rectangle (x, y, w, h) picks the nearest body along the camera ray
// through the click (static obstacles hide what is behind them); a click that
// hits no body, or Esc, clears the selection.
void articulated_viewport_pick(App& app, float x, float y, int w, int h);
// Selects body `body` of the shown take's model (0 clears). False when there is
// no such body.
bool articulated_select_body(App& app, int body);
// The selection refreshed for the shown take and frame (null when nothing is
// selected); re-resolves the body by name when another take is shown and sets
// the drawer's highlight (called once per UI frame by the viewport toolbar).
const ArticulatedSelection* articulated_selection(App& app);
// The inspector's "Selected body" section (nothing when no body is selected).
void draw_selected_body(App& app);

}  // namespace pliant::editor
