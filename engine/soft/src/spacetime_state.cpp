// SpacetimeCheckpoint's bytes (spacetime_state.h), in the manner of optimizer_state.cpp:
//   header  u32 magic "PLST"  u32 version (1)  u64 body bytes  u32 CRC32 of the body
//           u32 tag (the caller's)
//   body    i32 iteration  i32 steps  u8 stopped  f64 w_dmp  f64 lambda  f64 merit
//           u64 frames T  u64 modal coordinates r
//           per frame: i32 frame  f64 time_s  q[r]  q_prev[r]  R[9]  R_prev[9]  c[3]
//                      c_prev[3] (matrices column-major)
//           mat act  vec theta  vec res
//           report: vec merit, physics_violation, dmp_mismatch, w_dmp, resimulated
//           (iteration + 1 values each)
//   vec = u64 n + n f64; mat = u64 rows + u64 cols + rows x cols f64 (column-major).
#include "pliant/soft/spacetime_state.h"

#include <stdexcept>
#include <string>

#include "eigen_bytes.h"
#include "pliant/core/framed_blob.h"

namespace pliant::soft {
namespace {

constexpr uint32_t kMagic = 0x54534c50;  // "PLST"
constexpr uint32_t kVersion = 1;

// A report series: one value per iteration and the initial one.
std::vector<double> get_series(ByteReader& r, const char* what, int iteration) {
  std::vector<double> v = r.get_array<double>(what);
  if (v.size() != size_t(iteration) + 1)
    r.bad(std::string(what) + " has " + std::to_string(v.size()) + " values for " + std::to_string(iteration) +
          " iterations");
  return v;
}

}  // namespace

std::vector<uint8_t> spacetime_checkpoint_serialize(const SpacetimeCheckpoint& c, uint32_t tag) {
  const SpacetimeCarry& k = c.carry;
  const SpacetimeReport& rep = c.report;
  const int r = k.vars.frames.empty() ? 0 : int(k.vars.frames.front().q.size());
  for (const SoftState& s : k.vars.frames)
    if (s.q.size() != r || s.q_prev.size() != r)
      throw std::invalid_argument("spacetime_checkpoint_serialize: frames of different sizes");
  if (k.vars.act.cols() != Eigen::Index(k.vars.frames.size()))
    throw std::invalid_argument("spacetime_checkpoint_serialize: activations and frames disagree");
  std::vector<uint8_t> b = framed_blob_start(kMagic, kVersion, tag, 128 + k.vars.frames.size() * (12 + 8 * size_t(2 * r + 24)) +
            8 * size_t(k.vars.act.size() + k.vars.theta.size() + k.res.size() + 5 * rep.merit.size()));
  append_value<int32_t>(b, c.iteration);
  append_value<int32_t>(b, rep.steps);
  append_value<uint8_t>(b, k.stopped ? 1 : 0);
  append_value<double>(b, k.w_dmp);
  append_value<double>(b, k.lambda);
  append_value<double>(b, k.merit);
  append_value<uint64_t>(b, k.vars.frames.size());
  append_value<uint64_t>(b, uint64_t(r));
  for (const SoftState& s : k.vars.frames) {
    append_value<int32_t>(b, s.frame);
    append_value<double>(b, s.time_s);
    append_doubles(b, s.q.data(), size_t(r));
    append_doubles(b, s.q_prev.data(), size_t(r));
    append_doubles(b, s.R.data(), 9);
    append_doubles(b, s.R_prev.data(), 9);
    append_doubles(b, s.c.data(), 3);
    append_doubles(b, s.c_prev.data(), 3);
  }
  put_mat(b, k.vars.act);
  put_vec(b, k.vars.theta);
  put_vec(b, k.res);
  for (const std::vector<double>* v : {&rep.merit, &rep.physics_violation, &rep.dmp_mismatch, &rep.w_dmp,
                                       &rep.resimulated})
    append_array(b, *v);
  framed_blob_finish(b);
  return b;
}

SpacetimeCheckpoint spacetime_checkpoint_deserialize(const std::vector<uint8_t>& bytes, uint32_t* tag) {
  ByteReader r(bytes, "soft spacetime checkpoint");
  const uint32_t t = framed_blob_open(bytes, r, kMagic, kVersion, "spacetime state");

  SpacetimeCheckpoint c;
  SpacetimeCarry& k = c.carry;
  c.iteration = r.get<int32_t>();
  c.report.steps = r.get<int32_t>();
  if (c.iteration < 0 || c.report.steps < 0) r.bad("negative count");
  const uint8_t stopped = r.get<uint8_t>();
  if (stopped > 1) r.bad("bad stop flag");
  k.stopped = stopped == 1;
  k.w_dmp = r.get<double>();
  k.lambda = r.get<double>();
  k.merit = r.get<double>();
  const uint64_t T = r.get<uint64_t>(), nq = r.get<uint64_t>();
  // Bytes per frame; checked against what remains before anything is allocated.
  if (nq > r.remaining() / 16) r.bad(std::to_string(nq) + " modal coordinates longer than the data");
  const uint64_t frame_bytes = 12 + 8 * (2 * nq + 24);
  if (T > r.remaining() / frame_bytes) r.bad(std::to_string(T) + " frames longer than the data");
  k.vars.frames.resize(T);
  for (SoftState& s : k.vars.frames) {
    s.frame = r.get<int32_t>();
    s.time_s = r.get<double>();
    s.q.resize(Eigen::Index(nq));
    s.q_prev.resize(Eigen::Index(nq));
    r.get_values(s.q.data(), nq);
    r.get_values(s.q_prev.data(), nq);
    r.get_values(s.R.data(), 9);
    r.get_values(s.R_prev.data(), 9);
    r.get_values(s.c.data(), 3);
    r.get_values(s.c_prev.data(), 3);
  }
  const uint64_t rows = r.get<uint64_t>(), cols = r.get<uint64_t>();
  if (cols != T) r.bad("activations for " + std::to_string(cols) + " frames, expected " + std::to_string(T));
  if (cols != 0 && rows > r.remaining() / sizeof(double) / cols) r.bad("activations longer than the data");
  k.vars.act.resize(Eigen::Index(cols ? rows : 0), Eigen::Index(cols));
  r.get_values(k.vars.act.data(), size_t(k.vars.act.size()));
  k.vars.theta = get_vec(r, "theta");
  k.res = get_vec(r, "residuals");
  if (T != 0 && k.res.size() == 0) r.bad("a trajectory without residuals");
  SpacetimeReport& rep = c.report;
  rep.merit = get_series(r, "merit", c.iteration);
  rep.physics_violation = get_series(r, "physics violation", c.iteration);
  rep.dmp_mismatch = get_series(r, "DMP mismatch", c.iteration);
  rep.w_dmp = get_series(r, "DMP weight", c.iteration);
  rep.resimulated = get_series(r, "re-simulated objective", c.iteration);
  if (r.remaining() != 0) r.bad("trailing bytes in the body");
  if (tag) *tag = t;
  return c;
}

}  // namespace pliant::soft
