// libFuzzer target: decode_records on arbitrary bytes must not crash, must
// account for every byte (good + torn tail), and must round-trip: encoding the
// decoded records gives back exactly the good prefix. The same bytes as a
// frames.bin on disk must index identically through TakeReader.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "pliant/core/take.h"

namespace {

// One take folder per fuzzing process, removed at exit.
struct FuzzTake {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("pliant-fuzz-take-" + std::to_string(::getpid()));
  FuzzTake() {
    std::filesystem::remove_all(dir);
    pliant::Manifest m;
    m.kind = "smoke";
    pliant::TakeWriter::create(dir, m);
  }
  ~FuzzTake() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

const std::filesystem::path& take_dir() {
  static FuzzTake take;
  return take.dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bool torn = false;
  uint64_t good = 0;
  std::vector<pliant::Record> records = pliant::decode_records(data, size, &torn, &good);
  if (good > size || torn != (good < size)) __builtin_trap();

  std::vector<uint8_t> again;
  for (const auto& r : records) {
    auto b = pliant::encode_record(r);
    again.insert(again.end(), b.begin(), b.end());
  }
  if (again.size() != good || (good && std::memcmp(again.data(), data, good) != 0)) __builtin_trap();

  // The on-disk path costs file I/O: check it on every 8th input (always on
  // the first, so replaying one crash input runs it).
  static unsigned calls = 0;
  if (calls++ % 8 != 0) return 0;
  {
    std::ofstream out(take_dir() / "frames.bin", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  pliant::TakeReader reader(take_dir());
  if (reader.record_count() != records.size() || reader.torn_tail() != torn || reader.good_bytes() != good)
    __builtin_trap();
  for (size_t i = 0; i < reader.record_count(); ++i) {
    pliant::Record r = reader.read(i);
    if (r.index != records[i].index || r.fields.size() != records[i].fields.size()) __builtin_trap();
  }
  if (reader.frame_count() > 0) (void)reader.read_frame_at(reader.frame_count() - 1);
  return 0;
}
