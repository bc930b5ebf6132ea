// Parsing of UI scripts (see ui_script.h for the commands).
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "ui/ui_script.h"

namespace pliant::editor {

namespace {

struct Arity {
  int min, max;  // max -1: unbounded
};

const std::map<std::string, Arity>& commands() {
  static const std::map<std::string, Arity> m = {
      {"move", {2, 2}},        {"click", {0, 3}},        {"drag", {4, 6}},
      {"scroll", {1, 1}},      {"key", {1, 1}},          {"type", {1, 1}},
      {"wait", {1, 1}},        {"wait_job", {0, 1}},     {"wait_frames", {1, 2}},
      {"click_item", {1, 2}},  {"drag_item", {3, 4}},    {"set_frame", {1, 1}},
      {"screenshot", {1, 2}},  {"drop", {1, -1}},        {"expect", {1, 1}},
      {"expect_json", {2, 2}}, {"quit", {0, 0}},
      {"drag_item_at", {5, 6}}, {"click_item_at", {3, 3}}, {"export", {2, 2}},
      {"wait_export", {0, 1}},
  };
  return m;
}

// Splits on blanks; "double quoted" tokens may contain blanks.
std::vector<std::string> tokenize(const std::string& s, std::string* err) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i >= s.size()) break;
    std::string tok;
    if (s[i] == '"') {
      size_t end = s.find('"', i + 1);
      if (end == std::string::npos) {
        *err = "unterminated quote";
        return {};
      }
      tok = s.substr(i + 1, end - i - 1);
      i = end + 1;
    } else {
      while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) tok += s[i++];
    }
    out.push_back(tok);
  }
  return out;
}

bool is_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end && *end == '\0';
}

}  // namespace

Script parse_script(const std::string& text, const std::string& file_label,
                    const std::filesystem::path& dir) {
  Script sc;
  sc.file = file_label;
  sc.dir = dir;
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  auto fail = [&](const std::string& msg) {
    throw ScriptError(file_label + ":" + std::to_string(line) + ": " + msg);
  };
  while (std::getline(in, raw)) {
    ++line;
    size_t b = raw.find_first_not_of(" \t\r");
    if (b == std::string::npos || raw[b] == '#') continue;
    std::string body = raw.substr(b);
    while (!body.empty() && (body.back() == '\r' || body.back() == ' ' || body.back() == '\t'))
      body.pop_back();
    ScriptCommand c;
    c.line = line;
    size_t sp = body.find_first_of(" \t");
    c.op = body.substr(0, sp);
    std::string rest = sp == std::string::npos ? "" : body.substr(body.find_first_not_of(" \t", sp));
    auto it = commands().find(c.op);
    if (it == commands().end()) fail("unknown command '" + c.op + "'");
    if (c.op == "type" || c.op == "expect") {
      // The rest of the line, verbatim (quotes optional).
      if (rest.size() >= 2 && rest.front() == '"' && rest.back() == '"') rest = rest.substr(1, rest.size() - 2);
      if (rest.empty()) fail(c.op + ": expected text");
      c.args = {rest};
    } else if (c.op == "expect_json") {
      size_t s2 = rest.find_first_of(" \t");
      if (s2 == std::string::npos) fail("expect_json: expected POINTER JSON");
      c.args = {rest.substr(0, s2), rest.substr(rest.find_first_not_of(" \t", s2))};
      if (!nlohmann::json::accept(c.args[1])) fail("expect_json: invalid JSON '" + c.args[1] + "'");
    } else {
      std::string err;
      c.args = tokenize(rest, &err);
      if (!err.empty()) fail(err);
    }
    int n = static_cast<int>(c.args.size());
    const Arity& a = it->second;
    if (n < a.min || (a.max >= 0 && n > a.max))
      fail(c.op + ": expected " + std::to_string(a.min) +
           (a.max == a.min ? "" : a.max < 0 ? " or more" : " to " + std::to_string(a.max)) +
           " arguments, got " + std::to_string(n));
    // Numeric arguments.
    auto need_num = [&](int from, int to) {
      for (int k = from; k < std::min(to, n); ++k)
        if (!is_number(c.args[k])) fail(c.op + ": argument " + std::to_string(k + 1) + " '" + c.args[k] + "' is not a number");
    };
    if (c.op == "drag" && n == 6) {
      if (c.args[5] != "left" && c.args[5] != "right" && c.args[5] != "middle")
        fail("drag: unknown button '" + c.args[5] + "'");
      need_num(0, 5);
    } else if (c.op == "move" || c.op == "drag" || c.op == "scroll" || c.op == "wait" ||
        c.op == "wait_job" || c.op == "wait_frames" || c.op == "set_frame")
      need_num(0, n);
    if (c.op == "drag_item" || c.op == "drag_item_at" || c.op == "click_item_at") need_num(1, n);
    if (c.op == "wait_export") need_num(0, n);
    static const std::set<std::string> kFormats = {"png", "mp4", "vdb", "particles", "obj", "csv"};
    if (c.op == "export" && !kFormats.count(c.args[0]))
      fail("export: unknown format '" + c.args[0] + "' (png, mp4, vdb, particles, obj or csv)");
    if (c.op == "click") {
      int first = 0;
      if (n == 1 || n == 3) {
        const std::string& b2 = c.args[0];
        if (b2 != "left" && b2 != "right" && b2 != "middle") fail("click: unknown button '" + b2 + "'");
        first = 1;
      }
      if (n - first != 0 && n - first != 2) fail("click: expected [BUTTON] [X Y]");
      need_num(first, n);
    }
    if (c.op == "click_item" && n == 2 && c.args[1] != "left" && c.args[1] != "right" &&
        c.args[1] != "double")
      fail("click_item: unknown click kind '" + c.args[1] + "' (left, right or double)");
    if (c.op == "screenshot" && n == 2 && c.args[1] != "viewport")
      fail("screenshot: second argument must be 'viewport'");
    sc.commands.push_back(std::move(c));
  }
  return sc;
}

Script load_script(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw ScriptError(path.string() + ": cannot read the script");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_script(ss.str(), path.string(), path.parent_path());
}

}  // namespace pliant::editor
