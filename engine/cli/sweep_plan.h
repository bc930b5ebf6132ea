// A parameter sweep (`pliant sweep SWEEP.json --shard i/n`): one scene, some of
// its values replaced by each combination of the listed values.
//
//   {
//     "pliant_sweep": 1,
//     "scene": "plume_2d.json",            relative to the sweep file
//     "out": "plume_sweep",                 takes go to OUT/run_0000, ... (default
//                                           "<sweep file stem>_takes" beside it)
//     "threads": 1,                         optional, per run (0 = OpenMP default)
//     "parameters": [
//       {"pointer": "/buoyancy_m_per_s2", "values": [1.0, 2.0, 4.0]},
//       {"pointer": "/sources/0/radius_m", "values": [0.05, 0.07]}
//     ]
//   }
//
// Runs are the Cartesian product in a fixed order (the last parameter varies
// fastest), so run k is the same run on every machine; shard i of n takes the
// runs with k % n == i. Every pointer must name an existing value of the scene,
// so a typo fails before anything runs.
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pliant::cli {

struct SweepParameter {
  std::string pointer;  // RFC 6901 JSON pointer into the scene
  std::vector<nlohmann::json> values;
};

struct SweepPlan {
  std::filesystem::path file;   // the sweep file, as given
  std::filesystem::path scene;  // resolved scene path
  std::filesystem::path out;    // resolved output folder
  int threads = 0;
  nlohmann::json scene_doc;
  std::vector<SweepParameter> parameters;

  size_t run_count() const;
  std::string run_name(size_t k) const;            // "run_0007"
  nlohmann::json run_values(size_t k) const;       // {pointer: value, ...}
  nlohmann::json run_scene(size_t k) const;        // scene_doc with run k's values
};

// Throws InputError naming the sweep file, the JSON pointer and the problem.
SweepPlan load_sweep(const std::filesystem::path& file);

struct Shard {
  size_t index = 0, count = 1;
  bool owns(size_t run) const { return run % count == index; }
};
// "i/n" with 0 <= i < n; throws InputError naming --shard.
Shard parse_shard(const std::string& text);

}  // namespace pliant::cli
