// What every benchmark records about the machine it ran on: "<cores> x <CPU model>"
// (BENCHMARKS.md: absolute times are reported with nproc and the CPU model).
#pragma once
#include <fstream>
#include <string>
#include <thread>

namespace pliant::bench {

inline std::string machine_description() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  return std::to_string(std::thread::hardware_concurrency()) + " x " + model;
}

}  // namespace pliant::bench
