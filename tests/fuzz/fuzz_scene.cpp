// libFuzzer target: parse_scene on arbitrary bytes, then every JsonReader
// accessor on every object of the document. InputError is the expected
// failure; any other exception escapes and libFuzzer reports it as a crash.
#include <cstddef>
#include <cstdint>
#include <string>

#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"
#include "pliant/core/scene.h"

namespace {

template <class F>
void expect_input_error_or_value(F&& f) {
  try {
    f();
  } catch (const pliant::InputError& e) {
    if (e.what()[0] == '\0' || e.problem().empty()) __builtin_trap();  // messages must say something
  }
}

void exercise(const nlohmann::json& value, const std::string& pointer, int depth) {
  if (depth > 16) return;
  if (value.is_array()) {
    for (size_t i = 0; i < value.size() && i < 64; ++i)
      exercise(value[i], pointer + "/" + std::to_string(i), depth + 1);
    return;
  }
  if (!value.is_object()) {
    expect_input_error_or_value([&] { pliant::JsonReader(value, "fuzz.json", pointer); });
    return;
  }
  pliant::JsonReader r(value, "fuzz.json", pointer);
  for (const auto& item : value.items()) {
    const std::string& k = item.key();
    expect_input_error_or_value([&] { r.number(k, 0, -1, 1); });
    expect_input_error_or_value([&] { r.integer(k, 0, 1, 64); });
    expect_input_error_or_value([&] { r.boolean(k, false); });
    expect_input_error_or_value([&] { r.string(k, ""); });
    expect_input_error_or_value([&] { r.choice(k, "a", {"closed", "periodic", "smoke"}); });
    expect_input_error_or_value([&] { r.numbers(k, {}, 2, 3, 0, 1); });
    expect_input_error_or_value([&] { r.integers(k, {}, 1, 3, 1); });
    expect_input_error_or_value([&] { r.object(k); });
    expect_input_error_or_value([&] { r.objects(k); });
    exercise(item.value(), r.child_pointer(k), depth + 1);
  }
  pliant::JsonReader fresh(value, "fuzz.json", pointer);
  expect_input_error_or_value([&] { fresh.finish(); });
  expect_input_error_or_value([&] { fresh.required_number("required_number_never_present_", 0, 1); });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    pliant::Scene scene = pliant::parse_scene(text, "fuzz.json");
    if (scene.kind.empty()) __builtin_trap();
    exercise(scene.doc, "", 0);
  } catch (const pliant::InputError& e) {
    if (e.file() != "fuzz.json") __builtin_trap();
  }
  return 0;
}
