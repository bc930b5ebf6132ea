// bench_articulated: PBAD (2nd/3rd order) and our Euler/RK4 against MuJoCo 2.2.2's
// Euler, RK4 and implicit integrators on the same MJCF chains, in one process
// (BENCHMARKS.md, "Articulated bodies (PBAD)"). One JSON object per case on stdout;
// all of them in bench/results/articulated.json.
//   chain_swing: chain released horizontally (whips when it swings down);
//   chain_tilt:  chain released 30 degrees from vertical (smooth swing);
//   energy_drift = max |E(t) - E0| / (potential energy range, horizontal to hanging).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "../bench_machine.h"
#include "bench_common.h"

using namespace art_bench;

int main(int argc, char** argv) {
  bool quick = false, chains_only = false, filtered = false, merge = false;
  std::string out = std::string(PLIANT_RESULTS_DIR) + "/articulated.json";
  std::vector<int> only_links;
  std::vector<double> only_dts;
  std::string only_case, only_methods;
  auto parse_list = [](const char* text) {
    std::vector<double> v;
    for (const char* c = text; *c;) {
      char* end = nullptr;
      v.push_back(std::strtod(c, &end));
      if (end == c) break;
      c = *end == ',' ? end + 1 : end;
    }
    return v;
  };
  // Filters for exploring one corner (--links 10,40 --dt 0.05 --case chain_tilt
  // --chains-only); a filtered run writes a results file only with an explicit --out.
  bool explicit_out = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--chains-only")) chains_only = filtered = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i], explicit_out = true;
    else if (!std::strcmp(argv[i], "--merge")) merge = explicit_out = true;
    else if (!std::strcmp(argv[i], "--links") && i + 1 < argc) {
      for (double l : parse_list(argv[++i])) only_links.push_back(static_cast<int>(l));
      filtered = true;
    } else if (!std::strcmp(argv[i], "--dt") && i + 1 < argc) only_dts = parse_list(argv[++i]), filtered = true;
    else if (!std::strcmp(argv[i], "--case") && i + 1 < argc) only_case = argv[++i], filtered = true;
    else if (!std::strcmp(argv[i], "--methods") && i + 1 < argc) only_methods = argv[++i], filtered = true;
    else {
      std::fprintf(stderr, "usage: bench_articulated [--quick] [--out FILE] [--links 10,40] [--dt 0.02,0.05] "
                           "[--merge] [--case chain_swing|chain_tilt|pile|mesh_mesh|mesh_terrain|mesh_features|joint_friction|humanoid|batched] [--methods pbad3,pbad4,mujoco] [--chains-only]\n");
      return 2;
    }
  }
  g_machine = pliant::bench::machine_description();
  // --merge: rows of the cases run now replace those cases' rows in the results file;
  // every other row stays (one case re-measured without re-running the rest).
  const auto write_results = [&] {
    nlohmann::json rows = g_results;
    if (merge) {
      std::ifstream in(out);
      const nlohmann::json old = in ? nlohmann::json::parse(in) : nlohmann::json::array();
      std::set<std::string> fresh;
      for (const auto& r : g_results) fresh.insert(r.value("case", ""));
      rows = nlohmann::json::array();
      for (const auto& r : old)
        if (!fresh.count(r.value("case", ""))) rows.push_back(r);
      for (const auto& r : g_results) rows.push_back(r);
    }
    std::filesystem::create_directories(std::filesystem::path(out).parent_path());
    std::ofstream(out) << rows.dump(1) << "\n";
    std::fprintf(stderr, "wrote %s (%zu rows)\n", out.c_str(), rows.size());
  };
  if (only_case == "batched") {
    batched_case(quick);
    if (explicit_out) write_results();
    return 0;
  }
  if (only_case == "pile" || only_case == "mesh_mesh" || only_case == "mesh_terrain" || only_case == "mesh_features" ||
      only_case == "joint_friction" || only_case == "humanoid") {
    (only_case == "pile"        ? pile_case
     : only_case == "humanoid" ? humanoid_case
     : only_case == "joint_friction" ? joint_friction_case
     : only_case == "mesh_mesh" ? mesh_mesh_case
     : only_case == "mesh_terrain" ? mesh_terrain_case
                                   : mesh_features_case)(quick);
    if (explicit_out) write_results();
    return 0;
  }
  const double duration = quick ? 2.0 : 10.0;
  std::vector<int> link_counts = quick ? std::vector<int>{10, 40} : std::vector<int>{10, 40, 100};
  std::vector<double> dts = quick ? std::vector<double>{0.005, 0.01, 0.05}
                                  : std::vector<double>{0.001, 0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.1};
  if (!only_links.empty()) link_counts = only_links;
  if (!only_dts.empty()) dts = only_dts;
  chain_cases(duration, link_counts, dts, only_case, only_methods);
  if (!chains_only) {
    cost_per_step_case();
    contact_cases(quick);
    batched_case(quick);
    pile_case(quick);
    mesh_mesh_case(quick);
    mesh_terrain_case(quick);
    mesh_features_case(quick);
    joint_friction_case(quick);
    humanoid_case(quick);
  }
  if (filtered && !explicit_out) return 0;
  write_results();
  return 0;
}
