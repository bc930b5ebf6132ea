// A take: the result of a job on disk (ARCHITECTURE.md). DIR/take.json is the
// manifest, replaced atomically; DIR/frames.bin holds append-only records:
//
//   header (40 bytes, little-endian):
//     u32 magic 0x52464c50 ("PLFR")   u16 format version (1)   u16 record kind
//     i32 index                       u32 reserved (0)
//     f64 time_s                      u64 payload size
//     u32 payload CRC32               u32 header CRC32 (of the first 36 bytes)
//   payload: u32 field count, then per field:
//     u16 name length, name bytes, u8 dtype (1 = f32), u8 ndim, u32 dims[ndim],
//     then prod(dims) values (dims slowest-first: 2D density is [ny, nx]).
//
// A reader stops at the first record that is short or fails a CRC (a torn
// tail after a crash or kill -9) and reports it; everything before it is good.
#pragma once
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace pliant {

enum class RecordKind : uint16_t { Frame = 1, Preview = 2, Checkpoint = 3 };

struct Field {
  std::string name;             // "density", "velocity", "force", ...
  std::vector<uint32_t> shape;  // slowest-first
  std::vector<float> data;      // size == product of shape
};

struct Record {
  RecordKind kind = RecordKind::Frame;
  int32_t index = 0;  // frame index (or iteration for checkpoints/previews)
  double time_s = 0;
  std::vector<Field> fields;
  const Field* find(std::string_view name) const;  // nullptr if absent
};

struct Manifest {
  int schema = 1;
  std::string kind;                 // scene kind
  std::string scene_file;           // path of the scene it came from
  nlohmann::json scene;             // copy of the scene document
  std::string engine_version;
  std::string status = "running";   // running | done | cancelled | failed
  nlohmann::json progress = nlohmann::json::object();  // last progress event
  nlohmann::json metrics = nlohmann::json::object();
  std::string error;                // message when failed
  int frames_expected = 0;          // for timelines
  int frames_written = 0;
  double started_unix_s = 0, updated_unix_s = 0;

  nlohmann::json to_json() const;
  static Manifest from_json(const nlohmann::json& j);  // throws InputError on bad shape
};

// Serialization of one record (header + payload); used by writer, reader, fuzzers.
std::vector<uint8_t> encode_record(const Record& r);
inline constexpr size_t kRecordHeaderSize = 40;

class TakeWriter {
 public:
  // Creates DIR (and parents), a fresh empty frames.bin and take.json (status running).
  static TakeWriter create(const std::filesystem::path& dir, Manifest manifest);
  // Reopens an existing take to continue it (--resume): truncates frames.bin to
  // its last good record, status back to running.
  static TakeWriter reopen(const std::filesystem::path& dir);
  TakeWriter(TakeWriter&&) noexcept;
  TakeWriter& operator=(TakeWriter&&) noexcept;
  ~TakeWriter();

  // One write() per record; frames_written is bumped for RecordKind::Frame.
  void append(const Record& r);
  // Atomic replace of take.json (temp, fsync, rename).
  void write_manifest();
  // Sets status (+ error), fsyncs frames.bin, writes the manifest.
  void finish(const std::string& status, const std::string& error = "");

  Manifest& manifest() { return manifest_; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  TakeWriter() = default;
  std::filesystem::path dir_;
  Manifest manifest_;
  int fd_ = -1;
};

// Reads a take, possibly while another process is writing it.
class TakeReader {
 public:
  // Throws InputError if DIR/take.json is missing or malformed.
  explicit TakeReader(const std::filesystem::path& dir);
  // Re-reads the manifest and indexes any new complete records. Returns the
  // number of new records. Cheap when nothing changed.
  size_t refresh();

  const Manifest& manifest() const { return manifest_; }
  size_t record_count() const { return index_.size(); }
  RecordKind record_kind(size_t i) const { return index_[i].kind; }
  int32_t record_index(size_t i) const { return index_[i].index; }
  Record read(size_t i) const;  // reads and decodes record i

  // Frames only (RecordKind::Frame), in file order; the latest record wins when
  // the same frame index was written twice (after --resume).
  size_t frame_count() const;
  Record read_frame_at(size_t n) const;  // n-th frame
  // Latest record of a kind (e.g. the last checkpoint); false if none.
  bool latest(RecordKind kind, Record* out) const;

  // True when bytes after the last good record exist (torn or corrupt tail).
  bool torn_tail() const { return torn_tail_; }
  uint64_t good_bytes() const { return good_bytes_; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  struct Entry {
    uint64_t offset, size;
    RecordKind kind;
    int32_t index;
    double time_s;
  };
  std::filesystem::path dir_;
  Manifest manifest_;
  std::vector<Entry> index_;
  std::vector<size_t> frames_;  // positions in index_ of the frames
  uint64_t good_bytes_ = 0;
  bool torn_tail_ = false;
  // take.json's text as last parsed: readers refresh every UI frame, and the
  // manifest (with its copy of the scene) is re-parsed only when it changed.
  std::string manifest_text_;
};

// Decodes a whole frames.bin image from memory (used by the reader and the fuzzer).
// Returns the records that decode; sets *torn when trailing bytes were dropped.
std::vector<Record> decode_records(const uint8_t* data, size_t size, bool* torn,
                                   uint64_t* good_bytes = nullptr);

}  // namespace pliant
