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
#include <cstring>
#include <stdexcept>
#include <string>

#include "pliant/smoke/control.h"
// after control.h: smoke_workspace.h needs SmokeModel declared
#include "../smoke_workspace.h"

namespace pliant::smoke {
namespace {

constexpr uint32_t kMagic = 0x53434c50;  // "PLCS"
// 2: phase and NSO damping; 3: coarse-to-fine level, L-BFGS stop; 4: objective trace;
// 5: ADMM penalty (residual balancing)
constexpr uint32_t kVersion = 5;

template <class T>
void put(std::vector<uint8_t>& b, const T& v) {
  const size_t o = b.size();
  b.resize(o + sizeof(T));
  std::memcpy(b.data() + o, &v, sizeof(T));
}

template <class T>
void put_array(std::vector<uint8_t>& b, const std::vector<T>& v) {
  put<uint64_t>(b, v.size());
  const size_t o = b.size();
  b.resize(o + v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(b.data() + o, v.data(), v.size() * sizeof(T));
}

struct Reader {
  const std::vector<uint8_t>& b;
  size_t pos = 0;
  [[noreturn]] void bad(const std::string& what) const {
    throw std::runtime_error("control checkpoint: " + what + " at byte " + std::to_string(pos) + " of " +
                             std::to_string(b.size()));
  }
  template <class T>
  T get() {
    if (b.size() - pos < sizeof(T)) bad("truncated");
    T v;
    std::memcpy(&v, b.data() + pos, sizeof(T));
    pos += sizeof(T);
    return v;
  }
  template <class T>
  std::vector<T> get_array() {
    const uint64_t n = get<uint64_t>();
    if (n > (b.size() - pos) / sizeof(T)) bad("array of " + std::to_string(n) + " values longer than the data");
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), b.data() + pos, n * sizeof(T));
    pos += n * sizeof(T);
    return v;
  }
  FaceSeries series() {
    const uint32_t frames = get<uint32_t>();
    if (frames > (b.size() - pos) / sizeof(uint64_t)) bad("frame count " + std::to_string(frames) + " too large");
    FaceSeries s(frames);
    for (auto& f : s) f = get_array<float>();
    return s;
  }
};

void put_series(std::vector<uint8_t>& b, const FaceSeries& s) {
  put<uint32_t>(b, uint32_t(s.size()));
  for (const auto& f : s) put_array(b, f);
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
  put(b, kMagic);
  put(b, kVersion);
  put<int32_t>(b, s.iteration);
  put<double>(b, s.wall_s);
  for (const FaceSeries* f : {&s.force, &s.velocity, &s.split, &s.dual}) put_series(b, *f);
  for (const auto* h : {&s.objective_history, &s.primal_residual_history, &s.dual_residual_history}) put_array(b, *h);
  put<int32_t>(b, s.phase);
  put<double>(b, s.nso_damping);
  put<int32_t>(b, s.level);
  put<uint8_t>(b, s.lbfgs_stopped ? 1 : 0);
  put<double>(b, s.trace_s);
  put_array(b, s.objective_trace);
  put<double>(b, s.admm_beta);
  return b;
}

ControlState control_state_deserialize(const std::vector<uint8_t>& bytes) {
  Reader r{bytes};
  if (r.get<uint32_t>() != kMagic) r.bad("not a control checkpoint (bad magic)");
  const uint32_t version = r.get<uint32_t>();
  if (version < 2 || version > kVersion) r.bad("unsupported version " + std::to_string(version));
  ControlState s;
  s.iteration = r.get<int32_t>();
  if (s.iteration < 0) r.bad("negative iteration");
  s.wall_s = r.get<double>();
  for (FaceSeries* f : {&s.force, &s.velocity, &s.split, &s.dual}) *f = r.series();
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
  if (r.pos != bytes.size()) r.bad("trailing bytes");
  return s;
}

}  // namespace pliant::smoke
