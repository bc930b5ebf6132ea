// Internal: the pouring planners. Each returns a source trajectory that the job
// then validates with the full simulator.
#pragma once
#include <nlohmann/json.hpp>

#include "pliant/core/progress.h"
#include "pliant/liquid/liquid.h"

namespace pliant::liquid {

// Planner "simplified" (section 2.5): lookup tables + Bernoulli outflow +
// ballistic parcels, CMA-ES over a smooth trajectory. `info` gets planner metrics.
Trajectory plan_simplified(const LiquidModel& m, Progress& progress, nlohmann::json* info);
// Planner "correction" (Algorithm 2): alternate full simulation and a small
// optimisation of the trajectory under the rigid-follow particle model.
Trajectory plan_correction(const LiquidModel& m, Progress& progress, nlohmann::json* info);

// Simulates m (with its source_path) to the end; returns final fractions.
std::array<double, 3> simulate_fractions(const LiquidModel& m, Progress* progress = nullptr);

}  // namespace pliant::liquid
