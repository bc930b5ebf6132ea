// Batched rollouts and a small environment API for planning/learning on PBAD
// (dissertation ch. 5, Fig. 5.1: one worker per trajectory, one LM iteration per
// pass so that no trajectory starves), and a CEM model-predictive controller.
#pragma once
#include <functional>
#include <vector>

#include "pliant/articulated/sim.h"

namespace pliant::articulated {

// Advances every state by `steps` steps. PBAD: in each pass every unfinished
// trajectory gets exactly one LM iteration (OpenMP over trajectories); explicit
// integrators: one step per pass. threads <= 0: OpenMP default.
// Returns the number of passes.
int batch_rollout(const Model& m, const SimOptions& o, std::vector<State>& states, int steps,
                  int threads);

// reset/step(action)/observation/reward on a model with actuators; the "forward"
// direction is +x of body 1 (the torso/root).
class Environment {
 public:
  Environment(const Model& m, const SimOptions& o, const State& initial, int substeps = 2,
              double ctrl_cost = 1e-3);
  void reset();
  void reset(const State& s);
  // Applies the action (one value per actuator, clamped to ctrlrange) for `substeps`
  // simulation steps. Returns false if the simulation failed (non-finite state).
  bool step(const VecX& action);
  VecX observation() const;   // qpos without the root x, then qvel
  double reward() const;      // forward velocity of body 1 over the last step minus control cost
  double forward_position() const;
  const State& state() const { return s_; }
  int action_size() const { return static_cast<int>(m_->actuators.size()); }

 private:
  const Model* m_;
  SimOptions o_;
  State init_, s_;
  SimWorkspace ws_;
  int substeps_;
  double ctrl_cost_, last_reward_ = 0;
};

struct MpcOptions {
  double duration_s = 2;   // executed time
  int horizon = 8;         // control steps planned
  int substeps = 2;        // simulation steps per control step
  int samples = 32;
  int elites = 6;
  int iterations = 3;      // CEM refinements per control step
  double noise = 0.6;      // initial std of the action distribution (fraction of range)
  unsigned seed = 1;
  double ctrl_cost = 1e-3;
  double upright_weight = 5;  // score penalty per unit (1 - cos tilt) of the torso
  double height_weight = 10;  // per metre of torso centre below 80% of its start height
};

struct MpcResult {
  std::vector<State> trajectory;  // every simulation step executed (starts at the initial state)
  double distance = 0;            // forward displacement of body 1
  double wall_s = 0;
};

// CEM MPC (sampling-based): at each control step samples action sequences,
// evaluates them with parallel rollouts, refits mean/std to the elites, executes
// the first action. on_step(i, state) after each executed simulation step; it may
// throw (cancellation).
MpcResult run_cem_mpc(const Model& m, const SimOptions& o, const State& initial, const MpcOptions& mpc,
                      const std::function<void(int, const State&)>& on_step);

}  // namespace pliant::articulated
