// Scene envelope: schema version, kind, name (scene.h). The kind's compile
// step validates everything else.
#include "pliant/core/scene.h"

#include <cerrno>
#include <cstring>

#include "file_io.h"
#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"

namespace pliant {
namespace {

// nlohmann's parse_error text is "[json.exception.parse_error.101] parse error
// at line L, column C: DETAIL"; we keep DETAIL and compute line/column ourselves.
std::string parse_error_detail(const char* what) {
  std::string s = what;
  auto col = s.find("column ");
  if (col != std::string::npos) {
    auto colon = s.find(": ", col);
    if (colon != std::string::npos) return s.substr(colon + 2);
  }
  auto bracket = s.find("] ");
  return bracket == std::string::npos ? s : s.substr(bracket + 2);
}

void line_column(const std::string& text, size_t byte, size_t* line, size_t* column) {
  // nlohmann reports the 1-based byte count of the last character read.
  size_t end = std::min(byte == 0 ? 0 : byte - 1, text.size());
  *line = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < end; ++i)
    if (text[i] == '\n') {
      ++*line;
      line_start = i + 1;
    }
  *column = end - line_start + 1;
}

}  // namespace

std::filesystem::path Scene::asset_path(const std::string& relative) const {
  std::filesystem::path p(relative);
  return p.is_absolute() ? p : dir / p;
}

const std::vector<std::string>& scene_kinds() {
  static const std::vector<std::string> kinds = {"smoke", "liquid", "soft", "articulated"};
  return kinds;
}

Scene parse_scene(const std::string& text, const std::string& file_label,
                  const std::filesystem::path& dir) {
  Scene scene;
  scene.file = file_label;
  scene.dir = dir;
  try {
    scene.doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    size_t line = 0, column = 0;
    line_column(text, e.byte, &line, &column);
    throw InputError(file_label, "",
                     "invalid JSON at line " + std::to_string(line) + ", column " +
                         std::to_string(column) + ": " + parse_error_detail(e.what()));
  } catch (const nlohmann::json::exception& e) {
    // e.g. out_of_range.406 "number overflow parsing '2e308'", which has no position.
    throw InputError(file_label, "", "invalid JSON: " + parse_error_detail(e.what()));
  }
  if (!scene.doc.is_object()) throw InputError(file_label, "", "expected a JSON object at the top level");
  JsonReader r(scene.doc, file_label);
  if (!r.has("pliant")) r.fail("pliant", "missing required field; expected schema version 1");
  const auto& version = scene.doc.at("pliant");
  if (!version.is_number_integer() || version.get<long long>() != kSceneSchemaVersion)
    r.fail("pliant", "expected schema version 1, got " +
                         version.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  if (!r.has("kind")) r.fail("kind", "missing required field; expected one of \"smoke\", \"liquid\", \"soft\", \"articulated\"");
  scene.kind = r.choice("kind", "", scene_kinds());
  scene.name = r.string("name", "");
  // "asset_dir": where relative asset paths start when the document is a copy
  // saved elsewhere (the editor runs unsaved scenes from a copy beside the take).
  if (r.has("asset_dir")) {
    const std::filesystem::path a(r.string("asset_dir", ""));
    if (a.empty()) r.fail("asset_dir", "expected a folder path, got an empty string");
    scene.dir = a.is_absolute() ? a : dir / a;
  }
  return scene;
}

Scene load_scene(const std::filesystem::path& path) {
  std::string text;
  if (int err = detail::read_file_errno(path, &text); err != 0)
    throw InputError(path.string(), "", std::string("cannot read file: ") + std::strerror(err));
  std::filesystem::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  return parse_scene(text, path.string(), dir);
}

void save_json_atomic(const std::filesystem::path& path, const nlohmann::json& doc) {
  detail::write_file_atomic(path, doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

void accept_scene_envelope(JsonReader& root) {
  root.accept("pliant");
  root.accept("kind");
  root.accept("name");
  root.accept("asset_dir");
}

}  // namespace pliant
