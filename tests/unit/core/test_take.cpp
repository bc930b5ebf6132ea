#include "pliant/core/take.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <thread>

#include "pliant/core/crc32.h"
#include "pliant/core/error.h"
#include "temp_dir.h"

namespace pliant {
namespace {

using test::read_bytes;
using test::TempDir;
using test::write_text;

// A frame of an 8x8 density (and optionally a 2x4x4 velocity) with distinct values.
Record make_frame(int index, bool with_velocity = false, RecordKind kind = RecordKind::Frame) {
  Record r;
  r.kind = kind;
  r.index = index;
  r.time_s = 0.02 * index;
  Field d{"density", {8, 8}, std::vector<float>(64)};
  for (int i = 0; i < 64; ++i) d.data[i] = 0.5f * i + 100.0f * index - 7.25f;
  r.fields.push_back(d);
  if (with_velocity) {
    Field v{"velocity", {2, 4, 4}, std::vector<float>(32)};
    for (int i = 0; i < 32; ++i) v.data[i] = std::ldexp(1.0f, i % 20) * (i % 3 == 0 ? -1.f : 1.f);
    r.fields.push_back(v);
  }
  return r;
}

void expect_same(const Record& a, const Record& b) {
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(std::memcmp(&a.time_s, &b.time_s, sizeof(double)), 0);
  ASSERT_EQ(a.fields.size(), b.fields.size());
  for (size_t f = 0; f < a.fields.size(); ++f) {
    EXPECT_EQ(a.fields[f].name, b.fields[f].name);
    EXPECT_EQ(a.fields[f].shape, b.fields[f].shape);
    ASSERT_EQ(a.fields[f].data.size(), b.fields[f].data.size());
    EXPECT_EQ(std::memcmp(a.fields[f].data.data(), b.fields[f].data.data(), 4 * a.fields[f].data.size()), 0);
  }
}

Manifest test_manifest() {
  Manifest m;
  m.kind = "smoke";
  m.scene_file = "scenes/a.json";
  m.scene = {{"pliant", 1}, {"kind", "smoke"}};
  m.frames_expected = 3;
  return m;
}

void append_raw(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary | std::ios::app) << bytes;
}

TEST(Take, RecordLayoutMatchesTheHeaderComment) {
  Record r = make_frame(5);
  std::vector<uint8_t> b = encode_record(r);
  ASSERT_EQ(b.size(), kRecordHeaderSize + 4 + (2 + 7 + 2 + 8) + 64 * 4);
  uint32_t magic, payload_crc, header_crc;
  uint16_t version, kind;
  int32_t index;
  uint64_t payload_size;
  std::memcpy(&magic, &b[0], 4);
  std::memcpy(&version, &b[4], 2);
  std::memcpy(&kind, &b[6], 2);
  std::memcpy(&index, &b[8], 4);
  std::memcpy(&payload_size, &b[24], 8);
  std::memcpy(&payload_crc, &b[32], 4);
  std::memcpy(&header_crc, &b[36], 4);
  EXPECT_EQ(magic, 0x52464c50u);
  EXPECT_EQ(std::string(b.begin(), b.begin() + 4), "PLFR");
  EXPECT_EQ(version, 1);
  EXPECT_EQ(kind, 1);
  EXPECT_EQ(index, 5);
  EXPECT_EQ(payload_size, b.size() - kRecordHeaderSize);
  EXPECT_EQ(payload_crc, crc32(b.data() + 40, b.size() - 40));
  EXPECT_EQ(header_crc, crc32(b.data(), 36));
  EXPECT_EQ(b[40 + 4 + 2 + 7], 1);  // dtype f32
  EXPECT_EQ(b[40 + 4 + 2 + 7 + 1], 2);  // ndim
}

TEST(Take, EncodeRejectsInconsistentFields) {
  Record r;
  r.fields.push_back(Field{"density", {8, 8}, std::vector<float>(63)});
  EXPECT_THROW(encode_record(r), std::invalid_argument);
  r.fields[0] = Field{"d", std::vector<uint32_t>(9, 1), std::vector<float>(1)};
  EXPECT_THROW(encode_record(r), std::invalid_argument);
}

TEST(Take, DecodeRecordsRoundTrip) {
  std::vector<uint8_t> bytes;
  std::vector<Record> in = {make_frame(0, true), make_frame(1), make_frame(7, true, RecordKind::Checkpoint)};
  in.push_back(Record{RecordKind::Preview, -2, 1.5, {}});  // no fields at all
  for (const auto& r : in) {
    auto b = encode_record(r);
    bytes.insert(bytes.end(), b.begin(), b.end());
  }
  bool torn = true;
  uint64_t good = 0;
  auto out = decode_records(bytes.data(), bytes.size(), &torn, &good);
  EXPECT_FALSE(torn);
  EXPECT_EQ(good, bytes.size());
  ASSERT_EQ(out.size(), in.size());
  for (size_t i = 0; i < in.size(); ++i) expect_same(in[i], out[i]);
  ASSERT_NE(out[0].find("velocity"), nullptr);
  EXPECT_EQ(out[0].find("velocity")->shape, (std::vector<uint32_t>{2, 4, 4}));
  EXPECT_EQ(out[1].find("velocity"), nullptr);
}

TEST(Take, WriterReaderRoundTrip) {
  TempDir dir;
  const auto take_dir = dir / "take";
  {
    TakeWriter w = TakeWriter::create(take_dir, test_manifest());
    for (int i = 0; i < 3; ++i) w.append(make_frame(i, true));
    w.append(make_frame(2, false, RecordKind::Checkpoint));
    w.manifest().metrics = {{"max_divergence", 1e-7}};
    w.finish("done");
  }
  TakeReader r(take_dir);
  EXPECT_EQ(r.manifest().status, "done");
  EXPECT_EQ(r.manifest().kind, "smoke");
  EXPECT_EQ(r.manifest().scene_file, "scenes/a.json");
  EXPECT_EQ(r.manifest().frames_written, 3);
  EXPECT_EQ(r.manifest().frames_expected, 3);
  EXPECT_EQ(r.manifest().engine_version, "0.1.0");
  EXPECT_DOUBLE_EQ(r.manifest().metrics["max_divergence"].get<double>(), 1e-7);
  EXPECT_GT(r.manifest().started_unix_s, 1.6e9);
  EXPECT_GE(r.manifest().updated_unix_s, r.manifest().started_unix_s);
  EXPECT_EQ(r.record_count(), 4u);
  EXPECT_EQ(r.frame_count(), 3u);
  EXPECT_FALSE(r.torn_tail());
  for (int i = 0; i < 3; ++i) expect_same(r.read_frame_at(i), make_frame(i, true));
  Record cp;
  ASSERT_TRUE(r.latest(RecordKind::Checkpoint, &cp));
  expect_same(cp, make_frame(2, false, RecordKind::Checkpoint));
  EXPECT_FALSE(r.latest(RecordKind::Preview, nullptr));
  EXPECT_EQ(r.record_kind(3), RecordKind::Checkpoint);
  EXPECT_EQ(r.record_index(1), 1);
  EXPECT_THROW(r.read_frame_at(3), std::out_of_range);
}

TEST(Take, ManifestWritesAreAtomicAndRoundTrip) {
  TempDir dir;
  TakeWriter w = TakeWriter::create(dir.path(), test_manifest());
  w.manifest().progress = {{"stage", "simulate"}, {"iter", 2}};
  for (int i = 0; i < 5; ++i) w.write_manifest();
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"frames.bin", "take.json"}));
  Manifest m = Manifest::from_json(nlohmann::json::parse(read_bytes(dir / "take.json")));
  EXPECT_EQ(m.to_json(), w.manifest().to_json());
  EXPECT_EQ(m.progress["stage"], "simulate");
}

TEST(Take, ManifestErrorsNameTheFile) {
  TempDir dir;
  EXPECT_THROW(TakeReader{dir.path()}, InputError);
  write_text(dir / "take.json", R"({"schema": 1, "status": "finished"})");
  try {
    TakeReader r(dir.path());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "take.json").string());
    EXPECT_EQ(e.pointer(), "/status");
  }
  write_text(dir / "take.json", "{");
  EXPECT_THROW(TakeReader{dir.path()}, InputError);
  write_text(dir / "take.json", R"({"schema": 2})");
  try {
    TakeReader r(dir.path());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "take.json").string() + ": /schema: expected take schema version 1, got 2");
  }
}

TEST(Take, ReaderFollowsAGrowingFile) {
  TempDir dir;
  TakeWriter w = TakeWriter::create(dir.path(), test_manifest());
  TakeReader r(dir.path());
  EXPECT_EQ(r.frame_count(), 0u);
  EXPECT_EQ(r.refresh(), 0u);
  w.append(make_frame(0));
  EXPECT_EQ(r.refresh(), 1u);
  w.append(make_frame(1));
  w.append(make_frame(2));
  EXPECT_EQ(r.refresh(), 2u);
  EXPECT_EQ(r.refresh(), 0u);
  EXPECT_EQ(r.frame_count(), 3u);
  expect_same(r.read_frame_at(2), make_frame(2));

  // Half a record written: torn for now, picked up once complete.
  const auto bytes = encode_record(make_frame(3));
  const std::string all(bytes.begin(), bytes.end());
  append_raw(dir / "frames.bin", all.substr(0, 100));
  EXPECT_EQ(r.refresh(), 0u);
  EXPECT_TRUE(r.torn_tail());
  append_raw(dir / "frames.bin", all.substr(100));
  EXPECT_EQ(r.refresh(), 1u);
  EXPECT_FALSE(r.torn_tail());
  expect_same(r.read_frame_at(3), make_frame(3));
  w.finish("done");
  r.refresh();
  EXPECT_EQ(r.manifest().status, "done");
}

TEST(Take, ReopenTruncatesTornTailAndLatestFrameWins) {
  TempDir dir;
  {
    TakeWriter w = TakeWriter::create(dir.path(), test_manifest());
    w.append(make_frame(0));
    w.append(make_frame(1));
    w.finish("cancelled");
  }
  const uint64_t good = std::filesystem::file_size(dir / "frames.bin");
  const auto torn = encode_record(make_frame(2));
  append_raw(dir / "frames.bin", std::string(torn.begin(), torn.begin() + 57));
  {
    TakeReader r(dir.path());
    EXPECT_TRUE(r.torn_tail());
    EXPECT_EQ(r.good_bytes(), good);
  }
  TakeWriter w = TakeWriter::reopen(dir.path());
  EXPECT_EQ(std::filesystem::file_size(dir / "frames.bin"), good);
  EXPECT_EQ(w.manifest().status, "running");
  EXPECT_EQ(w.manifest().frames_written, 2);
  Record again = make_frame(1);
  again.fields[0].data[0] = 12345.f;
  w.append(again);  // frame 1 rewritten after resuming from an earlier checkpoint
  w.append(make_frame(2));
  w.finish("done");
  TakeReader r(dir.path());
  EXPECT_FALSE(r.torn_tail());
  EXPECT_EQ(r.record_count(), 4u);
  ASSERT_EQ(r.frame_count(), 3u);
  expect_same(r.read_frame_at(0), make_frame(0));
  expect_same(r.read_frame_at(1), again);
  expect_same(r.read_frame_at(2), make_frame(2));
  EXPECT_EQ(r.manifest().status, "done");
}

TEST(Take, ReaderRestartsWhenFileShrinks) {
  TempDir dir;
  TakeWriter w = TakeWriter::create(dir.path(), test_manifest());
  w.append(make_frame(0));
  w.append(make_frame(1));
  TakeReader r(dir.path());
  EXPECT_EQ(r.frame_count(), 2u);
  TakeWriter fresh = TakeWriter::create(dir.path(), test_manifest());  // truncates
  fresh.append(make_frame(9));
  r.refresh();
  ASSERT_EQ(r.frame_count(), 1u);
  expect_same(r.read_frame_at(0), make_frame(9));
}

// The reader must survive frames.bin cut at any byte: exactly the complete
// records before the cut are seen, and the tail is torn unless the cut falls
// on a record boundary.
TEST(Take, SurvivesTruncationAtEveryByteOffset) {
  TempDir dir;
  const auto source = dir / "source";
  {
    TakeWriter w = TakeWriter::create(source, test_manifest());
    for (int i = 0; i < 3; ++i) w.append(make_frame(i));
    w.finish("done");
  }
  const std::string full = read_bytes(source / "frames.bin");
  const size_t record = encode_record(make_frame(0)).size();
  ASSERT_EQ(full.size(), 3 * record);
  const auto cut_dir = dir / "cut";
  std::filesystem::create_directories(cut_dir);
  std::filesystem::copy_file(source / "take.json", cut_dir / "take.json");
  for (size_t offset = 0; offset <= full.size(); ++offset) {
    write_text(cut_dir / "frames.bin", full.substr(0, offset));
    TakeReader r(cut_dir);
    r.refresh();
    const size_t complete = offset / record;
    ASSERT_EQ(r.frame_count(), complete) << "offset " << offset;
    ASSERT_EQ(r.torn_tail(), offset % record != 0) << "offset " << offset;
    ASSERT_EQ(r.good_bytes(), complete * record);
    for (size_t i = 0; i < complete; ++i) expect_same(r.read_frame_at(i), make_frame(static_cast<int>(i)));

    bool torn = false;
    auto decoded = decode_records(reinterpret_cast<const uint8_t*>(full.data()), offset, &torn);
    ASSERT_EQ(decoded.size(), complete);
    ASSERT_EQ(torn, offset % record != 0);
  }
}

// A flipped byte anywhere fails a CRC (or the magic/version check): that record
// and everything after it are dropped.
TEST(Take, SingleByteCorruptionDropsTheRecordAndTheRest) {
  std::vector<uint8_t> bytes;
  for (int i = 0; i < 3; ++i) {
    auto b = encode_record(make_frame(i, i == 1));
    bytes.insert(bytes.end(), b.begin(), b.end());
  }
  const size_t r0 = encode_record(make_frame(0)).size(), r1 = encode_record(make_frame(1, true)).size();
  for (size_t pos = 0; pos < bytes.size(); ++pos) {
    for (uint8_t mask : {uint8_t(0x01), uint8_t(0x80), uint8_t(0xFF)}) {
      auto bad = bytes;
      bad[pos] ^= mask;
      bool torn = false;
      uint64_t good = 0;
      auto out = decode_records(bad.data(), bad.size(), &torn, &good);
      const size_t expected = pos < r0 ? 0 : pos < r0 + r1 ? 1 : 2;
      ASSERT_EQ(out.size(), expected) << "byte " << pos;
      ASSERT_TRUE(torn);
      for (size_t i = 0; i < out.size(); ++i) expect_same(out[i], make_frame(static_cast<int>(i), i == 1));
    }
  }
  // The same through the reader, for a few positions.
  TempDir dir;
  { TakeWriter::create(dir.path(), test_manifest()); }
  for (size_t pos : {size_t(3), r0 + 37, r0 + r1 + 100, bytes.size() - 1}) {
    auto bad = bytes;
    bad[pos] ^= 0x10;
    write_text(dir / "frames.bin", std::string(bad.begin(), bad.end()));
    TakeReader r(dir.path());
    EXPECT_EQ(r.frame_count(), pos < r0 ? 0u : pos < r0 + r1 ? 1u : 2u);
    EXPECT_TRUE(r.torn_tail());
  }
}

TEST(Take, GarbageNeverCrashesOrOverAllocates) {
  std::mt19937 rng(1234);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<uint8_t> junk(rng() % 300);
    for (auto& b : junk) b = static_cast<uint8_t>(rng());
    bool torn = false;
    auto out = decode_records(junk.data(), junk.size(), &torn);
    EXPECT_TRUE(out.empty());
    EXPECT_EQ(torn, !junk.empty());
  }
  // A valid header claiming an enormous payload: rejected without allocating it.
  auto b = encode_record(make_frame(0));
  uint64_t huge = uint64_t(1) << 60;
  std::memcpy(&b[24], &huge, 8);
  uint32_t hcrc = crc32(b.data(), 36);
  std::memcpy(&b[36], &hcrc, 4);
  bool torn = false;
  EXPECT_TRUE(decode_records(b.data(), b.size(), &torn).empty());
  EXPECT_TRUE(torn);
}

TEST(Take, DiskFullIsAClearError) {
  TempDir dir;
  std::filesystem::create_symlink("/dev/full", dir / "frames.bin");
  TakeWriter w = TakeWriter::create(dir.path(), test_manifest());
  try {
    w.append(make_frame(0));
    ADD_FAILURE() << "append to /dev/full succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "frames.bin").string() + ": disk full while trying to write");
  }
  EXPECT_EQ(w.manifest().frames_written, 0);
}

}  // namespace
}  // namespace pliant

namespace pliant {
namespace {

// tests/fuzz/make_take_seeds.py writes frames.bin images with Python's struct
// and zlib: an independent implementation of the layout in take.h.
TEST(Take, DecodesFramesWrittenByAnIndependentEncoder) {
  const auto seeds = std::filesystem::path(PLIANT_TESTS_DIR) / "fuzz/corpus/take";
  const std::string bytes = test::read_bytes(seeds / "three_frames.bin");
  bool torn = true;
  auto records = decode_records(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), &torn);
  EXPECT_FALSE(torn);
  ASSERT_EQ(records.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(records[i].index, i);
    EXPECT_DOUBLE_EQ(records[i].time_s, 0.02 * i);
    const Field* d = records[i].find("density");
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(d->shape, (std::vector<uint32_t>{4, 4}));
    for (int k = 0; k < 16; ++k) EXPECT_EQ(d->data[k], float(i * 100 + k) * 0.25f);
    // ... and our encoder reproduces the Python bytes exactly.
    auto again = encode_record(records[i]);
    EXPECT_EQ(std::string(again.begin(), again.end()), bytes.substr(i * again.size(), again.size()));
  }
  const std::string torn_bytes = test::read_bytes(seeds / "torn_tail.bin");
  records = decode_records(reinterpret_cast<const uint8_t*>(torn_bytes.data()), torn_bytes.size(), &torn);
  EXPECT_TRUE(torn);
  EXPECT_EQ(records.size(), 2u);
}

}  // namespace
}  // namespace pliant

namespace pliant {
namespace {

// A writer thread appends while the reader polls (separate descriptors, as
// with the editor previewing a job): every indexed frame must decode intact.
TEST(Take, ReaderPollsWhileAnotherThreadWrites) {
  TempDir dir;
  TakeWriter w = TakeWriter::create(dir.path(), test_manifest());
  TakeReader r(dir.path());
  constexpr int kFrames = 40;
  std::thread writer([&] {
    for (int i = 0; i < kFrames; ++i) w.append(make_frame(i, true));
    w.finish("done");
  });
  size_t checked = 0;
  for (int polls = 0; polls < 100000 && checked < size_t(kFrames); ++polls) {
    r.refresh();
    for (; checked < r.frame_count(); ++checked)
      expect_same(r.read_frame_at(checked), make_frame(static_cast<int>(checked), true));
  }
  writer.join();
  r.refresh();
  ASSERT_EQ(r.frame_count(), size_t(kFrames));
  for (; checked < r.frame_count(); ++checked)
    expect_same(r.read_frame_at(checked), make_frame(static_cast<int>(checked), true));
  EXPECT_FALSE(r.torn_tail());
  EXPECT_EQ(r.manifest().status, "done");
}

}  // namespace
}  // namespace pliant
