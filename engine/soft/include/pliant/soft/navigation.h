// Navigation of a soft character (dissertation section 4.6; ALGORITHMS.md section 3,
// "Navigation"): a few gaits that differ only in their DMP parameters (forward, turn
// left, turn right) are optimized once; each is measured as a motion primitive, the
// planar rigid motion (forward, sideways, yaw) of one controller period in the body
// frame. RRT* (OMPL, ompl::geometric::RRTstar, then shortcutting) plans a short path
// for the centre of mass to the goal disc around the obstacles' footprints, inflated
// by the body's radius + clearance (reported as the route). Execution is closed
// loop on the re-simulated body: every controller period each gait is
// re-simulated from the current state (DMP phase kept) and the one whose end pose
// has the smallest cost to go is played (a switch is held two periods). The cost
// to go (periods to the goal disc) comes from a breadth-first search over a
// lattice of planar poses (x, z, 180 yaw bins) x (gait, settled or just switched)
// whose edges are the held gaits' primitives and, for a switch, the transition
// primitives (the period after it, measured: gaits are not stationary), so it
// replans from wherever the body is. Planar coordinates are (x, z) of the world
// (y up); yaw = atan2(h_z, h_x) of the body axis h. A Dubins-space RRT* was tried first
// (see navigation.cpp).
// Without OMPL (libompl-dev) navigation is unavailable: soft_compile rejects a
// "navigation" section with an InputError.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "pliant/soft/objective.h"

namespace pliant::soft {

struct Gait {
  std::string name;
  Eigen::VectorXd theta;
  double forward_m = 0, side_m = 0, yaw_rad = 0;  // per period, body frame at its start
};

struct NavObstacle {
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();  // (x, z)
  double radius_m = 0;
};

struct NavSettings {
  bool enabled = false;
  Eigen::Vector2d goal_m = Eigen::Vector2d::Zero();  // (x, z)
  double goal_tolerance_m = 0.25;
  std::vector<NavObstacle> obstacles;
  Eigen::Vector3d body_axis = Eigen::Vector3d::UnitX();
  double speed_m_per_s = 0.15;       // gait targets
  double turn_rate_rad_per_s = 0.5;
  double clearance_m = 0.05;         // added to the body radius when inflating obstacles
  double planning_time_s = 1.0;
  int max_frames = 1500;
  std::vector<Eigen::VectorXd> cached_theta;  // forward, left, right (empty: optimize)
};

// True when this build has OMPL.
bool navigation_available();

// Objectives of gait k (0 forward, 1 left, 2 right) for problem p.
Objectives gait_objectives(const NavSettings& nav, int k);

// Mirror image of a gait under the reflection z -> 2 z_com - z (turn left <-> turn
// right) for a body symmetric under it: each controlled mode is then even or odd
// (U_k^T M P U_k = +-1) and its DMP parameters keep or flip sign. False when the
// lattice or a controlled mode is not symmetric.
bool mirror_gait(const Problem& p, const Eigen::VectorXd& theta, Eigen::VectorXd* mirrored);

// Measures a gait's primitive: simulates `warmup + periods` controller periods from
// rest and averages the per-period planar motion over the last `periods`.
Gait measure_gait(const Problem& p, const std::string& name, const Eigen::VectorXd& theta,
                  const Eigen::Vector3d& body_axis, int warmup = 2, int periods = 6);

// Transition primitives: entry prev * G + g is the planar motion (forward, side, yaw;
// body frame at its start) of one period of gait g right after `warmup` periods of
// gait prev from rest (the period after a switch differs from a held gait).
std::vector<Eigen::Vector3d> transition_primitives(const Problem& p, const std::vector<Gait>& gaits,
                                                   const Eigen::Vector3d& body_axis, int warmup = 2);

// Planar pose (x, z, yaw) of a state.
Eigen::Vector3d planar_pose(const SoftState& s, const Eigen::Vector3d& body_axis);

// Horizontal radius of the body (largest distance of a rest node from the COM axis).
double body_radius_m(const Character& ch);

// RRT* over (x, z) from pose start to the goal disc, avoiding obstacles inflated by
// `inflate`; dense poses (x, z, yaw of the path) along it. rho (the gaits' turning
// radius) is reported, not used by the planner.
// Throws std::runtime_error when no path is found or OMPL is missing.
std::vector<Eigen::Vector3d> plan_dubins_path(const Eigen::Vector3d& start, const NavSettings& nav, double rho,
                                              double inflate, unsigned seed = 1);

struct NavResult {
  std::vector<Eigen::Vector3d> planned;  // poses along the planned path
  std::vector<int> gait_sequence;        // one gait index per period
  std::vector<Eigen::Vector3d> com;      // simulated COM per frame (frame 0 first)
  double turning_radius_m = 0;
  double final_distance_m = 0;           // COM to goal, horizontal
  double min_clearance_m = 0;            // COM to the nearest obstacle footprint (not inflated)
  bool reached = false;
  int primitive_updates = 0;             // cost-to-go rebuilds (0 since the transition lattice; kept for the API)
};

// Plans and executes: on_frame(state, gait) after every simulated frame.
NavResult navigate(const Problem& p, const std::vector<Gait>& gaits, const NavSettings& nav,
                   const std::function<void(const SoftState&, int)>& on_frame = {});

}  // namespace pliant::soft
