// Painted keyframes: run-length + base64 codec and resampling (painted_grid.h).
#include "pliant/geom/painted_grid.h"

#include <algorithm>
#include <cmath>

namespace pliant::geom {
namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

int base64_digit(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

}  // namespace

std::string base64_encode(const std::vector<uint8_t>& bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t left = std::min<size_t>(3, bytes.size() - i);
    uint32_t v = uint32_t(bytes[i]) << 16;
    if (left > 1) v |= uint32_t(bytes[i + 1]) << 8;
    if (left > 2) v |= bytes[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += left > 1 ? kAlphabet[(v >> 6) & 63] : '=';
    out += left > 2 ? kAlphabet[v & 63] : '=';
  }
  return out;
}

std::vector<uint8_t> base64_decode(const std::string& text) {
  std::vector<uint8_t> out;
  out.reserve(text.size() / 4 * 3);
  uint32_t acc = 0;
  int bits = 0;
  size_t pad = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '=') {
      ++pad;
      continue;
    }
    const int d = base64_digit(c);
    if (d < 0 || pad > 0)
      throw GeomError("painted data: invalid base64 character at offset " + std::to_string(i));
    acc = (acc << 6) | uint32_t(d);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(uint8_t((acc >> bits) & 0xff));
    }
  }
  if (pad > 2) throw GeomError("painted data: too much base64 padding");
  return out;
}

std::string encode_painted(const PaintedGrid& g) {
  std::vector<uint8_t> rle;
  for (size_t i = 0; i < g.value.size();) {
    size_t run = 1;
    while (run < 256 && i + run < g.value.size() && g.value[i + run] == g.value[i]) ++run;
    rle.push_back(uint8_t(run - 1));
    rle.push_back(g.value[i]);
    i += run;
  }
  return base64_encode(rle);
}

PaintedGrid decode_painted(const std::string& data, int dim, const std::array<int, 3>& n) {
  PaintedGrid g;
  g.dim = dim;
  g.n = n;
  if (dim == 2) g.n[2] = 1;
  for (int a = 0; a < 3; ++a)
    if (g.n[a] < 1 || g.n[a] > 4096) throw GeomError("painted data: size must be 1..4096 per axis");
  const std::vector<uint8_t> rle = base64_decode(data);
  if (rle.size() % 2) throw GeomError("painted data: run-length bytes come in pairs (odd count)");
  g.value.reserve(g.cells());
  for (size_t i = 0; i < rle.size(); i += 2) {
    const size_t run = size_t(rle[i]) + 1;
    if (g.value.size() + run > g.cells())
      throw GeomError("painted data: runs cover more than the " + std::to_string(g.cells()) + " cells of its size");
    g.value.insert(g.value.end(), run, rle[i + 1]);
  }
  if (g.value.size() != g.cells())
    throw GeomError("painted data: runs cover " + std::to_string(g.value.size()) + " of " +
                    std::to_string(g.cells()) + " cells");
  return g;
}

std::vector<float> raster_painted(const RasterGrid& grid, const PaintedGrid& p) {
  const int dims = grid.dim;
  std::vector<float> out(grid.cells(), 0.0f);
  const int nz = dims == 3 ? grid.n[2] : 1;
  // Painted-grid coordinate of a target cell centre, clamped to the sample range.
  auto coord = [&](int i, int axis, int* i0, double* f) {
    const double x = (i + 0.5) * p.n[axis] / grid.n[axis] - 0.5;
    const double c = std::clamp(x, 0.0, double(p.n[axis] - 1));
    *i0 = std::min(int(std::floor(c)), p.n[axis] - 1);
    *f = c - *i0;
  };
  auto at = [&](int i, int j, int k) {
    i = std::min(i, p.n[0] - 1);
    j = std::min(j, p.n[1] - 1);
    k = std::min(k, p.n[2] - 1);
    return p.value[size_t(i) + size_t(p.n[0]) * (size_t(j) + size_t(p.n[1]) * k)] / 255.0;
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < grid.n[1]; ++j)
      for (int i = 0; i < grid.n[0]; ++i) {
        int i0, j0, k0 = 0;
        double fx, fy, fz = 0;
        coord(i, 0, &i0, &fx);
        coord(j, 1, &j0, &fy);
        if (dims == 3) coord(k, 2, &k0, &fz);
        double v = 0;
        for (int c = 0; c < (dims == 3 ? 8 : 4); ++c) {
          const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
          const double w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz);
          if (w > 0) v += w * at(i0 + dx, j0 + dy, k0 + dz);
        }
        out[size_t(i) + size_t(grid.n[0]) * (size_t(j) + size_t(grid.n[1]) * k)] = float(v);
      }
  return out;
}

}  // namespace pliant::geom
