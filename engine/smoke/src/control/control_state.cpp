// ControlState: initial state and a versioned little-endian binary serialisation
// for checkpoints (every size is checked against the bytes that remain).
//   "PLCS" u32 version i32 iteration f64 wall_s
//   4 x FaceSeries (force, velocity, split, dual): u32 frames, per frame u64 n + n f32
//   3 x double series (objective, primal residual, dual residual): u64 n + n f64
//   i32 phase f64 nso_damping (version >= 2), i32 level u8 lbfgs_stopped (version >= 3)
//   f64 trace_s, u64 n + n x (f64 seconds, f64 E) objective trace (version >= 4; older
//   checkpoints load with an empty trace from 0 s: their runs predate it)
//   f64 admm_beta (version >= 5; older checkpoints: 0, the continuation schedule's beta)
#include <cmath>
#include <string>

#include "pliant/core/byte_stream.h"
#include "pliant/smoke/control.h"
// after control.h: smoke_workspace.h needs SmokeModel declared
#include "../smoke_workspace.h"

namespace pliant::smoke {
namespace {

constexpr uint32_t kMagic = 0x53434c50;  // "PLCS"
// 2: phase and NSO damping; 3: coarse-to-fine level, L-BFGS stop; 4: objective trace;
// 5: ADMM penalty (residual balancing)
constexpr uint32_t kVersion = 5;

// A FaceSeries: u32 frames, then per frame u64 n + n f32.
void put_series(std::vector<uint8_t>& b, const FaceSeries& s) {
  append_value<uint32_t>(b, uint32_t(s.size()));
  for (const auto& f : s) append_array(b, f);
}

FaceSeries get_series(ByteReader& r) {
  const uint32_t frames = r.get<uint32_t>();
  if (frames > r.remaining() / sizeof(uint64_t)) r.bad("frame count " + std::to_string(frames) + " too large");
  FaceSeries s(frames);
  for (auto& f : s) f = r.get_array<float>();
  return s;
}

}  // namespace

ControlState control_init(const ControlModel& m) {
  const MacGrid g = model_grid(m.sim);
  const size_t nf = g.face_count(0) + g.face_count(1) + g.face_count(2);
  ControlState s;
  s.force.assign(m.sim.frames, std::vector<float>(nf, 0.0f));
  return s;
}

std::vector<uint8_t> control_state_serialize(const ControlState& s) {
  std::vector<uint8_t> b;
  append_value(b, kMagic);
  append_value(b, kVersion);
  append_value<int32_t>(b, s.iteration);
  append_value<double>(b, s.wall_s);
  for (const FaceSeries* f : {&s.force, &s.velocity, &s.split, &s.dual}) put_series(b, *f);
  for (const auto* h : {&s.objective_history, &s.primal_residual_history, &s.dual_residual_history})
    append_array(b, *h);
  append_value<int32_t>(b, s.phase);
  append_value<double>(b, s.nso_damping);
  append_value<int32_t>(b, s.level);
  append_value<uint8_t>(b, s.lbfgs_stopped ? 1 : 0);
  append_value<double>(b, s.trace_s);
  append_array(b, s.objective_trace);
  append_value<double>(b, s.admm_beta);
  return b;
}

ControlState control_state_deserialize(const std::vector<uint8_t>& bytes) {
  ByteReader r(bytes, "control checkpoint");
  if (r.get<uint32_t>() != kMagic) r.bad("not a control checkpoint (bad magic)");
  const uint32_t version = r.get<uint32_t>();
  if (version < 2 || version > kVersion) r.bad("unsupported version " + std::to_string(version));
  ControlState s;
  s.iteration = r.get<int32_t>();
  if (s.iteration < 0) r.bad("negative iteration");
  s.wall_s = r.get<double>();
  for (FaceSeries* f : {&s.force, &s.velocity, &s.split, &s.dual}) *f = get_series(r);
  for (auto* h : {&s.objective_history, &s.primal_residual_history, &s.dual_residual_history})
    *h = r.get_array<double>();
  s.phase = r.get<int32_t>();
  if (s.phase < 0 || s.phase > 1) r.bad("bad phase " + std::to_string(s.phase));
  s.nso_damping = r.get<double>();
  if (!(s.nso_damping >= 0)) r.bad("bad NSO damping");
  if (version >= 3) {  // version 2 checkpoints were always written on the fine level
    s.level = r.get<int32_t>();
    if (s.level < 0 || s.level > 8) r.bad("bad coarse-to-fine level " + std::to_string(s.level));
    const uint8_t stopped = r.get<uint8_t>();
    if (stopped > 1) r.bad("bad L-BFGS stop flag");
    s.lbfgs_stopped = stopped == 1;
  }
  if (version >= 4) {
    s.trace_s = r.get<double>();
    if (!(s.trace_s >= 0 && std::isfinite(s.trace_s))) r.bad("bad trace time");
    s.objective_trace = r.get_array<std::array<double, 2>>();
    for (size_t i = 0; i < s.objective_trace.size(); ++i) {
      const auto& p = s.objective_trace[i];
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || (i > 0 && !(p[1] < s.objective_trace[i - 1][1])))
        r.bad("objective trace point " + std::to_string(i) + " not finite or not decreasing");
    }
  }
  if (version >= 5) {
    s.admm_beta = r.get<double>();
    if (!(s.admm_beta >= 0 && std::isfinite(s.admm_beta))) r.bad("bad ADMM penalty");
  }
  if (r.remaining() != 0) r.bad("trailing bytes");
  return s;
}

}  // namespace pliant::smoke
