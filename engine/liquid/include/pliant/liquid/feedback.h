// Feedback planner (dissertation section 2.6; ALGORITHMS.md section 1, planner C).
//
// Offline: random training problems (problem_generator.h, training split only)
// are solved by the simplified planner inside `pliant sweep` jobs; each job's
// full-simulation runs are cut into control intervals of `interval_s` and every
// interval gives one sample (FeedbackSample): features of the pour state and of
// the action held during it -> what the full simulator did (outflow rate, and
// where and how fast the leaving liquid crossed the lip). Two 4-layer MLPs
// (engine/optim) learn these: `flow` (outflow rate, all samples) and `exit`
// (exit offset and velocity relative to the lip, samples with outflow). They
// are the "key parameters of the outflow quadratic curve": with them a
// stream's parabola, hence its landing point, is analytic.
//
// Online: receding-horizon MPC. Every interval the controller measures the
// liquid left in the source (full simulator), rolls each candidate action
// (tilt rate, horizontal speed) through the networks for `horizon` intervals,
// scores predicted spill (landing outside the opening where the target is
// when the stream arrives: TRANSFER+FOLLOW targets move), liquid landed,
// liquid left, the approach before the onset and smoothness, and commits the
// best one. Actions take effect one
// interval later (the key pose two intervals ahead is chosen), so the
// Catmull-Rom path the simulator follows never changes behind it and the
// closed-loop run is exactly reproducible from the recorded key poses.
#pragma once
#include <array>
#include <filesystem>
#include <functional>
#include <string>
#include <nlohmann/json.hpp>
#include <vector>

#include "pliant/core/progress.h"
#include "pliant/liquid/liquid.h"
#include "pliant/liquid/simplified_model.h"
#include "pliant/optim/mlp.h"

namespace pliant::liquid {

constexpr int kFeedbackFeatures = 17;
constexpr int kFeedbackExitOutputs = 4;  // exit offset x, y (dm), relative velocity x, y (m/s)

// Per-problem constants the features need (tables of the simplified model give
// the Bernoulli head and weir flow, the dissertation's "height at lip").
struct FeedbackContext {
  const LiquidModel* model = nullptr;
  OutflowTables tables;
  double vol0 = 0;         // initial liquid volume (tables' units)
  size_t particles0 = 0;   // particles initially in the source cavity
  explicit FeedbackContext(const LiquidModel& m);
  // Lip point (world) at a pose: where the simplified model releases parcels.
  Vec3 lip(const Pose& p) const;
  // Inputs: tilt, tilt rate, container vx, vy, volume fraction left, head / height,
  // Bernoulli outflow rate (fraction/s), fill, radius, height, opening radius,
  // log10 viscosity, shape one-hot (5).
  std::array<double, kFeedbackFeatures> features(double tilt, double tilt_rate, double vx, double vy,
                                                 double volume_fraction) const;
};

// Fraction of the initial source particles still in the source cavity.
double source_volume_fraction(const FeedbackContext& c, const LiquidState& s);

struct FeedbackSample {
  std::array<double, kFeedbackFeatures> x{};
  double outflow_rate = 0;  // fraction of the initial liquid per second leaving the source
  int leaving = 0;          // particles that left during the interval
  std::array<double, kFeedbackExitOutputs> exit{};  // mean exit offset (dm) and relative velocity
};

// Cuts a full simulation into samples; call record() after every frame.
class SampleRecorder {
 public:
  SampleRecorder(const FeedbackContext& c, const LiquidState& initial, double interval_s);
  void record(const LiquidState& s);
  const std::vector<FeedbackSample>& samples() const { return samples_; }
  static nlohmann::json to_json(const std::vector<FeedbackSample>& samples);
  static std::vector<FeedbackSample> from_json(const nlohmann::json& j);  // throws std::runtime_error

 private:
  void begin(const LiquidState& s);
  const FeedbackContext& c_;
  int frames_per_interval_ = 5;
  std::vector<unsigned char> in_source_;
  FeedbackSample cur_;
  int frames_in_ = 0;
  double start_fraction_ = 0;
  std::array<double, kFeedbackExitOutputs> sum_{};
  std::vector<FeedbackSample> samples_;
};

// Dataset job part (planner field "sample_rollouts"): full simulations of random
// monotone pours of the same problem (coverage beyond the planner's own path).
std::vector<FeedbackSample> random_rollout_samples(const LiquidModel& m, int rollouts, uint64_t seed,
                                                  double interval_s, Progress* progress = nullptr);

// The two networks with input/output normalisation; one JSON file.
struct FeedbackPredictor {
  optim::Mlp flow, exit;
  Eigen::VectorXd x_mean, x_scale;  // inputs are (x - mean) / scale
  double flow_scale = 1;            // flow net predicts rate / flow_scale
  double interval_s = 0.1;
  int samples = 0;                  // training set size (information)
  Eigen::VectorXd input(const std::array<double, kFeedbackFeatures>& x) const;
  double predict_flow(const Eigen::VectorXd& in) const;                          // fraction / s, >= 0
  std::array<double, kFeedbackExitOutputs> predict_exit(const Eigen::VectorXd& in) const;
  void save(const std::filesystem::path& file) const;
  static FeedbackPredictor load(const std::filesystem::path& file);  // throws std::runtime_error
};

struct FeedbackTraining {
  int epochs = 400;
  int hidden = 32;       // three hidden layers of this width: a 4-layer MLP
  double learning_rate = 3e-3;
  int batch = 32;
  uint64_t seed = 1;
  double flow_loss = 0, exit_loss = 0;          // results: final mean training loss
  double flow_loss_initial = 0, exit_loss_initial = 0;
};
FeedbackPredictor train_feedback(const std::vector<FeedbackSample>& samples, FeedbackTraining* options);
// Samples of every finished take under `dir` (a sweep's out folder or one take).
std::vector<FeedbackSample> gather_samples(const std::filesystem::path& dir, int* takes = nullptr);

// MPC action: tilt rate (rad/s), horizontal and vertical speed (m/s), held for one interval.
struct MpcAction {
  double tilt_rate = 0, vx = 0, vy = 0;
};

struct MpcSettings {
  int horizon = 4;  // intervals rolled through the networks
  std::vector<double> tilt_rates{0.0, 0.2, 0.45, 0.8, 1.3};
  std::vector<double> speeds{-0.2, -0.12, -0.06, -0.02, 0.0, 0.02, 0.06, 0.12, 0.2};
  // Before the flow starts (> 90% left; fading out by 60% of the pour time),
  // pull the lip toward approach_goal x the opening's inner radius short of the
  // target's centre (cost weight per interval, squared offset in inner radii). Tuned on validation problems of the training split
  // (liquid_train --evaluate), never on the held-out split.
  double approach_weight = 4, approach_goal = 0.3;
  // Spill score: landing offsets (inner radii) from the centre where the
  // penalty starts and where it is full, and its weight per unit of liquid.
  // The band and the width (below) were chosen with liquid_train --evaluate
  // on 224 training-split problems outside the dataset (ids 60-339), never on
  // the held-out split: success@5% 0.902 -> 0.946 with these values.
  double spill_inner = 0.25, spill_outer = 0.55, spill_weight = 6;
  // Landing offset from the centre, squared (inner radii), per unit of liquid
  // (validation: 3 -> 214/224 vs 212/224 with 1; FOLLOW keeps 1: 0.929 vs 0.964).
  double centre_weight = 3;
  // Stream width: the networks predict the stream's mean exit only. The
  // liquid also lands between the mean landing point and the point straight
  // below the lip moving with the container (a thin first trickle, liquid
  // running down the outer wall), and beyond the mean (the faster part of the
  // stream). The spill is averaged over points from `stream_near` of the way
  // back toward the lip's fall point to `stream_far` beyond the mean
  // (fractions of that distance); 0, 0 is the mean stream only.
  double stream_near = 0.5, stream_far = 0;
  // Moving targets (TRANSFER+FOLLOW) keep the mean-stream score: on 112
  // FOLLOW validation problems the width and the narrower band lowered
  // success@5% from 0.964 to 0.929 (the near edge lags a target moving away).
  double moving_spill_outer = 0.65, moving_stream_near = 0, moving_stream_far = 0, moving_centre_weight = 1;
  // Bottles pour from a narrow neck as a jet, not a trickle down the wall:
  // the width is off for them (on validation it stalled bottle pours).
  bool bottle_stream_width = false;
  // Stop (static targets): from stop_at x the planner's pour time on, tilt
  // back upright at stop_tilt_rate (rad/s) and hold the position, so the
  // stream has stopped and landed before the simulation ends (liquid still in
  // the air at the end counts as spilled: bottles still pouring at 2.6 s were
  // most of the remaining failures). Validation (ids 60-339): 216/224 vs
  // 214/224 without, mean transfer 0.939 -> 0.920; on ids 60-199 stop_at 0.95
  // and 1.1 gave 107/112 vs 109/112 at 1.0. Limiting the tilt rate / speed
  // late in the pour instead lowered validation success (README).
  double stop_at = 1.0, stop_tilt_rate = 1.3;
};
// Spill share (0..1) of a stream landing at `land` (mean) whose near edge
// lands at `near`, against an opening at `centre` with inner radius `inner`
// (x, m): the spill ramp averaged over the stream's width (MpcSettings).
double stream_spill(const MpcSettings& ms, double land, double near, double centre, double inner);
// Sets one MpcSettings field by name (liquid_train --evaluate --mpc NAME=VALUE);
// false for an unknown name.
bool set_mpc_setting(MpcSettings& ms, const std::string& name, double value);

// One MPC decision at the start of an interval: the volume fraction measured now,
// the pose now, and the action already committed for the current interval.
MpcAction mpc_decide(const FeedbackContext& c, const FeedbackPredictor& net, const MpcSettings& ms,
                     double time_s, const Pose& pose, double volume_fraction, const MpcAction& committed);

struct FeedbackRun {
  Trajectory path;          // key poses every interval (reproduces the run)
  LiquidState final_state;
  double mpc_step_ms_mean = 0, mpc_step_ms_max = 0;  // wall clock per decision
  double mpc_step_cpu_ms_mean = 0;                     // CPU time per decision
  int mpc_steps = 0;
};

// The closed loop: MPC decisions interleaved with full-simulation frames from
// `start` (frame 0, or a checkpoint with `path` holding the keys so far).
// on_frame(state) runs after every frame (take records, progress, cancel).
FeedbackRun run_feedback(const LiquidModel& m, const FeedbackPredictor& net, const MpcSettings& ms,
                         LiquidState start, Trajectory path,
                         const std::function<void(const LiquidModel&, const LiquidState&)>& on_frame);

// Default network shipped with the sources (assets/sweeps/liquid_dataset_net.json).
std::filesystem::path default_feedback_network();

}  // namespace pliant::liquid
