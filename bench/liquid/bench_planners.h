// Planner cases of bench_liquid (filled in with the planners).
#pragma once
#include <nlohmann/json.hpp>
#include <vector>

inline std::vector<nlohmann::json> bench_planners(bool /*quick*/) { return {}; }
