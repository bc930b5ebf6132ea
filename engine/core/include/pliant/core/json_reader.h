// Reading a JSON object with validation. Every accessor records the key as known;
// finish() then rejects unknown keys, suggesting the nearest known name
// ("/grid/resoluton: unknown field; did you mean \"resolution\"?").
// Every failure throws InputError naming file + JSON pointer + expectation.
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "pliant/core/error.h"

namespace pliant {

class JsonReader {
 public:
  // `value` must outlive the reader. `pointer` is the JSON pointer of `value`.
  // Throws InputError if value is not an object.
  JsonReader(const nlohmann::json& value, std::string file, std::string pointer = "");

  bool has(std::string_view key) const;
  const std::string& file() const { return file_; }
  const std::string& pointer() const { return pointer_; }
  std::string child_pointer(std::string_view key) const;  // escapes ~ and /

  // Scalars: `def` is used when the key is absent. Bounds are inclusive.
  double number(std::string_view key, double def, double min = -1e300, double max = 1e300);
  double required_number(std::string_view key, double min = -1e300, double max = 1e300);
  long long integer(std::string_view key, long long def, long long min = -(1LL << 62),
                    long long max = (1LL << 62));
  long long required_integer(std::string_view key, long long min = -(1LL << 62),
                             long long max = (1LL << 62));
  bool boolean(std::string_view key, bool def);
  std::string string(std::string_view key, std::string def);
  std::string required_string(std::string_view key);
  // One of `allowed`; an unknown value names the allowed ones and the nearest.
  std::string choice(std::string_view key, std::string def, const std::vector<std::string>& allowed);

  // Fixed-size numeric arrays ("expected an array of 3 numbers").
  std::vector<double> numbers(std::string_view key, std::vector<double> def, size_t min_size,
                              size_t max_size, double min = -1e300, double max = 1e300);
  std::vector<long long> integers(std::string_view key, std::vector<long long> def,
                                  size_t min_size, size_t max_size, long long min = -(1LL << 62),
                                  long long max = (1LL << 62));

  // Nested object / array of objects; absent -> nullopt / empty.
  std::optional<JsonReader> object(std::string_view key);
  std::vector<JsonReader> objects(std::string_view key);

  // Mark a key known without reading it (e.g. read elsewhere).
  void accept(std::string_view key);
  // Throws InputError for the first key never read/accepted.
  void finish() const;
  [[noreturn]] void fail(std::string_view key, const std::string& problem) const;

  const nlohmann::json& value() const { return *value_; }

 private:
  const nlohmann::json* value_;
  std::string file_, pointer_;
  std::set<std::string, std::less<>> known_;
};

// Edit distance used for "did you mean" suggestions.
size_t edit_distance(std::string_view a, std::string_view b);
// Nearest of `candidates` to `word`, or "" if none is close (distance > max(2, len/3)).
std::string nearest_name(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace pliant
