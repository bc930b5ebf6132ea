// Painted keyframes: the inline codec round-trips bit for bit, rejects damaged
// data with a message, and resampling preserves equal-size grids exactly and
// the covered area across resolutions.
#include <gtest/gtest.h>

#include <random>

#include "pliant/geom/keyframe_raster.h"
#include "pliant/geom/painted_grid.h"

namespace pliant::geom {
namespace {

TEST(PaintedGrid, Base64KnownVectors) {
  // RFC 4648 section 10 test vectors.
  const std::vector<std::pair<std::string, std::string>> v = {
      {"", ""}, {"f", "Zg=="}, {"fo", "Zm8="}, {"foo", "Zm9v"}, {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="},
      {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : v) {
    const std::vector<uint8_t> bytes(plain.begin(), plain.end());
    EXPECT_EQ(base64_encode(bytes), coded);
    EXPECT_EQ(base64_decode(coded), bytes);
  }
}

TEST(PaintedGrid, RoundTripIsBitExact) {
  PaintedGrid g;
  g.n = {37, 29, 1};
  g.value.assign(g.cells(), 0);
  std::mt19937 rng(7);
  // Long runs (longer than 256) and noisy patches both occur in painted masks.
  for (size_t i = 400; i < 900; ++i) g.value[i] = 255;
  for (size_t i = 900; i < g.cells(); ++i) g.value[i] = uint8_t(rng() % 3 == 0 ? rng() : 0);
  const PaintedGrid back = decode_painted(encode_painted(g), 2, g.n);
  EXPECT_EQ(back.value, g.value);
}

TEST(PaintedGrid, DamagedDataIsRejected) {
  PaintedGrid g;
  g.n = {8, 8, 1};
  g.value.assign(64, 9);
  const std::string ok = encode_painted(g);
  EXPECT_THROW(decode_painted(ok, 2, {8, 9, 1}), GeomError);  // too few cells
  EXPECT_THROW(decode_painted(ok, 2, {4, 8, 1}), GeomError);  // too many
  EXPECT_THROW(decode_painted("!!!!", 2, {8, 8, 1}), GeomError);
  try {
    decode_painted(ok, 2, {0, 8, 1});
    FAIL();
  } catch (const GeomError& e) {
    EXPECT_NE(std::string(e.what()).find("painted data"), std::string::npos);
  }
}

TEST(PaintedGrid, SameSizeCopiesAndResampleKeepsArea) {
  RasterGrid grid;
  grid.n = {32, 32, 1};
  grid.cell_size_m = 1.0 / 32;
  PaintedGrid p;
  p.n = {32, 32, 1};
  p.value.assign(p.cells(), 0);
  for (int j = 8; j < 24; ++j)
    for (int i = 4; i < 20; ++i) p.value[i + 32 * j] = 255;
  const auto same = raster_painted(grid, p);
  for (size_t c = 0; c < same.size(); ++c) ASSERT_FLOAT_EQ(same[c], p.value[c] / 255.0f);
  // A 16x16 square on a 64^2 grid covers the same area of the unit domain.
  RasterGrid fine = grid;
  fine.n = {64, 64, 1};
  fine.cell_size_m = 1.0 / 64;
  const double a_coarse = raster_measure(grid, same), a_fine = raster_measure(fine, raster_painted(fine, p));
  EXPECT_NEAR(a_fine, a_coarse, 0.02 * a_coarse);
  // Row 0 is the bottom: the square's lower edge stays in the lower half.
  const auto fine_d = raster_painted(fine, p);
  EXPECT_GT(fine_d[10 + 64 * 20], 0.99f);
  EXPECT_LT(fine_d[10 + 64 * 60], 0.01f);
}

}  // namespace
}  // namespace pliant::geom
