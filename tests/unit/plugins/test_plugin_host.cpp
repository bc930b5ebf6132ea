// PluginHost: loading, refusing and surviving bad plugins; exporting a
// synthetic take through the png_sequence plugin and decoding the PNGs.
#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "pliant/core/error.h"
#include "pliant/core/plugin_host.h"
#include "pliant/core/progress.h"
#include "pliant/core/take.h"

namespace fs = std::filesystem;
using pliant::PluginHost;

namespace {

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("pliant_plugins_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

const pliant::PluginFailure* failure_for(const PluginHost& host, const fs::path& file) {
  for (const auto& f : host.failures()) {
    if (f.path.filename() == file.filename()) return &f;
  }
  return nullptr;
}

// Writes a take whose frames hold one "density" field of `shape` and returns its dir.
fs::path write_take(const fs::path& dir, const std::vector<uint32_t>& shape,
                    const std::vector<std::vector<float>>& frames, bool with_density = true) {
  pliant::Manifest m;
  m.kind = "smoke";
  m.frames_expected = int(frames.size());
  pliant::TakeWriter w = pliant::TakeWriter::create(dir, m);
  for (size_t i = 0; i < frames.size(); ++i) {
    pliant::Record r;
    r.index = int32_t(i);
    r.time_s = 0.02 * double(i);
    r.fields.push_back({with_density ? "density" : "smell", shape, frames[i]});
    w.append(r);
  }
  w.finish("done");
  return dir;
}

// Decodes a greyscale PNG; empty when it cannot be read.
std::vector<unsigned char> read_png(const fs::path& file, int* w, int* h) {
  int comp = 0;
  unsigned char* data = stbi_load(file.c_str(), w, h, &comp, 1);
  if (!data) return {};
  std::vector<unsigned char> out(data, data + size_t(*w) * size_t(*h));
  stbi_image_free(data);
  return out;
}

// The documented mapping of the png plugin: grey = round(255 clamp(v / scale)).
unsigned char expected_grey(double v, double scale) {
  if (std::isnan(v)) return 0;
  return static_cast<unsigned char>(std::lround(255.0 * std::clamp(v / scale, 0.0, 1.0)));
}

}  // namespace

TEST(PluginHost, LoadsPngPluginFromItsBuildFolder) {
  PluginHost host;
  host.load_folder(fs::path(PNG_PLUGIN_PATH).parent_path());
  ASSERT_TRUE(host.failures().empty()) << host.failures()[0].reason;
  // The folder holds every plugin of the build (png_sequence, openvdb_export when
  // OpenVDB is installed); the png one is among them with exactly its exporter.
  const size_t loaded = host.plugins().size();
  ASSERT_GE(loaded, 1u);
  const auto png_plugin =
      std::find_if(host.plugins().begin(), host.plugins().end(),
                   [](const auto& p) { return p.path.filename() == fs::path(PNG_PLUGIN_PATH).filename(); });
  ASSERT_NE(png_plugin, host.plugins().end());
  ASSERT_EQ(png_plugin->exporters, std::vector<std::string>{"png"});
  const pliant::Exporter* png = host.find_exporter("png");
  ASSERT_NE(png, nullptr);
  EXPECT_EQ(png->extension, ".png");
  EXPECT_FALSE(png->description.empty());
  EXPECT_EQ(host.find_exporter("no-such-format"), nullptr);
  // Loading the same library again is a no-op.
  EXPECT_TRUE(host.load_file(PNG_PLUGIN_PATH));
  EXPECT_EQ(host.plugins().size(), loaded);
}

TEST(PluginHost, RefusesWrongApiVersionNamingFileAndVersions) {
  PluginHost host;
  EXPECT_FALSE(host.load_file(BAD_VERSION_PLUGIN_PATH));  // its load would abort()
  ASSERT_EQ(host.failures().size(), 1u);
  const std::string& reason = host.failures()[0].reason;
  EXPECT_TRUE(contains(reason, fs::path(BAD_VERSION_PLUGIN_PATH).filename().string())) << reason;
  EXPECT_TRUE(contains(reason, "built for plugin API 99")) << reason;
  EXPECT_TRUE(contains(reason, "this Pliant has API 1")) << reason;
  EXPECT_TRUE(host.plugins().empty());
}

TEST(PluginHost, KeepsGoingAfterBrokenPlugins) {
  TempDir tmp;
  // Names chosen so the broken ones load first (folder order is by name).
  fs::copy_file(BAD_VERSION_PLUGIN_PATH, tmp.path() / "a_bad_version.so");
  fs::copy_file(FAILING_PLUGIN_PATH, tmp.path() / "b_failing.so");
  fs::copy_file(NO_LOAD_PLUGIN_PATH, tmp.path() / "c_no_load.so");
  std::ofstream(tmp.path() / "d_text.so") << "this is not a shared library\n";
  fs::copy_file(PNG_PLUGIN_PATH, tmp.path() / "e_png.so");
  std::ofstream(tmp.path() / "readme.txt") << "ignored: not a .so\n";

  PluginHost host;
  host.load_folder(tmp.path());
  ASSERT_EQ(host.failures().size(), 4u);
  ASSERT_EQ(host.plugins().size(), 1u);
  EXPECT_EQ(host.plugins()[0].path.filename(), "e_png.so");
  EXPECT_NE(host.find_exporter("png"), nullptr);

  const auto* failing = failure_for(host, "b_failing.so");
  ASSERT_NE(failing, nullptr);
  EXPECT_TRUE(contains(failing->reason, "returned 7")) << failing->reason;
  // What it registered before failing was dropped with it.
  EXPECT_EQ(host.find_exporter("half_loaded"), nullptr);
  EXPECT_EQ(host.exporters().size(), 1u);

  const auto* no_load = failure_for(host, "c_no_load.so");
  ASSERT_NE(no_load, nullptr);
  EXPECT_TRUE(contains(no_load->reason, "no pliant_plugin_load")) << no_load->reason;
  const auto* text = failure_for(host, "d_text.so");
  ASSERT_NE(text, nullptr);
  EXPECT_TRUE(contains(text->reason, "cannot load")) << text->reason;
  EXPECT_TRUE(contains(text->reason, "d_text.so")) << text->reason;
}

TEST(PluginHost, DefaultFoldersIncludeBinaryFolderAndEnvironment) {
  ::setenv("PLIANT_PLUGIN_PATH", "/tmp/pliant_a::/tmp/pliant_b", 1);
  const auto folders = PluginHost::default_folders();
  ::unsetenv("PLIANT_PLUGIN_PATH");
  ASSERT_EQ(folders.size(), 3u);
  EXPECT_EQ(folders[0].filename(), "plugins");
  EXPECT_EQ(folders[0].parent_path(), fs::read_symlink("/proc/self/exe").parent_path());
  EXPECT_EQ(folders[1], "/tmp/pliant_a");
  EXPECT_EQ(folders[2], "/tmp/pliant_b");
}

TEST(PngExport, TwoDimensionalFramesMatchDensityFlippedSoYIsUp) {
  TempDir tmp;
  const uint32_t ny = 5, nx = 7;
  std::vector<std::vector<float>> frames;
  for (int f = 0; f < 3; ++f) {
    std::vector<float> d(ny * nx);
    for (uint32_t j = 0; j < ny; ++j)
      for (uint32_t i = 0; i < nx; ++i) d[j * nx + i] = 0.1f * float(i + j + f) - 0.15f;
    frames.push_back(d);
  }
  frames[1][0] = std::numeric_limits<float>::quiet_NaN();
  frames[2][ny * nx - 1] = 5.0f;  // clamps to white
  pliant::TakeReader take(write_take(tmp.path() / "take", {ny, nx}, frames));

  PluginHost host;
  ASSERT_TRUE(host.load_file(PNG_PLUGIN_PATH));
  pliant::Progress progress;
  const fs::path out = tmp.path() / "out" / "pngs";  // parents are created
  ASSERT_EQ(pliant::export_take(take, *host.find_exporter("png"), out, &progress), 3);
  EXPECT_EQ(progress.last().stage, "export");
  EXPECT_EQ(progress.last().iter, 3);

  size_t files = std::distance(fs::directory_iterator(out), fs::directory_iterator());
  EXPECT_EQ(files, 3u);  // no temporaries left behind
  for (int f = 0; f < 3; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", f);
    int w = 0, h = 0;
    const auto px = read_png(out / name, &w, &h);
    ASSERT_EQ(w, int(nx)) << name;
    ASSERT_EQ(h, int(ny)) << name;
    for (uint32_t row = 0; row < ny; ++row) {
      for (uint32_t i = 0; i < nx; ++i) {
        const float v = frames[f][(ny - 1 - row) * nx + i];  // image row 0 is the top (+y)
        ASSERT_EQ(px[row * nx + i], expected_grey(v, 1.0)) << name << " row " << row << " x " << i;
      }
    }
  }
  // Anchors of the mapping: NaN and negative -> black, >= 1 -> white.
  int w = 0, h = 0;
  auto px1 = read_png(out / "frame_00001.png", &w, &h);
  EXPECT_EQ(px1[(ny - 1) * nx + 0], 0);  // NaN at cell (0,0), bottom-left
  auto px2 = read_png(out / "frame_00002.png", &w, &h);
  EXPECT_EQ(px2[0 * nx + nx - 1], 255);  // 5.0 at the top-right cell
}

TEST(PngExport, ThreeDimensionalFramesAreProjectedAlongZ) {
  TempDir tmp;
  const uint32_t nz = 8, ny = 3, nx = 4;  // scale = max(1, nz/4) = 2
  std::vector<float> d(nz * ny * nx);
  for (uint32_t k = 0; k < nz; ++k)
    for (uint32_t j = 0; j < ny; ++j)
      for (uint32_t i = 0; i < nx; ++i) d[(k * ny + j) * nx + i] = 0.02f * float(k + 2 * i + 3 * j);
  pliant::TakeReader take(write_take(tmp.path() / "take", {nz, ny, nx}, {d}));
  PluginHost host;
  ASSERT_TRUE(host.load_file(PNG_PLUGIN_PATH));
  ASSERT_EQ(pliant::export_take(take, *host.find_exporter("png"), tmp.path() / "out"), 1);
  int w = 0, h = 0;
  const auto px = read_png(tmp.path() / "out" / "frame_00000.png", &w, &h);
  ASSERT_EQ(w, int(nx));
  ASSERT_EQ(h, int(ny));
  for (uint32_t row = 0; row < ny; ++row) {
    for (uint32_t i = 0; i < nx; ++i) {
      const uint32_t j = ny - 1 - row;
      // Closed form of the sum over k of 0.02 (k + 2i + 3j).
      const double column = 0.02 * (nz * (nz - 1) / 2.0 + nz * (2.0 * i + 3.0 * j));
      EXPECT_NEAR(px[row * nx + i], expected_grey(column, 2.0), 1) << row << "," << i;
    }
  }
}

TEST(PngExport, ReportsFrameWithoutDensity) {
  TempDir tmp;
  pliant::TakeReader take(write_take(tmp.path() / "take", {2, 2}, {{0, 0, 0, 0}}, false));
  PluginHost host;
  ASSERT_TRUE(host.load_file(PNG_PLUGIN_PATH));
  try {
    pliant::export_take(take, *host.find_exporter("png"), tmp.path() / "out");
    FAIL() << "expected ExportError";
  } catch (const pliant::ExportError& e) {
    EXPECT_TRUE(contains(e.what(), "exporter \"png\"")) << e.what();
    EXPECT_TRUE(contains(e.what(), "frame 0")) << e.what();
    EXPECT_TRUE(contains(e.what(), "no \"density\" field")) << e.what();
  }
}

TEST(PngExport, ReportsOutputDirectoryThatCannotBeCreated) {
  TempDir tmp;
  pliant::TakeReader take(write_take(tmp.path() / "take", {2, 2}, {{0, 1, 0, 1}}));
  std::ofstream(tmp.path() / "file") << "a file, not a folder";
  PluginHost host;
  ASSERT_TRUE(host.load_file(PNG_PLUGIN_PATH));
  try {
    pliant::export_take(take, *host.find_exporter("png"), tmp.path() / "file" / "out");
    FAIL() << "expected ExportError";
  } catch (const pliant::ExportError& e) {
    EXPECT_TRUE(contains(e.what(), "cannot create directory")) << e.what();
    EXPECT_TRUE(contains(e.what(), (tmp.path() / "file" / "out").string())) << e.what();
  }
}

TEST(PngExport, StopsWhenCancelled) {
  TempDir tmp;
  pliant::TakeReader take(write_take(tmp.path() / "take", {2, 2}, {{0, 1, 0, 1}, {1, 0, 1, 0}}));
  PluginHost host;
  ASSERT_TRUE(host.load_file(PNG_PLUGIN_PATH));
  pliant::Progress progress;
  progress.cancel();
  EXPECT_THROW(pliant::export_take(take, *host.find_exporter("png"), tmp.path() / "out", &progress),
               pliant::CancelledError);
  EXPECT_FALSE(fs::exists(tmp.path() / "out" / "frame_00000.png"));
}
