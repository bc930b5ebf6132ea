#include <gtest/gtest.h>

#include <filesystem>

#include "render/image_compare.h"
#include "render/screenshot.h"

namespace pliant::editor {
namespace {

Image solid(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  Image img{w, h, std::vector<uint8_t>(size_t(w) * h * 4)};
  for (int i = 0; i < w * h; ++i) {
    img.rgba[i * 4 + 0] = r;
    img.rgba[i * 4 + 1] = g;
    img.rgba[i * 4 + 2] = b;
    img.rgba[i * 4 + 3] = 255;
  }
  return img;
}

TEST(ImageCompare, IdenticalImagesPassWithZeroDifference) {
  const Image a = solid(8, 4, 10, 20, 30);
  const auto r = compare(a, a, 0, 0.0);
  EXPECT_TRUE(r.pass);
  EXPECT_EQ(r.max_diff, 0);
  EXPECT_DOUBLE_EQ(r.mean_diff, 0.0);
}

TEST(ImageCompare, MaxAndMeanOfOneChangedPixel) {
  const Image a = solid(10, 10, 100, 100, 100);
  Image b = a;
  b.pixel(3, 7)[1] = 112;  // one channel of one pixel off by 12
  const auto r = compare(b, a, 8, 0.5);
  EXPECT_EQ(r.max_diff, 12);
  EXPECT_NEAR(r.mean_diff, 12.0 / 400.0, 1e-12);  // 100 pixels x 4 channels
  EXPECT_EQ(r.differing_pixels, 1);
  EXPECT_FALSE(r.pass);                      // max beyond 8
  EXPECT_TRUE(compare(b, a, 12, 0.5).pass);  // within 12
  EXPECT_FALSE(compare(b, a, 12, 0.01).pass);  // mean beyond 0.01
}

TEST(ImageCompare, SizeMismatchFails) {
  const auto r = compare(solid(4, 4, 0, 0, 0), solid(4, 5, 0, 0, 0), 255, 255);
  EXPECT_FALSE(r.pass);
  EXPECT_TRUE(r.size_mismatch);
  EXPECT_NE(r.message.find("4x5"), std::string::npos) << r.message;
}

TEST(ImageCompare, DiffImageAmplifiesAndMarksFailures) {
  const Image a = solid(2, 1, 100, 100, 100);
  Image b = a;
  b.pixel(0, 0)[0] = 103;  // small: amplified x8 = 24
  b.pixel(1, 0)[2] = 200;  // beyond tolerance: magenta
  const Image d = diff_image(b, a, 8, 8.0f);
  ASSERT_EQ(d.width, 2);
  EXPECT_EQ(d.pixel(0, 0)[0], 24);
  EXPECT_EQ(d.pixel(0, 0)[1], 0);
  EXPECT_EQ(d.pixel(1, 0)[0], 255);
  EXPECT_EQ(d.pixel(1, 0)[1], 0);
  EXPECT_EQ(d.pixel(1, 0)[2], 255);
  EXPECT_EQ(d.pixel(1, 0)[3], 255);
}

TEST(Screenshot, PngRoundTripIsLossless) {
  Image a = solid(5, 3, 1, 2, 3);
  a.pixel(4, 2)[0] = 250;
  a.pixel(0, 0)[3] = 128;
  const auto path = (std::filesystem::temp_directory_path() / "pliant_png_roundtrip.png").string();
  std::string err;
  ASSERT_TRUE(write_png(path, a, &err)) << err;
  const Image b = read_png(path, &err);
  ASSERT_FALSE(b.empty()) << err;
  EXPECT_EQ(b.width, 5);
  EXPECT_EQ(b.height, 3);
  EXPECT_EQ(b.rgba, a.rgba);
  std::filesystem::remove(path);
  EXPECT_TRUE(read_png(path, &err).empty());
  EXPECT_NE(err.find(path), std::string::npos) << err;
}

}  // namespace
}  // namespace pliant::editor
