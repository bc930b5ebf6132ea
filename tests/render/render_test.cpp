// Golden-image and pixel tests of the renderer on EGL headless (Mesa llvmpipe).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "golden.h"
#include "render/image_compare.h"
#include "render/mat4.h"
#include "render_test_util.h"
#include "synthetic_frames.h"

namespace pliant::test {
namespace {
using editor::Image;
using editor::OrbitCamera;

// Blob in the upper-right part of a 64x48 domain, so orientation errors show.
Record blob_frame(float cx = 40, float cy = 30) { return frame_of({gaussian_blob_2d(64, 48, cx, cy, 6.0f)}); }

class EglRender : public ::testing::Test {
 protected:
  void SetUp() override {
    platform_ = editor::make_egl_platform();
    editor::PlatformOptions opt;
    opt.width = kWidth;
    opt.height = kHeight;
    std::string err;
    ASSERT_TRUE(platform_->init(opt, &err)) << "cannot create the EGL platform: " << err;
    ASSERT_TRUE(renderer_.init(&err)) << err;
  }
  void TearDown() override {
    renderer_.shutdown();
    if (platform_) platform_->shutdown();
  }
  Image render(const Record& frame, const OrbitCamera& cam = {}, editor::ViewSettings view = golden_view()) {
    return render_frame(*platform_, renderer_, frame, cam, view);
  }
  // Pixel (top-down) where the world point (x, y, 0) of a 2D frame lands.
  std::array<int, 2> pixel_of_2d(const OrbitCamera& cam, float x, float y) {
    const auto e = renderer_.domain_extent();
    const auto m = cam.view_projection_2d(float(kWidth) / kHeight, e[0], e[1]);
    const auto c = editor::mat4_apply(m, {x, y, 0, 1});
    return {int((c[0] * 0.5f + 0.5f) * kWidth), int((0.5f - c[1] * 0.5f) * kHeight)};
  }

  std::unique_ptr<editor::Platform> platform_;
  editor::Renderer renderer_;
};

TEST_F(EglRender, Blob2DMatchesGolden) {
  PLIANT_EXPECT_MATCHES_GOLDEN(render(blob_frame()), golden_path("blob2d"), diff_path("blob2d"));
}

TEST_F(EglRender, Blob2DWithVelocityArrowsMatchesGolden) {
  auto view = golden_view();
  view.show_velocity = true;
  const Record f = frame_of({gaussian_blob_2d(64, 48, 40, 30, 6.0f), vortex_velocity_2d(64, 48, 32, 24)});
  const Image img = render(f, {}, view);
  PLIANT_EXPECT_MATCHES_GOLDEN(img, golden_path("blob2d_velocity"), diff_path("blob2d_velocity"));
  // The arrows change the picture compared to the same frame without them.
  view.show_velocity = false;
  EXPECT_GT(editor::compare(img, render(f, {}, view), 8, 0.5).max_diff, 64);
}

TEST_F(EglRender, Sphere3DMatchesGolden) {
  PLIANT_EXPECT_MATCHES_GOLDEN(render(frame_of({sphere_3d(32, 10.0f)})), golden_path("sphere3d"), diff_path("sphere3d"));
}

// The golden comparison can fail: a shifted blob is far outside its tolerance.
TEST_F(EglRender, ShiftedBlobFailsTheGoldenTolerance) {
  const Image reference = render(blob_frame());
  const auto r = editor::compare(render(blob_frame(24, 18)), reference, kGoldenMaxTol, kGoldenMeanTol);
  EXPECT_FALSE(r.pass) << r.message;
  EXPECT_GT(r.max_diff, 100);
  // And a one-cell shift is still caught by the maximum.
  EXPECT_FALSE(editor::compare(render(blob_frame(41, 30)), reference, kGoldenMaxTol, kGoldenMeanTol).pass);
}

TEST_F(EglRender, BlobCentreIsBrightAndUpIsUp) {
  const OrbitCamera cam;
  const Image img = render(blob_frame());
  const auto e = renderer_.domain_extent();
  ASSERT_FLOAT_EQ(e[0], 1.0f);
  ASSERT_FLOAT_EQ(e[1], 0.75f);
  // Cell (40, 30) centre in world units: the domain is [-0.5, 0.5] x [-0.375, 0.375].
  const float cell = 1.0f / 64;
  const auto p = pixel_of_2d(cam, -0.5f + 40.5f * cell, -0.375f + 30.5f * cell);
  const float centre = luma(img, p[0], p[1]);
  EXPECT_GT(centre, 120.0f);
  EXPECT_LT(luma(img, 2, 2), 30.0f);  // background corner
  // Density row 30 of 48 is above the middle: the top-right quadrant is brighter
  // than the bottom-left one (an upside-down or mirrored image would flip this).
  EXPECT_GT(mean_luma(img, kWidth / 2, 0, kWidth, kHeight / 2), mean_luma(img, 0, kHeight / 2, kWidth / 2, kHeight) + 10);
  EXPECT_GT(p[0], kWidth / 2);
  EXPECT_LT(p[1], kHeight / 2);
}

// Uniform density d gives alpha = 1 - exp(-scale * d) over the background
// (smoke2d.frag, Beer-Lambert), exactly, inside the domain.
TEST_F(EglRender, UniformDensityFollowsBeerLambert) {
  auto view = golden_view();
  view.show_grid = false;
  view.density_scale = 1.0f;
  const Image img = render(frame_of({uniform_density({48, 64}, 0.5f)}), {}, view);
  const float a = 1.0f - std::exp(-0.5f);
  for (int c = 0; c < 3; ++c) {
    const float expect = 255.0f * (view.background[c] * (1 - a) + view.smoke_color[c] * a);
    EXPECT_NEAR(img.pixel(kWidth / 2, kHeight / 2)[c], expect, 1.5f) << "channel " << c;
    EXPECT_NEAR(img.pixel(2, 2)[c], 255.0f * view.background[c], 1.0f) << "outside the domain, channel " << c;
  }
  EXPECT_EQ(img.pixel(kWidth / 2, kHeight / 2)[3], 255);
}

TEST_F(EglRender, ZeroDensityIsPureBackgroundIn2DAnd3D) {
  auto view = golden_view();
  view.show_grid = false;
  for (const Record& f : {frame_of({uniform_density({48, 64}, 0.0f)}), frame_of({uniform_density({16, 16, 16}, 0.0f)})}) {
    const Image img = render(f, {}, view);
    int worst = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        for (int c = 0; c < 3; ++c)
          worst = std::max(worst, std::abs(int(img.pixel(x, y)[c]) - int(std::lround(255 * view.background[c]))));
    EXPECT_LE(worst, 1) << "dim " << renderer_.frame_dim();
  }
}

TEST_F(EglRender, SphereCentreIsLitCornerIsBackground) {
  const Image img = render(frame_of({sphere_3d(32, 10.0f)}));
  EXPECT_EQ(renderer_.frame_dim(), 3);
  // The default camera looks at the origin, the sphere's centre: the middle pixel.
  EXPECT_GT(luma(img, kWidth / 2, kHeight / 2), 100.0f);
  EXPECT_LT(luma(img, 2, 2), 30.0f);
  // Thinner smoke scatters less light: the centre gets darker.
  auto view = golden_view();
  view.density_scale = 0.05f;
  const Image thin = render(frame_of({sphere_3d(32, 10.0f)}), {}, view);
  EXPECT_LT(luma(thin, kWidth / 2, kHeight / 2), luma(img, kWidth / 2, kHeight / 2) - 30.0f);
}

// Density index j grows up the screen and i to the right (the default camera
// looks from +z, turned 30 degrees toward +x, so +x still points right).
TEST_F(EglRender, VolumeUpIsUpAndRightIsRight) {
  auto view = golden_view();
  view.show_grid = false;
  const Image up = render(frame_of({sphere_3d_at(32, 6, 15.5f, 25, 15.5f)}), {}, view);
  EXPECT_GT(mean_luma(up, 0, 0, kWidth, kHeight / 2), mean_luma(up, 0, kHeight / 2, kWidth, kHeight) + 5);
  const Image right = render(frame_of({sphere_3d_at(32, 6, 25, 15.5f, 15.5f)}), {}, view);
  EXPECT_GT(mean_luma(right, kWidth / 2, 0, kWidth, kHeight), mean_luma(right, 0, 0, kWidth / 2, kHeight) + 5);
}

TEST_F(EglRender, RenderingIsDeterministic) {
  const Record f = frame_of({sphere_3d(32, 10.0f)});
  const auto r = editor::compare(render(f), render(f), 0, 0.0);
  EXPECT_TRUE(r.pass) << r.message;
}

TEST_F(EglRender, FrameWithoutDensityClearsTheFrame) {
  renderer_.set_frame(blob_frame());
  EXPECT_EQ(renderer_.frame_dim(), 2);
  renderer_.set_frame(frame_of({}));
  EXPECT_FALSE(renderer_.has_frame());
  Field bad = gaussian_blob_2d(8, 8, 4, 4, 2);
  bad.data.pop_back();  // shape and data disagree
  renderer_.set_frame(frame_of({bad}));
  EXPECT_FALSE(renderer_.has_frame());
  renderer_.set_frame(frame_of({sphere_3d(8, 3)}));
  EXPECT_EQ(renderer_.frame_dim(), 3);
  EXPECT_FLOAT_EQ(renderer_.domain_extent()[2], 1.0f);
}

}  // namespace
}  // namespace pliant::test
