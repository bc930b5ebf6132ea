// Articulated bodies with frictional contact (issue 6; dissertation ch. 5; Pan &
// Manocha, "Time integrating articulated body dynamics using position-based
// collocation methods", WAFR 2018). Public entry points of job kind "articulated".
//
// Numerical choices (details in sim.h, contact.h, dynamics.h):
// - generalized coordinates, MuJoCo's joint conventions (hinge, slide, ball, free);
// - PBAD 2nd/3rd order: backward position stencils collocated at t_{i+1}, each step
//   an energy minimisation by Levenberg-Marquardt whose Gauss-Newton system is solved
//   in O(N) by the articulated-body recursion;
// - explicit baselines: semi-implicit Euler and RK4 with O(N) forward dynamics;
// - contact: penalty on penetration; friction lagged on the previous normal force
//   (smoothed dry Coulomb or the C_k tangential model).
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "pliant/articulated/io.h"
#include "pliant/articulated/mpc.h"
#include "pliant/articulated/sim.h"
#include "pliant/core/job.h"
#include "pliant/core/scene.h"

namespace pliant::articulated {

struct ArticulatedScene {
  Model model;
  SimOptions options;
  double duration_s = 5;
  int steps = 500;
  int write_every = 1;
  int frames = 501;  // including the initial state
  State initial;
  std::optional<MpcOptions> mpc;  // hopper MPC: plan with CEM, write the executed trajectory
};

ArticulatedScene articulated_compile(const Scene& scene);  // throws InputError

// Take record: "body_pose" [nbodies-1, 7] (x y z, qw qx qy qz; world body omitted),
// "contacts" [n, 6] (point xyz, force xyz), "energy" [3] (kinetic, potential, total).
Record articulated_frame_record(const Model& m, const SimOptions& o, const State& s, int index,
                                SimWorkspace& ws);

nlohmann::json articulated_run_job(JobContext& ctx);
int articulated_job_frames(const Scene& scene);
nlohmann::json articulated_summary(const Scene& scene);

}  // namespace pliant::articulated
