// liquid_train DIR NET.json [--epochs N] [--hidden H] [--seed S]
// Gathers the samples of every finished take under DIR (the out folder of
// `pliant sweep assets/sweeps/liquid_dataset.json`, all shards) and trains the
// feedback planner's networks; writes NET.json and prints one JSON line.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "pliant/liquid/feedback.h"

int main(int argc, char** argv) {
  using namespace pliant::liquid;
  if (argc < 3) {
    std::fprintf(stderr, "usage: liquid_train DIR NET.json [--epochs N] [--hidden H] [--seed S]\n");
    return 2;
  }
  FeedbackTraining o;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--epochs") o.epochs = std::atoi(argv[i + 1]);
    else if (k == "--hidden") o.hidden = std::atoi(argv[i + 1]);
    else if (k == "--seed") o.seed = std::strtoull(argv[i + 1], nullptr, 10);
    else {
      std::fprintf(stderr, "liquid_train: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  try {
    int takes = 0;
    const auto samples = gather_samples(argv[1], &takes);
    if (samples.empty()) {
      std::fprintf(stderr, "liquid_train: no finished takes with samples under %s\n", argv[1]);
      return 2;
    }
    FeedbackPredictor p = train_feedback(samples, &o);
    p.save(argv[2]);
    nlohmann::json out = {{"takes", takes},
                          {"samples", samples.size()},
                          {"epochs", o.epochs},
                          {"flow_loss_initial", o.flow_loss_initial},
                          {"flow_loss", o.flow_loss},
                          {"exit_loss_initial", o.exit_loss_initial},
                          {"exit_loss", o.exit_loss},
                          {"network", argv[2]}};
    std::printf("%s\n", out.dump().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "liquid_train: %s\n", e.what());
    return 1;
  }
}
