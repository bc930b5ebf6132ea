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
#include <bit>
#include <cstring>
#include <stdexcept>
#include <string>

#include "pliant/core/crc32.h"
#include "pliant/soft/optimizer.h"

static_assert(std::endian::native == std::endian::little, "the checkpoint format is little-endian");

namespace pliant::soft {
namespace {

constexpr uint32_t kMagic = 0x4f534c50;  // "PLSO"
constexpr uint32_t kVersion = 1;
constexpr size_t kHeaderBytes = 24;
constexpr uint32_t kMaxStepKind = 64;

template <class T>
void put(std::vector<uint8_t>& b, const T& v) {
  const size_t o = b.size();
  b.resize(o + sizeof(T));
  std::memcpy(b.data() + o, &v, sizeof(T));
}

void put_doubles(std::vector<uint8_t>& b, const double* p, size_t n) {
  const size_t o = b.size();
  b.resize(o + n * sizeof(double));
  if (n) std::memcpy(b.data() + o, p, n * sizeof(double));
}

void put_vec(std::vector<uint8_t>& b, const Eigen::VectorXd& v) {
  put<uint64_t>(b, uint64_t(v.size()));
  put_doubles(b, v.data(), size_t(v.size()));
}

void put_mat(std::vector<uint8_t>& b, const Eigen::MatrixXd& m) {
  put<uint64_t>(b, uint64_t(m.rows()));
  put<uint64_t>(b, uint64_t(m.cols()));
  put_doubles(b, m.data(), size_t(m.size()));
}

struct Reader {
  const std::vector<uint8_t>& b;
  size_t pos = 0, end = 0;
  [[noreturn]] void bad(const std::string& what) const {
    throw std::runtime_error("soft optimizer checkpoint: " + what + " at byte " + std::to_string(pos) + " of " +
                             std::to_string(b.size()));
  }
  size_t left() const { return end - pos; }
  template <class T>
  T get() {
    if (left() < sizeof(T)) bad("truncated");
    T v;
    std::memcpy(&v, b.data() + pos, sizeof(T));
    pos += sizeof(T);
    return v;
  }
  int32_t count(const char* what) {
    const int32_t v = get<int32_t>();
    if (v < 0) bad(std::string("negative ") + what);
    return v;
  }
  void doubles(double* p, uint64_t n) {
    if (n) std::memcpy(p, b.data() + pos, n * sizeof(double));
    pos += n * sizeof(double);
  }
  // A vector of n doubles; `want` >= 0: its size must be 0 or want.
  Eigen::VectorXd vec(const char* what, int64_t want = -1) {
    const uint64_t n = get<uint64_t>();
    if (n > left() / sizeof(double))
      bad(std::string(what) + " of " + std::to_string(n) + " values longer than the data");
    if (want >= 0 && n != 0 && n != uint64_t(want))
      bad(std::string(what) + " has " + std::to_string(n) + " values, expected " + std::to_string(want));
    Eigen::VectorXd v(static_cast<Eigen::Index>(n));
    doubles(v.data(), n);
    return v;
  }
  // Empty, or rows x cols.
  Eigen::MatrixXd mat(const char* what, int64_t rows, int64_t cols) {
    const uint64_t r = get<uint64_t>(), c = get<uint64_t>();
    const bool empty = r == 0 || c == 0;
    if (!empty && (r != uint64_t(rows) || c != uint64_t(cols)))
      bad(std::string(what) + " is " + std::to_string(r) + " x " + std::to_string(c) + ", expected " +
          std::to_string(rows) + " x " + std::to_string(cols));
    if (!empty && r > left() / sizeof(double) / c) bad(std::string(what) + " longer than the data");
    Eigen::MatrixXd m(static_cast<Eigen::Index>(empty ? 0 : r), static_cast<Eigen::Index>(empty ? 0 : c));
    doubles(m.data(), uint64_t(m.size()));
    return m;
  }
};

}  // namespace

std::vector<uint8_t> optimizer_state_serialize(const OptimizerState& s, uint32_t tag) {
  std::vector<uint8_t> b;
  const OptimizerMemory& m = s.memory;
  size_t reserve = kHeaderBytes + 256 + 8 * size_t(s.theta.size() + s.history.size() + m.theta.size() + m.r.size() +
                                                   m.J.size() + m.J_at.size() + m.g_prev.size() + m.theta_prev.size());
  for (size_t i = 0; i < m.S.size(); ++i) reserve += 16 + 8 * size_t(m.S[i].size() + m.Y[i].size());
  for (const auto& k : s.step_kinds) reserve += 4 + k.size();
  b.reserve(reserve);
  put(b, kMagic);
  put(b, kVersion);
  put<uint64_t>(b, 0);  // body bytes, set below
  put<uint32_t>(b, 0);  // CRC, set below
  put<uint32_t>(b, tag);
  put<int32_t>(b, s.iteration);
  put<int32_t>(b, s.evaluations);
  put<int32_t>(b, s.lbfgs_restarts_used);
  put<uint8_t>(b, s.in_lbfgs ? 1 : 0);
  put<double>(b, s.objective);
  put<double>(b, s.lambda);
  put_vec(b, s.theta);
  put<uint64_t>(b, s.history.size());
  put_doubles(b, s.history.data(), s.history.size());
  put<uint64_t>(b, s.step_kinds.size());
  for (const auto& k : s.step_kinds) {
    if (k.size() > kMaxStepKind) throw std::invalid_argument("optimizer_state_serialize: step kind too long");
    put<uint32_t>(b, uint32_t(k.size()));
    b.insert(b.end(), k.begin(), k.end());
  }
  put_vec(b, m.theta);
  put_vec(b, m.r);
  put_mat(b, m.J);
  put<int32_t>(b, m.reused);
  put_mat(b, m.J_at);
  put<int32_t>(b, m.lm_stalls);
  put<double>(b, m.last_lm_step);
  put<double>(b, m.last_lbfgs_step);
  put<double>(b, m.radius);
  put<uint64_t>(b, m.S.size());
  for (size_t i = 0; i < m.S.size(); ++i) put_vec(b, m.S[i]), put_vec(b, m.Y[i]);
  put_vec(b, m.g_prev);
  put_vec(b, m.theta_prev);
  const uint64_t body = b.size() - kHeaderBytes;
  const uint32_t crc = crc32(b.data() + kHeaderBytes, body);
  std::memcpy(b.data() + 8, &body, 8);
  std::memcpy(b.data() + 16, &crc, 4);
  return b;
}

OptimizerState optimizer_state_deserialize(const std::vector<uint8_t>& bytes, uint32_t* tag) {
  Reader r{bytes, 0, bytes.size()};
  if (r.get<uint32_t>() != kMagic) r.bad("not a soft optimizer state (bad magic)");
  const uint32_t version = r.get<uint32_t>();
  if (version != kVersion) r.bad("unsupported version " + std::to_string(version));
  const uint64_t body = r.get<uint64_t>();
  const uint32_t crc = r.get<uint32_t>();
  const uint32_t t = r.get<uint32_t>();
  if (body > bytes.size() - kHeaderBytes)
    r.bad("truncated: the body has " + std::to_string(bytes.size() - kHeaderBytes) + " of its " +
          std::to_string(body) + " bytes");
  if (bytes.size() - kHeaderBytes - body > 3) r.bad("trailing bytes");
  for (size_t i = kHeaderBytes + body; i < bytes.size(); ++i)
    if (bytes[i] != 0) r.bad("trailing bytes");
  r.end = kHeaderBytes + body;
  if (crc32(bytes.data() + kHeaderBytes, body) != crc) r.bad("CRC mismatch (damaged data)");

  OptimizerState s;
  s.iteration = r.count("iteration");
  s.evaluations = r.count("evaluation count");
  s.lbfgs_restarts_used = r.count("restart count");
  const uint8_t in_lbfgs = r.get<uint8_t>();
  if (in_lbfgs > 1) r.bad("bad L-BFGS phase flag");
  s.in_lbfgs = in_lbfgs == 1;
  s.objective = r.get<double>();
  s.lambda = r.get<double>();
  s.theta = r.vec("theta");
  const int64_t n = s.theta.size();
  const uint64_t h = r.get<uint64_t>();
  if (h > r.left() / sizeof(double)) r.bad("history of " + std::to_string(h) + " values longer than the data");
  // One objective per iteration after the initial one.
  if (h != uint64_t(s.iteration) + 1)
    r.bad("history of " + std::to_string(h) + " values for " + std::to_string(s.iteration) + " iterations");
  s.history.resize(h);
  r.doubles(s.history.data(), h);
  const uint64_t kinds = r.get<uint64_t>();
  if (kinds > r.left() / 4 || kinds > uint64_t(s.iteration))
    r.bad(std::to_string(kinds) + " step kinds for " + std::to_string(s.iteration) + " iterations");
  s.step_kinds.resize(kinds);
  for (auto& k : s.step_kinds) {
    const uint32_t len = r.get<uint32_t>();
    if (len > kMaxStepKind || len > r.left()) r.bad("bad step kind length " + std::to_string(len));
    k.assign(reinterpret_cast<const char*>(bytes.data() + r.pos), len);
    r.pos += len;
  }
  OptimizerMemory& m = s.memory;
  m.theta = r.vec("memory theta", n);
  m.r = r.vec("residuals");
  const int64_t rows = m.r.size();
  m.J = r.mat("J", rows, n);
  m.reused = r.count("Broyden reuse count");
  m.J_at = r.mat("J_at", rows, n);
  m.lm_stalls = r.count("LM stall count");
  m.last_lm_step = r.get<double>();
  m.last_lbfgs_step = r.get<double>();
  m.radius = r.get<double>();
  const uint64_t pairs = r.get<uint64_t>();
  if (pairs > r.left() / 16) r.bad(std::to_string(pairs) + " curvature pairs longer than the data");
  for (uint64_t i = 0; i < pairs; ++i) {
    m.S.push_back(r.vec("curvature pair s", n));
    m.Y.push_back(r.vec("curvature pair y", n));
    if (m.S.back().size() != n || m.Y.back().size() != n) r.bad("empty curvature pair");
  }
  m.g_prev = r.vec("previous gradient", n);
  m.theta_prev = r.vec("previous point", n);
  if (r.pos != r.end) r.bad("trailing bytes in the body");
  if (m.theta.size() != 0 && m.r.size() == 0) r.bad("memory without residuals");
  if (tag) *tag = t;
  return s;
}

}  // namespace pliant::soft
