// A scene: the JSON document a job runs (ARCHITECTURE.md, "The one path").
// load_scene checks the envelope ("pliant": 1, "kind", "name"); the kind's own
// compile step (e.g. smoke::smoke_compile) validates the rest with JsonReader.
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pliant {

class JsonReader;

inline constexpr int kSceneSchemaVersion = 1;

struct Scene {
  std::string file;               // as given by the user; used in messages
  std::filesystem::path dir;      // asset paths are relative to this (the file's folder,
                                  // or the optional top-level "asset_dir")
  std::string kind;               // "smoke", "liquid", "soft", "articulated"
  std::string name;               // optional display name
  nlohmann::json doc;             // the whole document

  std::filesystem::path asset_path(const std::string& relative) const;
};

// Known kinds (even those whose job is not implemented yet).
const std::vector<std::string>& scene_kinds();

// Throws InputError (unreadable file, JSON syntax error with line/column,
// wrong schema version, unknown kind).
Scene load_scene(const std::filesystem::path& path);
Scene parse_scene(const std::string& text, const std::string& file_label,
                  const std::filesystem::path& dir = ".");

// Marks the envelope fields load_scene checked ("pliant", "kind", "name", "asset_dir") as known
// on a kind's root reader, so its finish() rejects only the kind's own unknown keys.
void accept_scene_envelope(JsonReader& root);

// Writes pretty JSON atomically (temp file, fsync, rename).
void save_json_atomic(const std::filesystem::path& path, const nlohmann::json& doc);

}  // namespace pliant
