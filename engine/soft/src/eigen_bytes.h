// Eigen vectors and matrices in soft's checkpoint blobs (optimizer_state.cpp,
// spacetime_state.cpp), on core's byte streams:
//   vec = u64 n + n f64; mat = u64 rows + u64 cols + rows x cols f64 (column-major).
#pragma once
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "pliant/core/byte_stream.h"

namespace pliant::soft {

inline void put_vec(std::vector<uint8_t>& b, const Eigen::VectorXd& v) {
  append_value<uint64_t>(b, uint64_t(v.size()));
  append_doubles(b, v.data(), size_t(v.size()));
}

inline void put_mat(std::vector<uint8_t>& b, const Eigen::MatrixXd& m) {
  append_value<uint64_t>(b, uint64_t(m.rows()));
  append_value<uint64_t>(b, uint64_t(m.cols()));
  append_doubles(b, m.data(), size_t(m.size()));
}

// A vector of n doubles; `want` >= 0: its size must be 0 or want.
inline Eigen::VectorXd get_vec(ByteReader& r, const char* what, int64_t want = -1) {
  const uint64_t n = r.get_length<double>(what);
  if (want >= 0 && n != 0 && n != uint64_t(want))
    r.bad(std::string(what) + " has " + std::to_string(n) + " values, expected " + std::to_string(want));
  Eigen::VectorXd v(static_cast<Eigen::Index>(n));
  r.get_values(v.data(), n);
  return v;
}

// Empty, or rows x cols.
inline Eigen::MatrixXd get_mat(ByteReader& r, const char* what, int64_t rows, int64_t cols) {
  const uint64_t nr = r.get<uint64_t>(), nc = r.get<uint64_t>();
  const bool empty = nr == 0 || nc == 0;
  if (!empty && (nr != uint64_t(rows) || nc != uint64_t(cols)))
    r.bad(std::string(what) + " is " + std::to_string(nr) + " x " + std::to_string(nc) + ", expected " +
          std::to_string(rows) + " x " + std::to_string(cols));
  if (!empty && nr > r.remaining() / sizeof(double) / nc) r.bad(std::string(what) + " longer than the data");
  Eigen::MatrixXd m(static_cast<Eigen::Index>(empty ? 0 : nr), static_cast<Eigen::Index>(empty ? 0 : nc));
  r.get_values(m.data(), size_t(m.size()));
  return m;
}

}  // namespace pliant::soft
