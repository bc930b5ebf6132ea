// bench_soft_util.h's helpers.
#include "bench_soft_util.h"

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <iostream>
#include <omp.h>

#include "pliant/core/scene.h"
#include "../bench_machine.h"

using namespace pliant;
using namespace pliant::soft;

namespace soft_bench {
namespace {
std::vector<nlohmann::json> all_results;
}  // namespace

// OpenMP threads a parallel region would use (OMP_NUM_THREADS).
int omp_threads() {
  int n = 1;
#pragma omp parallel
#pragma omp single
  n = omp_get_num_threads();
  return n;
}
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
// CPU seconds of this process (all threads): on a shared, loaded machine the wall
// clock counts other people's work too; with OMP_NUM_THREADS=1 frames per CPU second
// is the rate an idle core would give.
double cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
double load_average() {
  double l = -1;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &l) != 1) l = -1;
    std::fclose(f);
  }
  return l;
}

const std::vector<nlohmann::json>& results() { return all_results; }

void emit(nlohmann::json j) {
  j["bench"] = "soft";
  j["machine"] = pliant::bench::machine_description();
  std::cout << j.dump() << std::endl;
  all_results.push_back(j);
}

// NEWTON_DECREMENT_STOP=x: SimParams::newton_decrement_stop (opt-in step stop) for the
// playback cases.
void decrement_stop_override(SoftModel& m) {
  if (const char* e = std::getenv("NEWTON_DECREMENT_STOP")) m.problem.sim.newton_decrement_stop = std::atof(e);
}

// SCENE_SET="/objectives/steady/weight=0;/optimizer/fused_trials=true": JSON values
// written at these JSON pointers before compiling (variants without a scene copy).
void scene_overrides(Scene& sc) {
  const char* e = std::getenv("SCENE_SET");
  if (!e) return;
  std::string all = e;
  for (size_t a = 0; a < all.size();) {
    size_t b = all.find(';', a);
    if (b == std::string::npos) b = all.size();
    const std::string kv = all.substr(a, b - a);
    const size_t eq = kv.find('=');
    if (eq != std::string::npos)
      sc.doc[nlohmann::json::json_pointer(kv.substr(0, eq))] = nlohmann::json::parse(kv.substr(eq + 1));
    a = b + 1;
  }
}

SoftModel load(const std::string& name) {
  Scene sc = load_scene(std::string(PLIANT_ASSETS_DIR) + "/scenes/" + name);
  scene_overrides(sc);
  SoftModel m = soft_compile(sc);
  soft_bind(m);
  return m;
}

}  // namespace soft_bench
