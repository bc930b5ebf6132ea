// take.json <-> Manifest. Reading is lenient about unknown keys so that a
// newer engine's takes still open in an older editor.
#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"
#include "pliant/core/take.h"

namespace pliant {

nlohmann::json Manifest::to_json() const {
  return nlohmann::json{{"schema", schema},
                        {"kind", kind},
                        {"scene_file", scene_file},
                        {"scene", scene},
                        {"engine_version", engine_version},
                        {"status", status},
                        {"progress", progress},
                        {"metrics", metrics},
                        {"error", error},
                        {"frames_expected", frames_expected},
                        {"frames_written", frames_written},
                        {"started_unix_s", started_unix_s},
                        {"updated_unix_s", updated_unix_s}};
}

Manifest Manifest::from_json(const nlohmann::json& j) {
  JsonReader r(j, "take.json");
  Manifest m;
  if (!r.has("schema")) r.fail("schema", "missing required field; expected take schema version 1");
  r.accept("schema");
  if (j.at("schema") != 1)
    r.fail("schema", "expected take schema version 1, got " +
                         j.at("schema").dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  m.schema = 1;
  m.kind = r.string("kind", "");
  m.scene_file = r.string("scene_file", "");
  if (r.has("scene")) m.scene = j.at("scene");
  m.engine_version = r.string("engine_version", "");
  m.status = r.choice("status", "running", {"running", "done", "cancelled", "failed"});
  if (auto p = r.object("progress")) m.progress = p->value();
  if (auto p = r.object("metrics")) m.metrics = p->value();
  m.error = r.string("error", "");
  m.frames_expected = static_cast<int>(r.integer("frames_expected", 0, 0, 1 << 30));
  m.frames_written = static_cast<int>(r.integer("frames_written", 0, 0, 1 << 30));
  m.started_unix_s = r.number("started_unix_s", 0);
  m.updated_unix_s = r.number("updated_unix_s", 0);
  return m;
}

}  // namespace pliant
