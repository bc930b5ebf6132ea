// Scenes shared by the soft unit tests (one literal, not a copy per test file).
#pragma once
#include <string>

#include "pliant/core/scene.h"
#include "pliant/soft/environment.h"

namespace pliant::soft::test {

// Flat ground (the plane y = 0) with friction coefficient mu.
inline Environment ground(double mu) {
  Environment env;
  env.friction = mu;
  env.obstacles.push_back({Obstacle::Plane, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 0});
  return env;
}

// The small T-shape (t_shape.obj, 4 cells, 6 modes, 30 frames of 25 ms) of the
// jump tests in test_objective.cpp and test_spacetime.cpp; `objectives` and
// `optimizer` are JSON object texts.
inline Scene t_shape_scene(const std::string& objectives, const std::string& optimizer) {
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "t_shape.obj", "resolution": 4, "modes": 6},
    "material": {"density_kg_per_m3": 1000, "young_pa": 1e5, "poisson": 0.3},
    "environment": {"type": "ground", "friction": 0.8},
    "simulation": {"dt_s": 0.025, "frames": 30},
    "controller": {"modes": 6, "kernels": 3, "period_s": 0.6, "max_activation_rel": 1.0},
    "objectives": )" + objectives + R"(, "optimizer": )" + optimizer + "}";
  return parse_scene(text, "t.json", std::string(PLIANT_ASSETS_DIR) + "/characters");
}

// soft_worm_crawl.json's worm at resolution 6 (3 x 3 DMP kernels, 12 parameters)
// for 20 frames of 40 ms, the horizon of the resume tests (test_soft_job_resume.cpp);
// its optimizers keep gaining for a dozen iterations. `optimizer`: JSON object text.
inline Scene worm_crawl_scene(const std::string& optimizer) {
  const std::string text = R"({"pliant": 1, "kind": "soft",
    "character": {"mesh": "worm.obj", "resolution": 6, "modes": 6},
    "material": {"density_kg_per_m3": 1000, "young_pa": 5e4, "poisson": 0.3},
    "environment": {"type": "ground", "friction": 0.6},
    "simulation": {"dt_s": 0.04, "frames": 20},
    "controller": {"modes": 3, "kernels": 3, "period_s": 0.8, "max_activation_rel": 0.8},
    "objectives": {"velocity": {"target_m_per_s": [0.05, 0, 0], "weight": 100}, "effort": {"weight": 1e-3}},
    "optimizer": )" + optimizer + "}";
  return parse_scene(text, "worm.json", std::string(PLIANT_ASSETS_DIR) + "/characters");
}

// The jump objective of those tests: 3 cm, weight 100, effort 1e-4.
inline const char* t_shape_jump_objectives() {
  return R"({"jump": {"height_m": 0.03, "weight": 100}, "effort": {"weight": 1e-4}})";
}

}  // namespace pliant::soft::test
