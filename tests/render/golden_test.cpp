// The golden-image helper itself: passes on a match, fails with diff and actual
// files on a mismatch, rewrites the golden when PLIANT_UPDATE_GOLDEN=1.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <unistd.h>

#include "golden.h"
#include "render/screenshot.h"

namespace pliant::test {
namespace {
namespace fs = std::filesystem;

editor::Image gradient(int w, int h, int offset) {
  editor::Image img{w, h, std::vector<uint8_t>(size_t(w) * h * 4, 255)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.pixel(x, y)[0] = uint8_t((x * 16 + offset) & 255);
  return img;
}

class GoldenHelper : public ::testing::Test {
 protected:
  void SetUp() override {
    saved_ = std::getenv("PLIANT_UPDATE_GOLDEN") ? std::getenv("PLIANT_UPDATE_GOLDEN") : "";
    unsetenv("PLIANT_UPDATE_GOLDEN");
    dir_ = fs::temp_directory_path() / ("pliant_golden_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override {
    if (!saved_.empty()) setenv("PLIANT_UPDATE_GOLDEN", saved_.c_str(), 1);
    fs::remove_all(dir_);
  }
  std::string saved_;
  fs::path dir_;
};

TEST_F(GoldenHelper, MatchMismatchAndUpdate) {
  const std::string golden = (dir_ / "g" / "img.png").string();
  const std::string diff = (dir_ / "out" / "img_diff.png").string();
  // Missing golden: fails and says how to make one.
  auto r = matches_golden(gradient(8, 8, 0), golden, diff);
  EXPECT_FALSE(r);
  EXPECT_NE(std::string(r.message()).find("PLIANT_UPDATE_GOLDEN=1"), std::string::npos) << r.message();
  // Update mode writes it.
  setenv("PLIANT_UPDATE_GOLDEN", "1", 1);
  EXPECT_TRUE(matches_golden(gradient(8, 8, 0), golden, diff));
  unsetenv("PLIANT_UPDATE_GOLDEN");
  ASSERT_TRUE(fs::exists(golden));
  // Within tolerance: a shift of 3 levels passes at max_tol 8 (mean 3/4 over RGBA > 0.5, so widen it).
  EXPECT_TRUE(matches_golden(gradient(8, 8, 3), golden, diff, 8, 1.0));
  EXPECT_FALSE(fs::exists(diff));
  // Beyond tolerance: fails, writes the diff and the actual, and names them.
  r = matches_golden(gradient(8, 8, 40), golden, diff);
  EXPECT_FALSE(r);
  EXPECT_TRUE(fs::exists(diff));
  const std::string actual = (dir_ / "out" / "img_diff_actual.png").string();
  EXPECT_TRUE(fs::exists(actual));
  EXPECT_NE(std::string(r.message()).find(diff), std::string::npos) << r.message();
  EXPECT_EQ(editor::read_png(actual).rgba, gradient(8, 8, 40).rgba);
}

}  // namespace
}  // namespace pliant::test
