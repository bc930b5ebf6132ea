// `pliant info TAKE [--json]`: what a take holds (manifest, record counts,
// frame fields) and whether a torn tail (crash or kill -9) was dropped.
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>

#include "commands.h"
#include "pliant/core/take.h"

namespace pliant::cli {
namespace {

struct InfoOptions {
  std::filesystem::path take;
  bool json = false;
};

const char* kind_name(RecordKind k) {
  switch (k) {
    case RecordKind::Frame: return "frame";
    case RecordKind::Preview: return "preview";
    case RecordKind::Checkpoint: return "checkpoint";
  }
  return "unknown";
}

nlohmann::json describe(const TakeReader& take) {
  const Manifest& m = take.manifest();
  nlohmann::json counts = {{"frame", 0}, {"preview", 0}, {"checkpoint", 0}};
  for (size_t i = 0; i < take.record_count(); ++i) {
    counts[kind_name(take.record_kind(i))] = counts.value(kind_name(take.record_kind(i)), 0) + 1;
  }
  nlohmann::json fields = nlohmann::json::array();
  if (take.frame_count() > 0) {
    const Record first = take.read_frame_at(0);
    for (const Field& f : first.fields) fields.push_back({{"name", f.name}, {"shape", f.shape}});
  }
  std::error_code ec;
  const auto size = std::filesystem::file_size(take.dir() / "frames.bin", ec);
  const uint64_t file_bytes = ec ? 0 : uint64_t(size);
  const uint64_t dropped = file_bytes > take.good_bytes() ? file_bytes - take.good_bytes() : 0;
  return {{"take", take.dir().string()},
          {"status", m.status},
          {"kind", m.kind},
          {"scene", m.scene_file},
          {"engine_version", m.engine_version},
          {"frames_written", m.frames_written},
          {"frames_expected", m.frames_expected},
          {"frames_readable", take.frame_count()},
          {"progress", m.progress},
          {"metrics", m.metrics},
          {"error", m.error},
          {"records", counts},
          {"frame_fields", fields},
          {"good_bytes", take.good_bytes()},
          {"torn_tail", take.torn_tail()},
          {"torn_tail_bytes", dropped}};
}

void print_text(const nlohmann::json& j) {
  auto s = [&](const char* key) { return j[key].get<std::string>(); };
  std::printf("take:     %s\n", s("take").c_str());
  std::printf("status:   %s\n", s("status").c_str());
  std::printf("kind:     %s\n", s("kind").c_str());
  std::printf("scene:    %s\n", s("scene").c_str());
  std::printf("engine:   %s\n", s("engine_version").c_str());
  std::printf("frames:   %d written, %d expected, %zu readable\n", j["frames_written"].get<int>(),
              j["frames_expected"].get<int>(), j["frames_readable"].get<size_t>());
  if (!j["progress"].empty()) std::printf("progress: %s\n", j["progress"].dump().c_str());
  if (!j["metrics"].empty()) std::printf("metrics:  %s\n", j["metrics"].dump().c_str());
  if (!s("error").empty()) std::printf("error:    %s\n", s("error").c_str());
  const auto& c = j["records"];
  std::printf("records:  %d frame, %d preview, %d checkpoint\n", c["frame"].get<int>(),
              c["preview"].get<int>(), c["checkpoint"].get<int>());
  for (const auto& f : j["frame_fields"]) {
    std::string shape;
    for (const auto& n : f["shape"]) {
      if (!shape.empty()) shape += 'x';
      shape += std::to_string(n.get<uint32_t>());
    }
    std::printf("field:    %s [%s] f32\n", f["name"].get<std::string>().c_str(), shape.c_str());
  }
  if (j["torn_tail"].get<bool>()) {
    std::printf("torn tail: dropped %llu bytes after %llu good bytes\n",
                (unsigned long long)j["torn_tail_bytes"].get<uint64_t>(),
                (unsigned long long)j["good_bytes"].get<uint64_t>());
  } else {
    std::printf("torn tail: none\n");
  }
}

int info(const InfoOptions& o) {
  const TakeReader take(o.take);  // throws InputError when take.json is missing/bad
  const nlohmann::json j = describe(take);
  if (o.json) {
    std::printf("%s\n", j.dump().c_str());
  } else {
    print_text(j);
  }
  return 0;
}

}  // namespace

void add_info_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<InfoOptions>();
  CLI::App* sub = app.add_subcommand(
      "info", "Describe a take: manifest, record counts, frame fields, torn tail");
  sub->add_option("take", opt->take, "Take directory")->required();
  sub->add_flag("--json", opt->json, "One JSON object on stdout instead of text");
  sub->callback([opt, &action] { action = [opt] { return info(*opt); }; });
}

}  // namespace pliant::cli
