// OptimizerState's checkpoint form (optimizer.h): versioned, little-endian, every
// value a double where the state holds one, every size checked against the bytes
// that remain before anything is allocated.
//   header  u32 magic "PLSO"  u32 version (1)  u64 body bytes  u32 CRC32 of the body
//           u32 tag (the caller's)
//   body    i32 iteration  i32 evaluations  i32 lbfgs_restarts_used  u8 in_lbfgs
//           f64 objective  f64 lambda  vec theta  vec history
//           u64 count, per step kind u32 length + bytes
//           memory: vec theta  vec r  mat J  i32 reused  mat J_at  i32 lm_stalls
//           f64 last_lm_step  f64 last_lbfgs_step  f64 radius
//           u64 pairs, per pair vec s + vec y  vec g_prev  vec theta_prev
//   vec = u64 n + n f64; mat = u64 rows + u64 cols + rows x cols f64 (column-major).
// Up to 3 zero bytes may follow the body (a take field's padding to 4 bytes).
#include <stdexcept>
#include <string>

#include "eigen_bytes.h"
#include "pliant/core/framed_blob.h"
#include "pliant/soft/optimizer.h"

namespace pliant::soft {
namespace {

constexpr uint32_t kMagic = 0x4f534c50;  // "PLSO"
constexpr uint32_t kVersion = 1;
constexpr uint32_t kMaxStepKind = 64;

int32_t get_count(ByteReader& r, const char* what) {
  const int32_t v = r.get<int32_t>();
  if (v < 0) r.bad(std::string("negative ") + what);
  return v;
}

}  // namespace

std::vector<uint8_t> optimizer_state_serialize(const OptimizerState& s, uint32_t tag) {
  const OptimizerMemory& m = s.memory;
  size_t reserve = 256 + 8 * size_t(s.theta.size() + s.history.size() + m.theta.size() + m.r.size() +
                                                   m.J.size() + m.J_at.size() + m.g_prev.size() + m.theta_prev.size());
  for (size_t i = 0; i < m.S.size(); ++i) reserve += 16 + 8 * size_t(m.S[i].size() + m.Y[i].size());
  for (const auto& k : s.step_kinds) reserve += 4 + k.size();
  std::vector<uint8_t> b = framed_blob_start(kMagic, kVersion, tag, reserve);
  append_value<int32_t>(b, s.iteration);
  append_value<int32_t>(b, s.evaluations);
  append_value<int32_t>(b, s.lbfgs_restarts_used);
  append_value<uint8_t>(b, s.in_lbfgs ? 1 : 0);
  append_value<double>(b, s.objective);
  append_value<double>(b, s.lambda);
  put_vec(b, s.theta);
  append_value<uint64_t>(b, s.history.size());
  append_doubles(b, s.history.data(), s.history.size());
  append_value<uint64_t>(b, s.step_kinds.size());
  for (const auto& k : s.step_kinds) {
    if (k.size() > kMaxStepKind) throw std::invalid_argument("optimizer_state_serialize: step kind too long");
    append_value<uint32_t>(b, uint32_t(k.size()));
    append_bytes(b, k.data(), k.size());
  }
  put_vec(b, m.theta);
  put_vec(b, m.r);
  put_mat(b, m.J);
  append_value<int32_t>(b, m.reused);
  put_mat(b, m.J_at);
  append_value<int32_t>(b, m.lm_stalls);
  append_value<double>(b, m.last_lm_step);
  append_value<double>(b, m.last_lbfgs_step);
  append_value<double>(b, m.radius);
  append_value<uint64_t>(b, m.S.size());
  for (size_t i = 0; i < m.S.size(); ++i) put_vec(b, m.S[i]), put_vec(b, m.Y[i]);
  put_vec(b, m.g_prev);
  put_vec(b, m.theta_prev);
  framed_blob_finish(b);
  return b;
}

OptimizerState optimizer_state_deserialize(const std::vector<uint8_t>& bytes, uint32_t* tag) {
  ByteReader r(bytes, "soft optimizer checkpoint");
  const uint32_t t = framed_blob_open(bytes, r, kMagic, kVersion, "soft optimizer state");

  OptimizerState s;
  s.iteration = get_count(r, "iteration");
  s.evaluations = get_count(r, "evaluation count");
  s.lbfgs_restarts_used = get_count(r, "restart count");
  const uint8_t in_lbfgs = r.get<uint8_t>();
  if (in_lbfgs > 1) r.bad("bad L-BFGS phase flag");
  s.in_lbfgs = in_lbfgs == 1;
  s.objective = r.get<double>();
  s.lambda = r.get<double>();
  s.theta = get_vec(r, "theta");
  const int64_t n = s.theta.size();
  const uint64_t h = r.get_length<double>("history");
  // One objective per iteration after the initial one.
  if (h != uint64_t(s.iteration) + 1)
    r.bad("history of " + std::to_string(h) + " values for " + std::to_string(s.iteration) + " iterations");
  s.history.resize(h);
  r.get_values(s.history.data(), h);
  const uint64_t kinds = r.get<uint64_t>();
  if (kinds > r.remaining() / 4 || kinds > uint64_t(s.iteration))
    r.bad(std::to_string(kinds) + " step kinds for " + std::to_string(s.iteration) + " iterations");
  s.step_kinds.resize(kinds);
  for (auto& k : s.step_kinds) {
    const uint32_t len = r.get<uint32_t>();
    if (len > kMaxStepKind || len > r.remaining()) r.bad("bad step kind length " + std::to_string(len));
    k.resize(len);
    r.get_bytes(k.data(), len);
  }
  OptimizerMemory& m = s.memory;
  m.theta = get_vec(r, "memory theta", n);
  m.r = get_vec(r, "residuals");
  const int64_t rows = m.r.size();
  m.J = get_mat(r, "J", rows, n);
  m.reused = get_count(r, "Broyden reuse count");
  m.J_at = get_mat(r, "J_at", rows, n);
  m.lm_stalls = get_count(r, "LM stall count");
  m.last_lm_step = r.get<double>();
  m.last_lbfgs_step = r.get<double>();
  m.radius = r.get<double>();
  const uint64_t pairs = r.get<uint64_t>();
  if (pairs > r.remaining() / 16) r.bad(std::to_string(pairs) + " curvature pairs longer than the data");
  for (uint64_t i = 0; i < pairs; ++i) {
    m.S.push_back(get_vec(r, "curvature pair s", n));
    m.Y.push_back(get_vec(r, "curvature pair y", n));
    if (m.S.back().size() != n || m.Y.back().size() != n) r.bad("empty curvature pair");
  }
  m.g_prev = get_vec(r, "previous gradient", n);
  m.theta_prev = get_vec(r, "previous point", n);
  if (r.remaining() != 0) r.bad("trailing bytes in the body");
  if (m.theta.size() != 0 && m.r.size() == 0) r.bad("memory without residuals");
  if (tag) *tag = t;
  return s;
}

}  // namespace pliant::soft
