// What the bench_soft cases share: clocks, the JSON output, loading a bench scene.
#pragma once
#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pliant/soft/soft.h"

namespace soft_bench {

using Clock = std::chrono::steady_clock;

int omp_threads();  // threads a parallel region would use (OMP_NUM_THREADS)
double since(Clock::time_point t);
double cpu_s();  // CPU seconds of this process, all threads
double load_average();
void emit(nlohmann::json j);  // prints one case's object and keeps it for the file
const std::vector<nlohmann::json>& results();
void decrement_stop_override(pliant::soft::SoftModel& m);
pliant::soft::SoftModel load(const std::string& name);  // assets/scenes/<name>, compiled and bound

// The optimizer comparison on one scene (bench_soft_optimizers.cpp).
void optimizers(const std::string& scene, int iterations);

}  // namespace soft_bench
