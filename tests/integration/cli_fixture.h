// Shared pieces of the CLI integration tests: a temp folder per test, small
// smoke scenes written by the test, JSON-lines parsing.
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "pliant/core/take.h"
#include "subprocess.h"

namespace pliant::test {

namespace fs = std::filesystem;

inline const std::string kPliant = PLIANT_EXE;  // $<TARGET_FILE:pliant>
// The source tree (assets/, tests/meshes/), absolute.
inline const fs::path kRepo = PLIANT_SOURCE_DIR;

// A 2D plume: a source near the bottom, buoyancy, a vortex; deterministic.
inline nlohmann::json smoke_scene(int nx, int ny, int frames) {
  return {{"pliant", 1},
          {"kind", "smoke"},
          {"name", "integration test plume"},
          {"grid", {{"resolution", {nx, ny}}, {"cell_size_m", 1.0 / nx}, {"boundary", "closed"}}},
          {"time", {{"dt_s", 0.02}, {"frames", frames}, {"substeps", 1}}},
          {"buoyancy_m_per_s2", 2.0},
          {"sources",
           {{{"shape", "sphere"},
             {"center_m", {0.5, 0.2}},
             {"radius_m", 0.12},
             {"density_per_s", 4.0},
             {"velocity_m_per_s", {0.0, 0.4}}}}},
          {"forces",
           {{{"type", "vortex"}, {"center_m", {0.5, 0.7}}, {"radius_m", 0.2}, {"strength_per_s", 1.5}}}},
          {"output", {{"velocity", true}, {"every", 1}}}};
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("pliant_cli_" + std::string(info->test_suite_name()) +
                                        "_" + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);  // keep evidence of failures
  }

  fs::path write_text(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }
  fs::path write_scene(const std::string& name, const nlohmann::json& scene) {
    return write_text(name, scene.dump(2));
  }
  ProcessResult pliant(std::vector<std::string> args, const std::vector<std::string>& env = {}) {
    args.insert(args.begin(), kPliant);
    return run_process(args, env);
  }

  fs::path dir_;
};

// Every line must be a JSON object with an "event"; failures are reported.
inline std::vector<nlohmann::json> parse_json_lines(const std::string& out) {
  std::vector<nlohmann::json> events;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    try {
      nlohmann::json j = nlohmann::json::parse(line);
      EXPECT_TRUE(j.is_object() && j.contains("event")) << line;
      events.push_back(std::move(j));
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a JSON line: " << line << " (" << e.what() << ")";
    }
  }
  return events;
}

inline bool all_finite(const Record& r) {
  for (const Field& f : r.fields)
    for (float v : f.data)
      if (!std::isfinite(v)) return false;
  return true;
}

inline bool bitwise_equal(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

inline bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace pliant::test
