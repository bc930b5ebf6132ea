// Validating reader over a nlohmann::json object (json_reader.h). Messages
// follow error.h: "FILE: POINTER: expected ..., got VALUE".
#include "pliant/core/json_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pliant {
namespace {

constexpr double kNoMin = -1e300, kNoMax = 1e300;
constexpr long long kNoMinInt = -(1LL << 62), kNoMaxInt = (1LL << 62);

// A value as it appears in JSON; long ones are shortened.
std::string shown(const nlohmann::json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array of " + std::to_string(v.size());
  std::string s = v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::string fmt_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}

std::string quote_str(const std::string& s) { return "\"" + s + "\""; }

std::string suggestion(std::string_view word, const std::vector<std::string>& candidates) {
  std::string near = nearest_name(word, candidates);
  return near.empty() ? "" : "; did you mean " + quote_str(near) + "?";
}

// "expected a number >= 0" etc.: names the bound that `x` violates.
std::string number_bound_problem(double x, double min, double max) {
  if (min != kNoMin && max != kNoMax && (x < min || x > max))
    return "expected a number in [" + fmt_number(min) + ", " + fmt_number(max) + "]";
  if (x < min) return min == 0 ? "expected a non-negative number" : "expected a number >= " + fmt_number(min);
  return "expected a number <= " + fmt_number(max);
}

std::string integer_bound_problem(long long x, long long min, long long max) {
  if (x < min && min == 1) return "expected a positive integer";
  if (x < min && min == 0) return "expected a non-negative integer";
  if (min != kNoMinInt && max != kNoMaxInt)
    return "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (x < min) return "expected an integer >= " + std::to_string(min);
  return "expected an integer <= " + std::to_string(max);
}

// Checks one number; returns an empty string when fine, else the problem.
std::string check_number(const nlohmann::json& v, double min, double max, double* out) {
  if (!v.is_number()) return "expected a number, got " + shown(v);
  double x = v.get<double>();
  if (!(x >= min && x <= max)) return number_bound_problem(x, min, max) + ", got " + shown(v);
  *out = x;
  return {};
}

std::string check_integer(const nlohmann::json& v, long long min, long long max, long long* out) {
  long long x = 0;
  if (v.is_number_unsigned()) {
    auto u = v.get<unsigned long long>();
    if (u > static_cast<unsigned long long>(max)) return integer_bound_problem(max, min, max) + ", got " + shown(v);
    x = static_cast<long long>(u);
  } else if (v.is_number_integer()) {
    x = v.get<long long>();
  } else if (v.is_number_float()) {
    double d = v.get<double>();
    // 3.0 is an integer written as a float; 2.5 is not.
    if (!(std::floor(d) == d) || !(std::fabs(d) < 9.0e18)) return "expected an integer, got " + shown(v);
    x = static_cast<long long>(d);
  } else {
    return "expected an integer, got " + shown(v);
  }
  if (x < min || x > max) return integer_bound_problem(x, min, max) + ", got " + shown(v);
  *out = x;
  return {};
}

std::string array_size_text(size_t min_size, size_t max_size, const char* what) {
  if (min_size == max_size) return "expected an array of " + std::to_string(min_size) + " " + what;
  return "expected an array of " + std::to_string(min_size) + " to " + std::to_string(max_size) + " " + what;
}

std::string escape_pointer_token(std::string_view key) {
  std::string out;
  out.reserve(key.size());
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

}  // namespace

JsonReader::JsonReader(const nlohmann::json& value, std::string file, std::string pointer)
    : value_(&value), file_(std::move(file)), pointer_(std::move(pointer)) {
  if (!value.is_object())
    throw InputError(file_, pointer_, "expected an object, got " + shown(value));
}

bool JsonReader::has(std::string_view key) const { return value_->find(key) != value_->end(); }

std::string JsonReader::child_pointer(std::string_view key) const {
  return pointer_ + "/" + escape_pointer_token(key);
}

void JsonReader::accept(std::string_view key) { known_.emplace(key); }

void JsonReader::fail(std::string_view key, const std::string& problem) const {
  throw InputError(file_, child_pointer(key), problem);
}

double JsonReader::number(std::string_view key, double def, double min, double max) {
  accept(key);
  auto it = value_->find(key);
  if (it == value_->end()) return def;
  double x = 0;
  if (auto p = check_number(*it, min, max, &x); !p.empty()) fail(key, p);
  return x;
}

double JsonReader::required_number(std::string_view key, double min, double max) {
  if (!has(key)) fail(key, "missing required field; expected a number");
  return number(key, 0, min, max);
}

long long JsonReader::integer(std::string_view key, long long def, long long min, long long max) {
  accept(key);
  auto it = value_->find(key);
  if (it == value_->end()) return def;
  long long x = 0;
  if (auto p = check_integer(*it, min, max, &x); !p.empty()) fail(key, p);
  return x;
}

long long JsonReader::required_integer(std::string_view key, long long min, long long max) {
  if (!has(key)) fail(key, "missing required field; expected an integer");
  return integer(key, 0, min, max);
}

bool JsonReader::boolean(std::string_view key, bool def) {
  accept(key);
  auto it = value_->find(key);
  if (it == value_->end()) return def;
  if (!it->is_boolean()) fail(key, "expected true or false, got " + shown(*it));
  return it->get<bool>();
}

std::string JsonReader::string(std::string_view key, std::string def) {
  accept(key);
  auto it = value_->find(key);
  if (it == value_->end()) return def;
  if (!it->is_string()) fail(key, "expected a string, got " + shown(*it));
  return it->get<std::string>();
}

std::string JsonReader::required_string(std::string_view key) {
  if (!has(key)) fail(key, "missing required field; expected a string");
  return string(key, "");
}

std::string JsonReader::choice(std::string_view key, std::string def,
                               const std::vector<std::string>& allowed) {
  accept(key);
  auto it = value_->find(key);
  if (it == value_->end()) return def;
  std::string list;
  for (size_t i = 0; i < allowed.size(); ++i) list += (i ? ", " : "") + quote_str(allowed[i]);
  if (!it->is_string()) fail(key, "expected one of " + list + ", got " + shown(*it));
  std::string s = it->get<std::string>();
  if (std::find(allowed.begin(), allowed.end(), s) == allowed.end())
    fail(key, "expected one of " + list + ", got " + shown(*it) + suggestion(s, allowed));
  return s;
}

std::vector<double> JsonReader::numbers(std::string_view key, std::vector<double> def,
                                        size_t min_size, size_t max_size, double min, double max) {
  accept(key);
  auto it = value_->find(key);
  if (it == value_->end()) return def;
  if (!it->is_array() || it->size() < min_size || it->size() > max_size)
    fail(key, array_size_text(min_size, max_size, "numbers") + ", got " + shown(*it));
  std::vector<double> out(it->size());
  for (size_t i = 0; i < it->size(); ++i) {
    if (auto p = check_number((*it)[i], min, max, &out[i]); !p.empty())
      throw InputError(file_, child_pointer(key) + "/" + std::to_string(i), p);
  }
  return out;
}

std::vector<long long> JsonReader::integers(std::string_view key, std::vector<long long> def,
                                            size_t min_size, size_t max_size, long long min,
                                            long long max) {
  accept(key);
  auto it = value_->find(key);
  if (it == value_->end()) return def;
  if (!it->is_array() || it->size() < min_size || it->size() > max_size)
    fail(key, array_size_text(min_size, max_size, "integers") + ", got " + shown(*it));
  std::vector<long long> out(it->size());
  for (size_t i = 0; i < it->size(); ++i) {
    if (auto p = check_integer((*it)[i], min, max, &out[i]); !p.empty())
      throw InputError(file_, child_pointer(key) + "/" + std::to_string(i), p);
  }
  return out;
}

std::optional<JsonReader> JsonReader::object(std::string_view key) {
  accept(key);
  auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return JsonReader(*it, file_, child_pointer(key));
}

std::vector<JsonReader> JsonReader::objects(std::string_view key) {
  accept(key);
  auto it = value_->find(key);
  std::vector<JsonReader> out;
  if (it == value_->end()) return out;
  if (!it->is_array()) fail(key, "expected an array of objects, got " + shown(*it));
  out.reserve(it->size());
  for (size_t i = 0; i < it->size(); ++i)
    out.emplace_back((*it)[i], file_, child_pointer(key) + "/" + std::to_string(i));
  return out;
}

void JsonReader::finish() const {
  // nlohmann::json objects are std::map-backed, so items() is in key order.
  for (const auto& item : value_->items()) {
    if (known_.count(item.key())) continue;
    std::vector<std::string> known(known_.begin(), known_.end());
    fail(item.key(), "unknown field" + suggestion(item.key(), known));
  }
}

size_t edit_distance(std::string_view a, std::string_view b) {
  // Levenshtein distance, one row of the dynamic-programming table.
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string nearest_name(std::string_view word, const std::vector<std::string>& candidates) {
  const size_t limit = std::max<size_t>(2, word.size() / 3);
  std::string best;
  size_t best_d = limit + 1;
  for (const auto& c : candidates) {
    size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

}  // namespace pliant
