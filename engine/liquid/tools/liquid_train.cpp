// liquid_train DIR NET.json [--epochs N] [--hidden H] [--seed S]
// Gathers the samples of every finished take under DIR (the out folder of
// `pliant sweep assets/sweeps/liquid_dataset.json`, all shards) and trains the
// feedback planner's networks; writes NET.json and prints one JSON line.
//
// liquid_train --evaluate NET.json [--first ID] [--count N] [--seed S]
//   [--family zero|follow] [--trace ID] [--mpc NAME=VALUE ...] [--shape bottle|...]
// Runs the feedback closed loop (MPC + full 2D simulation) on N validation
// problems of the generator: training-split ids from ID on (id % 5 != 0, so the
// held-out split is never touched) that the shipped dataset does not use
// (it uses ids 1..59). This is where MPC settings are tuned; prints one JSON
// line per problem and a summary line.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <string>

#include "pliant/liquid/feedback.h"
#include "pliant/liquid/problem_generator.h"

namespace {

// Per-problem diagnosis of a closed loop: the first frame with liquid out of
// the source (onset) and the first with more than 1% spilled; tilt and the
// lip's x offset from the target's centre (in target inner radii) at both.
struct Diagnosis {
  explicit Diagnosis(const pliant::liquid::LiquidModel& m) : c(m) {}
  pliant::liquid::FeedbackContext c;
  double ground_fraction = 0;  // spilled for good (below the rim, outside both)
  double start = -1, onset_t = -1, onset_tilt = 0, onset_dx = 0, spill_t = -1, spill_tilt = 0, spill_dx = 0;
  void observe(const pliant::liquid::LiquidModel& m, const pliant::liquid::LiquidState& s) {
    using namespace pliant::liquid;
    const auto fr = liquid_fractions(m, s);
    if (start < 0) start = fr[2];
    const Pose q = source_pose_at(m, s.time_s);
    const double inner = m.target.shape.opening_radius() - 0.3 * m.target.shape.wall_m;
    const double dx = (c.lip(q)[0] - target_pose_at(m, s.time_s).position_m[0]) / inner;
    if (onset_t < 0 && fr[2] < start - 0.01) onset_t = s.time_s, onset_tilt = q.tilt_rad, onset_dx = dx;
    // Spilled for good: outside both cavities and below the target's rim.
    const Pose tp = target_pose_at(m, s.time_s);
    size_t ground = 0;
    for (size_t p = 0; p < s.count(); ++p) {
      const Vec3 x{s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]};
      ground += x[1] < tp.position_m[1] + m.target.shape.height_m &&
                !m.target.shape.in_cavity(tp.to_local(x), m.dim) && !m.source.shape.in_cavity(q.to_local(x), m.dim);
    }
    ground_fraction = double(ground) / std::max<size_t>(1, s.count());
    if (spill_t < 0 && ground > 0.01 * s.count()) spill_t = s.time_s, spill_tilt = q.tilt_rad, spill_dx = dx;
  }
};

int evaluate(int argc, char** argv) {
  using namespace pliant::liquid;
  if (argc < 3) {
    std::fprintf(stderr, "usage: liquid_train --evaluate NET.json [--first ID] [--count N] [--seed S]\n");
    return 2;
  }
  int first = 60, count = 30, trace = -1;
  uint64_t seed = 2026;
  std::string family = "zero";
  MpcSettings ms;
  std::string shape;
  const char* shapes[] = {"cylinder", "oval", "box", "cup", "bottle", "mesh"};
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--first") first = std::atoi(argv[i + 1]);
    else if (k == "--count") count = std::atoi(argv[i + 1]);
    else if (k == "--seed") seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (k == "--family") family = argv[i + 1];
    else if (k == "--shape") shape = argv[i + 1];  // only problems with this source shape
    else if (k == "--trace") trace = std::atoi(argv[i + 1]);  // per-frame lines of one problem
    else if (k == "--mpc") {  // NAME=VALUE of an MpcSettings field
      const std::string kv = argv[i + 1];
      const auto eq = kv.find('=');
      if (eq == std::string::npos || !set_mpc_setting(ms, kv.substr(0, eq), std::atof(kv.c_str() + eq + 1))) {
        std::fprintf(stderr, "liquid_train: bad --mpc %s\n", kv.c_str());
        return 2;
      }
    }
    else {
      std::fprintf(stderr, "liquid_train: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  const FeedbackPredictor net = FeedbackPredictor::load(argv[2]);
  int done = 0, success = 0;
  double transfer = 0, spilled = 0;
  for (int id = trace >= 0 ? trace : first; done < count; ++id) {
    if (id % 5 == 0) continue;  // held out: never used for tuning
    const TransferProblem p = generate_problem(id, seed, 2, family == "follow" ? Family::Follow : Family::Zero);
    if (!shape.empty() && trace < 0 && shape != shapes[int(p.model.source.shape.type)]) continue;
    std::function<void(const LiquidModel&, const LiquidState&)> on_frame;
    Diagnosis dg(p.model);
    if (trace >= 0) {
      count = 1;
      const LiquidModel& pm = p.model;
      std::fprintf(stderr, "shape %d radius %.3f height %.3f fill %.2f mu %.4f target x %.3f r %.3f h %.3f\n",
                   int(pm.source.shape.type), pm.source.shape.radius_m, pm.source.shape.height_m, pm.fill_fraction,
                   pm.viscosity_pa_s, pm.target.pose.position_m[0], pm.target.shape.radius_m,
                   pm.target.shape.height_m);
      on_frame = [&dg](const LiquidModel& m, const LiquidState& s) {
        const Pose q = source_pose_at(m, s.time_s);
        const auto fr = liquid_fractions(m, s);
        std::fprintf(stderr, "t %.2f x %.3f y %.3f tilt %5.1f  target %.3f  in %.3f spill %.3f left %.3f ground %.3f\n",
                     s.time_s, q.position_m[0], q.position_m[1], q.tilt_rad * 57.2958,
                     target_pose_at(m, s.time_s).position_m[0], fr[0], fr[1], fr[2], dg.ground_fraction);
      };
    }
    // Diagnosis (every problem): when the flow starts and where, when the spill
    // starts and at what tilt.
    auto diagnose = [&dg, on_frame](const LiquidModel& m, const LiquidState& s) {
      dg.observe(m, s);
      if (on_frame) on_frame(m, s);
    };
    const FeedbackRun run = run_feedback(p.model, net, ms, liquid_init(p.model), {}, diagnose);
    LiquidModel m = p.model;
    m.source_path = run.path;
    const auto fr = liquid_fractions(m, run.final_state);
    ++done;
    success += fr[1] < 0.05;
    transfer += fr[0];
    spilled += fr[1];
    const LiquidModel& pm = p.model;
    const Pose tp = target_pose_at(m, run.final_state.time_s);
    int short_n = 0, long_n = 0, air_n = 0;
    for (size_t q = 0; q < run.final_state.count(); ++q) {
      const Vec3 x{run.final_state.x[3 * q], run.final_state.x[3 * q + 1], run.final_state.x[3 * q + 2]};
      if (m.target.shape.in_cavity(tp.to_local(x), m.dim) ||
          m.source.shape.in_cavity(source_pose_at(m, run.final_state.time_s).to_local(x), m.dim))
        continue;
      // Above the target's rim: still falling or clinging to the source.
      if (x[1] > tp.position_m[1] + m.target.shape.height_m) ++air_n;
      else (x[0] < tp.position_m[0] ? short_n : long_n)++;
    }
    const double n = double(run.final_state.count());
    std::printf(
        "{\"id\": %d, \"in_target\": %.4f, \"spilled\": %.4f, \"in_source\": %.4f, \"shape\": \"%s\", "
        "\"radius\": %.3f, \"height\": %.3f, \"fill\": %.2f, \"mu\": %.4f, \"target_x\": %.3f, \"target_r\": %.3f, "
        "\"spill_short\": %.3f, \"spill_long\": %.3f, \"spill_air\": %.3f, \"onset_t\": %.2f, \"onset_tilt\": %.0f, "
        "\"onset_lip_dx\": %.3f, \"spill_t\": %.2f, \"spill_tilt\": %.0f, \"spill_lip_dx\": %.3f, \"final_tilt\": %.0f}\n",
        id, fr[0], fr[1], fr[2], shapes[int(pm.source.shape.type)], pm.source.shape.radius_m, pm.source.shape.height_m,
        pm.fill_fraction, pm.viscosity_pa_s, pm.target.pose.position_m[0], pm.target.shape.radius_m, short_n / n,
        long_n / n, air_n / n, dg.onset_t, dg.onset_tilt * 57.2958, dg.onset_dx, dg.spill_t, dg.spill_tilt * 57.2958, dg.spill_dx,
        source_pose_at(m, run.final_state.time_s).tilt_rad * 57.2958);
    std::fflush(stdout);
  }
  std::printf("{\"problems\": %d, \"success_at_5\": %.4f, \"mean_transfer\": %.4f, \"mean_spilled\": %.4f}\n",
              count, double(success) / count, transfer / count, spilled / count);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace pliant::liquid;
  if (argc >= 2 && std::string(argv[1]) == "--evaluate") {
    try {
      return evaluate(argc, argv);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "liquid_train: %s\n", e.what());
      return 1;
    }
  }
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
