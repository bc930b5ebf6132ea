// Keyframe target rasterisers: areas and volumes against analytic values, image
// round trips, text masks of plausible size, mesh voxelisation, error messages.
#include <gtest/gtest.h>
#include <stb/stb_image_write.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "pliant/geom/keyframe_raster.h"

namespace pliant::geom {
namespace {

RasterGrid grid2(int n, double h = 0.01) {
  RasterGrid g;
  g.dim = 2;
  g.n = {n, n, 1};
  g.cell_size_m = h;
  return g;
}

TEST(KeyframeRaster, CircleAreaWithinOnePercent) {
  const RasterGrid g = grid2(64);
  Placement p;
  p.center_m = {0.31, 0.33, 0};
  const double r = 0.17;
  const auto d = raster_sphere(g, p, r, 4);
  EXPECT_NEAR(raster_measure(g, d), std::numbers::pi * r * r, 0.01 * std::numbers::pi * r * r);
  for (float v : d) {
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
  }
}

TEST(KeyframeRaster, RotatedBoxKeepsItsArea) {
  const RasterGrid g = grid2(64);
  Placement p;
  p.center_m = {0.32, 0.32, 0};
  p.rotation_deg = 30;
  p.scale = 1.5;
  const auto d = raster_box(g, p, {0.1, 0.05, 0}, 4);
  const double area = (2 * 0.1 * 1.5) * (2 * 0.05 * 1.5);
  EXPECT_NEAR(raster_measure(g, d), area, 0.01 * area);
}

TEST(KeyframeRaster, SphereVolume3D) {
  RasterGrid g;
  g.dim = 3;
  g.n = {32, 32, 32};
  g.cell_size_m = 1.0 / 32;
  Placement p;
  p.center_m = {0.5, 0.5, 0.5};
  const auto d = raster_sphere(g, p, 0.3, 3);
  const double v = 4.0 / 3.0 * std::numbers::pi * 0.027;
  EXPECT_NEAR(raster_measure(g, d), v, 0.01 * v);
}

TEST(KeyframeRaster, ImageRoundTrip) {
  // A 40x20 PNG, white left half: placed to cover the grid exactly, the left half
  // of the grid is 1 and the right half 0 (rows flip: image row 0 is the top).
  const int w = 40, h = 20;
  std::vector<unsigned char> px(size_t(w) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) px[size_t(y) * w + x] = (x < w / 2 && y < h / 2) ? 255 : 0;
  const auto file = std::filesystem::temp_directory_path() / "pliant_geom_roundtrip.png";
  ASSERT_TRUE(stbi_write_png(file.string().c_str(), w, h, 1, px.data(), w));
  CoverageImage img = load_coverage_image(file, "roundtrip.png", ImageChannel::Luma);
  ASSERT_EQ(img.width, w);
  ASSERT_EQ(img.height, h);
  RasterGrid g;
  g.dim = 2;
  g.n = {40, 20, 1};
  g.cell_size_m = 0.01;
  Placement p;
  p.center_m = {0.2, 0.1, 0};
  threshold_coverage(img, 0.5, "roundtrip.png");
  const auto d = raster_image(g, img, p, 0.2, 0, 1);
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 40; ++i) EXPECT_FLOAT_EQ(d[i + 40 * j], (i < 20 && j >= 10) ? 1.0f : 0.0f) << i << "," << j;
  std::filesystem::remove(file);
  EXPECT_THROW(load_coverage_image(file, "gone.png", ImageChannel::Luma), GeomError);
  try {
    load_coverage_image(file, "assets/masks/gone.png", ImageChannel::Luma);
  } catch (const GeomError& e) {
    EXPECT_NE(std::string(e.what()).find("assets/masks/gone.png: cannot read image"), std::string::npos);
  }
}

TEST(KeyframeRaster, EmptyMaskAfterThresholdIsAnError) {
  CoverageImage img;
  img.width = img.height = 2;
  img.value = {0.1f, 0.2f, 0.3f, 0.4f};
  try {
    threshold_coverage(img, 0.5, "dim.png");
    FAIL();
  } catch (const GeomError& e) {
    EXPECT_NE(std::string(e.what()).find("mask is empty after thresholding"), std::string::npos);
  }
}

TEST(KeyframeRaster, TextHasPlausibleInk) {
  const auto font = std::filesystem::path(PLIANT_ASSETS_DIR) / "fonts/DejaVuSans-Bold.ttf";
  const CoverageImage img = render_text("F", font, "DejaVuSans-Bold.ttf", 100);
  // A bold F of cap height ~73 px: ink is a sizeable but partial fraction of its box.
  EXPECT_GT(img.height, 60);
  EXPECT_LT(img.height, 100);
  double ink = 0;
  for (float v : img.value) ink += v;
  const double frac = ink / (double(img.width) * img.height);
  EXPECT_GT(frac, 0.3);
  EXPECT_LT(frac, 0.8);
  // Placed on a grid, its area is the image fraction times the placed box.
  const RasterGrid g = grid2(128);
  Placement p;
  p.center_m = {0.64, 0.64, 0};
  const auto d = raster_image(g, img, p, 0.8, 0, 3);
  const double box = 0.8 * 0.8 * img.width / img.height;
  EXPECT_NEAR(raster_measure(g, d), frac * box, 0.03 * frac * box);
  // Wider text is wider.
  const CoverageImage word = render_text("FLUID", font, "DejaVuSans-Bold.ttf", 100);
  EXPECT_GT(word.width, 4 * img.width);
  EXPECT_THROW(render_text("", font, "f", 100), GeomError);
  EXPECT_THROW(render_text("A", "/nonexistent.ttf", "nofont.ttf", 100), GeomError);
}

TEST(KeyframeRaster, CubeMeshVoxelisesToItsVolume) {
  const TriangleMesh cube = unit_cube_mesh();
  EXPECT_NEAR(cube.signed_volume(), 1.0, 1e-12);
  RasterGrid g;
  g.dim = 3;
  g.n = {32, 32, 32};
  g.cell_size_m = 1.0 / 32;
  Placement p;
  p.center_m = {0.5, 0.5, 0.5};
  const auto d = raster_mesh(g, cube, p, 0.5, 2);
  EXPECT_NEAR(raster_measure(g, d), 0.125, 0.125 * 0.01);
  // Rotated 45 degrees about z the volume is the same.
  p.rotation_deg = 45;
  const auto r = raster_mesh(g, cube, p, 0.5, 2);
  EXPECT_NEAR(raster_measure(g, r), 0.125, 0.125 * 0.03);
}

// Principal axis (largest second moment) of a 3D density about its centroid, by
// power iteration on the 3x3 covariance.
std::array<double, 3> principal_axis(const RasterGrid& g, const std::vector<float>& d) {
  double m = 0, c[3] = {0, 0, 0};
  auto pos = [&](int i, int a) {
    const int idx[3] = {i % g.n[0], (i / g.n[0]) % g.n[1], i / (g.n[0] * g.n[1])};
    return (idx[a] + 0.5) * g.cell_size_m;
  };
  for (int i = 0; i < int(d.size()); ++i) {
    m += d[i];
    for (int a = 0; a < 3; ++a) c[a] += d[i] * pos(i, a);
  }
  for (double& x : c) x /= m;
  double C[3][3] = {};
  for (int i = 0; i < int(d.size()); ++i)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) C[a][b] += d[i] * (pos(i, a) - c[a]) * (pos(i, b) - c[b]);
  std::array<double, 3> v{0.3, 0.5, 0.7};
  for (int it = 0; it < 200; ++it) {
    std::array<double, 3> w{};
    for (int a = 0; a < 3; ++a) w[a] = C[a][0] * v[0] + C[a][1] * v[1] + C[a][2] * v[2];
    const double n = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    for (int a = 0; a < 3; ++a) v[a] = w[a] / n;
  }
  return v;
}

// A mesh placed with rotation_deg about an arbitrary rotation_axis turns as asked: a
// 3:1:1 box (long along x) voxelised with a rotation has its principal axis at R x, and
// its volume is unchanged. The default axis (+z) keeps the 2D / z-only behaviour.
TEST(KeyframeRaster, MeshRotatesAboutAnyAxis) {
  TriangleMesh rod = unit_cube_mesh();
  for (auto& v : rod.vertices) v[0] *= 3.0;  // long along x
  RasterGrid g;
  g.dim = 3;
  g.n = {32, 32, 32};
  g.cell_size_m = 1.0 / 32;
  Placement p;
  p.center_m = {0.5, 0.5, 0.5};
  const double size = 0.75, volume = size * (size / 3) * (size / 3);
  struct Case {
    std::array<double, 3> axis;
    double deg;
  };
  for (const Case& k : {Case{{0, 0, 1}, 0}, Case{{0, 1, 0}, 90}, Case{{0, 0, 1}, 90}, Case{{1, 1, 0}, 90},
                        Case{{1, 2, 3}, 50}}) {
    p.rotation_axis = k.axis;
    p.rotation_deg = k.deg;
    const Rotation3 R = placement_rotation(p);
    // R is orthonormal with determinant 1 and leaves its axis fixed.
    const double n = std::sqrt(k.axis[0] * k.axis[0] + k.axis[1] * k.axis[1] + k.axis[2] * k.axis[2]);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(R[a][0] * k.axis[0] + R[a][1] * k.axis[1] + R[a][2] * k.axis[2], k.axis[a], 1e-12 * n);
    const auto d = raster_mesh(g, rod, p, size, 2);
    EXPECT_NEAR(raster_measure(g, d), volume, 0.05 * volume) << "axis " << k.axis[0] << k.axis[1] << k.axis[2];
    const auto v = principal_axis(g, d);
    const std::array<double, 3> expected{R[0][0], R[1][0], R[2][0]};  // R e_x
    const double cosang = std::abs(v[0] * expected[0] + v[1] * expected[1] + v[2] * expected[2]);
    EXPECT_GT(cosang, std::cos(3.0 * std::numbers::pi / 180)) << "deg " << k.deg << " axis " << k.axis[0] << ","
                                                              << k.axis[1] << "," << k.axis[2];
  }
  // Rotating about y by 90 degrees puts the long axis on z (a direct check of the sense).
  p.rotation_axis = {0, 1, 0};
  p.rotation_deg = 90;
  const auto v = principal_axis(g, raster_mesh(g, rod, p, size, 2));
  EXPECT_GT(std::abs(v[2]), 0.999);
  // The same rotation of an analytic box agrees with the voxelised mesh.
  const auto box = raster_box(g, p, {size / 2, size / 6, size / 6}, 2);
  const auto vb = principal_axis(g, box);
  EXPECT_GT(std::abs(vb[2]), 0.999);
  p.rotation_axis = {0, 0, 0};
  EXPECT_THROW(placement_rotation(p), GeomError);
}

TEST(KeyframeRaster, MeshFileThroughAssimp) {
  // An OBJ cube written here, loaded through assimp.
  const auto file = std::filesystem::temp_directory_path() / "pliant_geom_cube.obj";
  {
    FILE* f = std::fopen(file.string().c_str(), "w");
    ASSERT_TRUE(f);
    const TriangleMesh c = unit_cube_mesh();
    for (const auto& v : c.vertices) std::fprintf(f, "v %g %g %g\n", v[0], v[1], v[2]);
    for (const auto& t : c.triangles) std::fprintf(f, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    std::fclose(f);
  }
  const TriangleMesh m = load_mesh(file, "cube.obj");
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_NEAR(std::abs(m.signed_volume()), 1.0, 1e-9);
  std::filesystem::remove(file);
  try {
    load_mesh("/nonexistent/bunny.ply", "assets/meshes/bunny.ply");
    FAIL();
  } catch (const GeomError& e) {
    EXPECT_NE(std::string(e.what()).find("assets/meshes/bunny.ply: cannot load mesh"), std::string::npos);
  }
}

}  // namespace
}  // namespace pliant::geom
