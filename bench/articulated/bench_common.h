// Shared by bench_articulated's files: result rows, CPU clocks, contact-free chains, timed rollouts, the cases.
#pragma once
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "pliant/articulated/articulated.h"
#include "pliant/articulated/io.h"
#include "pliant/articulated/mpc.h"
#include "pliant/articulated/sim.h"
#ifdef PLIANT_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace art_bench {

using namespace pliant::articulated;
using Clock = std::chrono::steady_clock;

// Every emitted row (written to the results file at the end) and the machine line.
extern nlohmann::json g_results;
extern std::string g_machine;
void emit(nlohmann::json j);

struct Outcome {
  double drift = 0, wall = 0, sim_time = 0, iterations = 0;
  int steps = 0;
  bool stable = true;
};

struct Timing {
  double cpu = 0, wall = 0;
};

double thread_cpu_s();
double load_average();
nlohmann::json row(const std::string& c, const std::string& method, int links, double dt, const Outcome& o);

// `steps` steps from `initial`, the fastest of `reps` runs in thread CPU time; the
// last run's LM iteration and contact statistics (sums over the steps) and its end.
struct TimedRollout {
  double cpu_s = 1e300;
  double iterations = 0, max_iterations = 0;
  double contacts = 0, pair_contacts = 0, max_pair_depth = 0;
  State final;
};
TimedRollout timed_rollout(const Model& m, const SimOptions& o, const State& initial, int steps, int reps);

// Contact-free chains (bench_chains.cpp): energy range, initial state, the energy-drift
// run and the stepping-only timing.
double chain_range(const Model& m, int links, double len);
State chain_initial(const Model& m, bool tilt);
Outcome run_ours(const Model& m, Integrator integ, double dt, double duration, const State& init, double range);
Timing time_ours(const Model& m, Integrator integ, double dt, double duration, const State& init);
#ifdef PLIANT_HAVE_MUJOCO
mjModel* mujoco_load(const std::string& xml, std::string* error);
#endif

// The cases. Chains (bench_chains.cpp): the dt sweep of every integrator, then per link
// count the matched-accuracy re-timing (bench_matched.cpp); cost per step; batched rollouts.
void chain_cases(double duration, const std::vector<int>& link_counts, const std::vector<double>& dts,
                 const std::string& only_case, const std::string& only_methods);
void matched_case(const char* chain_case, int links, const std::string& xml, const Model& m, const State& init,
                  double duration, const std::vector<std::pair<std::string, double>>& candidates);
void cost_per_step_case();
void batched_case(bool quick);
// Contact (bench_contact.cpp): slope creep and box slide against MuJoCo; the body-body pile.
void contact_cases(bool quick);
void pile_case(bool quick);
// Meshes (bench_meshes.cpp): mesh-mesh stack, static terrain, obstacle features on meshes.
void mesh_mesh_case(bool quick);
void mesh_terrain_case(bool quick);
void mesh_features_case(bool quick);
// Joint frictionloss (bench_friction.cpp): rotor spin-down and a friction-held pendulum against MuJoCo.
void joint_friction_case(bool quick);
// MuJoCo's own humanoid.xml / 22_humanoids.xml falling limp (bench_humanoid.cpp).
void humanoid_case(bool quick);

}  // namespace art_bench
