// Parsing and expanding sweep files (sweep_plan.h).
#include "sweep_plan.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"
#include "pliant/core/scene.h"

namespace pliant::cli {
namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxRuns = 1000000;

nlohmann::json read_json_file(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "", "cannot read the sweep file");
  std::stringstream text;
  text << in.rdbuf();
  try {
    return nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(file.string(), "", std::string("invalid JSON: ") + e.what());
  }
}

}  // namespace

size_t SweepPlan::run_count() const {
  size_t n = 1;
  for (const auto& p : parameters) n *= p.values.size();
  return n;
}

std::string SweepPlan::run_name(size_t k) const {
  char buf[32];
  std::snprintf(buf, sizeof buf, "run_%04zu", k);
  return buf;
}

nlohmann::json SweepPlan::run_values(size_t k) const {
  // Mixed-radix digits of k, the last parameter least significant.
  std::vector<size_t> digit(parameters.size());
  for (size_t i = parameters.size(); i-- > 0;) {
    digit[i] = k % parameters[i].values.size();
    k /= parameters[i].values.size();
  }
  nlohmann::json values = nlohmann::json::object();
  for (size_t i = 0; i < parameters.size(); ++i) {
    values[parameters[i].pointer] = parameters[i].values[digit[i]];
  }
  return values;
}

nlohmann::json SweepPlan::run_scene(size_t k) const {
  nlohmann::json doc = scene_doc;
  const nlohmann::json values = run_values(k);  // must outlive the items() view
  for (const auto& [pointer, value] : values.items()) {
    doc[nlohmann::json::json_pointer(pointer)] = value;
  }
  return doc;
}

SweepPlan load_sweep(const fs::path& file) {
  const nlohmann::json doc = read_json_file(file);
  JsonReader r(doc, file.string());
  r.required_integer("pliant_sweep", 1, 1);
  SweepPlan plan;
  plan.file = file;
  const fs::path base = file.parent_path();
  plan.scene = base / r.required_string("scene");
  plan.out = base / r.string("out", file.stem().string() + "_takes");
  plan.threads = int(r.integer("threads", 0, 0, 4096));
  try {
    plan.scene_doc = load_scene(plan.scene).doc;
  } catch (const InputError& e) {
    r.fail("scene", std::string("the scene does not load: ") + e.what());
  }
  std::vector<JsonReader> params = r.objects("parameters");
  if (params.empty()) r.fail("parameters", "expected a non-empty array of {pointer, values}");
  size_t runs = 1;
  for (JsonReader& p : params) {
    SweepParameter sp;
    sp.pointer = p.required_string("pointer");
    try {
      const nlohmann::json::json_pointer ptr(sp.pointer);
      if (sp.pointer.empty() || !plan.scene_doc.contains(ptr)) {
        p.fail("pointer", "the scene " + plan.scene.string() + " has no value at \"" +
                              sp.pointer + "\"");
      }
    } catch (const nlohmann::json::exception& e) {
      p.fail("pointer", "not a JSON pointer (RFC 6901): \"" + sp.pointer + "\"");
    }
    p.accept("values");
    const nlohmann::json& values = p.value().contains("values") ? p.value()["values"] : nlohmann::json();
    if (!values.is_array() || values.empty()) p.fail("values", "expected a non-empty array");
    sp.values.assign(values.begin(), values.end());
    p.finish();
    runs *= sp.values.size();
    if (runs > kMaxRuns) p.fail("values", "the sweep would have more than 1000000 runs");
    plan.parameters.push_back(std::move(sp));
  }
  r.finish();
  return plan;
}

Shard parse_shard(const std::string& text) {
  Shard s;
  const size_t slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    size_t used = 0;
    const long long i = std::stoll(text.substr(0, slash), &used);
    if (used != slash) throw std::invalid_argument("index");
    const std::string rest = text.substr(slash + 1);
    const long long n = std::stoll(rest, &used);
    if (used != rest.size() || n < 1 || i < 0 || i >= n) throw std::invalid_argument("range");
    s.index = size_t(i);
    s.count = size_t(n);
  } catch (const std::exception&) {
    throw InputError("--shard", "", "expected I/N with 0 <= I < N, got \"" + text + "\"");
  }
  return s;
}

}  // namespace pliant::cli
