// `pliant info`, `pliant export --format png` and `pliant plugins` on real takes.
#include <stb/stb_image.h>

#include "cli_fixture.h"

namespace pliant::test {
namespace {

class TakeTools : public CliTest {
 protected:
  // A finished 2D take of `frames` frames (frames + 1 records: 0..frames).
  fs::path make_take(int nx, int ny, int frames) {
    const fs::path scene = write_scene("scene.json", smoke_scene(nx, ny, frames));
    const fs::path take_dir = dir_ / "take";
    const ProcessResult r =
        pliant({"run", scene.string(), "--take", take_dir.string(), "--threads", "1"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return take_dir;
  }
};

TEST_F(TakeTools, InfoReportsStatusFieldsAndTornTail) {
  const fs::path take_dir = make_take(16, 20, 8);
  const size_t frames = TakeReader(take_dir).frame_count();

  ProcessResult r = pliant({"info", take_dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "status:   done")) << r.out;
  EXPECT_TRUE(contains(r.out, "kind:     smoke")) << r.out;
  EXPECT_TRUE(contains(r.out, "density [20x16] f32")) << r.out;
  EXPECT_TRUE(contains(r.out, "torn tail: none")) << r.out;

  // Simulate a write cut short by a crash: 17 stray bytes after the last record.
  {
    std::ofstream f(take_dir / "frames.bin", std::ios::binary | std::ios::app);
    f << "PLFR-torn-record!";
  }
  r = pliant({"info", take_dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "torn tail: dropped 17 bytes")) << r.out;

  r = pliant({"info", "--json", take_dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["status"], "done");
  EXPECT_EQ(j["torn_tail"], true);
  EXPECT_EQ(j["torn_tail_bytes"], 17);
  EXPECT_EQ(j["frames_readable"], frames);
  EXPECT_EQ(j["records"]["frame"], frames);
  EXPECT_EQ(j["frame_fields"][0]["name"], "density");
  EXPECT_EQ(j["frame_fields"][0]["shape"], nlohmann::json({20, 16}));
  EXPECT_EQ(j["good_bytes"].get<uint64_t>() + 17, fs::file_size(take_dir / "frames.bin"));
}

TEST_F(TakeTools, InfoOnMissingTakeIsInvalidInput) {
  const ProcessResult r = pliant({"info", (dir_ / "nothing").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "take.json")) << r.err;
}

TEST_F(TakeTools, ExportPngWritesOnePngPerFrame) {
  const fs::path take_dir = make_take(16, 20, 6);
  TakeReader take(take_dir);
  const fs::path out = dir_ / "pngs";
  const ProcessResult r =
      pliant({"export", take_dir.string(), "--format", "png", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto events = parse_json_lines(r.out);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back()["event"], "done");
  EXPECT_EQ(events.back()["metrics"]["frames"], take.frame_count());

  size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(out)) pngs += e.path().extension() == ".png";
  EXPECT_EQ(pngs, take.frame_count());
  // The last image is the last frame's density (2D: grey = 255 clamp(d), +y up).
  const Record last = take.read_frame_at(take.frame_count() - 1);
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05d.png", last.index);
  int w = 0, h = 0, c = 0;
  unsigned char* px = stbi_load((out / name).c_str(), &w, &h, &c, 1);
  ASSERT_NE(px, nullptr) << name;
  ASSERT_EQ(w, 16);
  ASSERT_EQ(h, 20);
  const Field* d = last.find("density");
  int mismatches = 0;
  for (int row = 0; row < h; ++row) {
    for (int x = 0; x < w; ++x) {
      const double v = std::clamp(double(d->data[(h - 1 - row) * w + x]), 0.0, 1.0);
      mismatches += px[row * w + x] != std::lround(255 * v);
    }
  }
  stbi_image_free(px);
  EXPECT_EQ(mismatches, 0);
}

// `pliant export --format csv` on a hand-written take: small fixed-shape fields become
// columns (flattened slowest index first), a field whose shape changes between frames
// and one over 256 values are left out and named in a warning, a frame missing a field
// leaves its cells empty, and the values are the take's.
TEST_F(TakeTools, ExportCsvTabulatesEveryFramesSmallFields) {
  const fs::path take_dir = dir_ / "synthetic";
  Manifest m;
  m.kind = "articulated";
  TakeWriter w = TakeWriter::create(take_dir, m);
  for (int i = 0; i < 5; ++i) {
    Record r;
    r.index = i;
    r.time_s = 0.25 * i;
    r.fields.push_back({"energy", {3}, {float(i), 2.5f, float(i) + 2.5f}});
    r.fields.push_back({"pose", {2, 2}, {1.f * i, 2.f, 3.f, -0.125f * i}});
    r.fields.push_back({"contacts", {uint32_t(i % 2), 6}, std::vector<float>(6 * (i % 2), 1.f)});
    r.fields.push_back({"image", {300}, std::vector<float>(300, 0.5f)});
    if (i != 3) r.fields.push_back({"speed", {}, {0.5f * i}});
    w.append(r);
  }
  w.finish("done");

  const fs::path out = dir_ / "csv";
  const ProcessResult r = pliant({"export", take_dir.string(), "--format", "csv", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "csv: left out contacts [0x6], then [1x6] in frame 1")) << r.out;
  EXPECT_TRUE(contains(r.out, "image [300] in frame 0: over 256 values")) << r.out;
  std::ifstream in(out / "frames.csv");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0], "frame,time_s,energy[0],energy[1],energy[2],pose[0][0],pose[0][1],pose[1][0],pose[1][1],speed");
  EXPECT_EQ(lines[1], "0,0,0,2.5,2.5,0,2,3,0,0");  // -0.125 * 0 is written as 0, not -0
  EXPECT_EQ(lines[3], "2,0.5,2,2.5,4.5,2,2,3,-0.25,1");
  EXPECT_EQ(lines[4], "3,0.75,3,2.5,5.5,3,2,3,-0.375,");  // frame 3 has no speed
  EXPECT_FALSE(fs::exists(out / "frames.csv.tmp"));
}

// A take of nothing but large fields (a smoke take's density and velocity) has nothing
// to tabulate: the export fails naming the fields and writes no table.
TEST_F(TakeTools, ExportCsvOfOnlyLargeFieldsFailsNamingThem) {
  const fs::path take_dir = make_take(20, 20, 2);
  const fs::path out = dir_ / "csv";
  const ProcessResult r = pliant({"export", take_dir.string(), "--format", "csv", "--out", out.string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "density [20x20] in frame 0: over 256 values")) << r.err;
  EXPECT_FALSE(fs::exists(out / "frames.csv"));
}

TEST_F(TakeTools, ExportUnknownFormatListsAvailable) {
  const fs::path take_dir = make_take(8, 8, 2);
  const ProcessResult r =
      pliant({"export", take_dir.string(), "--format", "gif", "--out", (dir_ / "o").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "\"gif\"")) << r.err;
  EXPECT_TRUE(contains(r.err, "png")) << r.err;
}

TEST_F(TakeTools, PluginsListsPngAndReportsBrokenPluginsInPath) {
  const fs::path extra = dir_ / "extra_plugins";
  fs::create_directories(extra);
  std::ofstream(extra / "broken.so") << "not a library";
  const ProcessResult r = pliant({"plugins", "--json"}, {"PLIANT_PLUGIN_PATH=" + extra.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  bool png = false;
  for (const auto& p : j["plugins"])
    for (const auto& e : p["exporters"]) png |= e["name"] == "png";
  EXPECT_TRUE(png) << r.out;
  ASSERT_EQ(j["failures"].size(), 1u) << r.out;
  EXPECT_TRUE(contains(j["failures"][0]["reason"], "broken.so")) << r.out;

  const ProcessResult text = pliant({"plugins"}, {"PLIANT_PLUGIN_PATH=" + extra.string()});
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_TRUE(contains(text.out, "exporter png")) << text.out;
  EXPECT_TRUE(contains(text.out, "broken.so")) << text.out;
}

}  // namespace
}  // namespace pliant::test
