// Log lines shown in the log panel: from jobs and from the editor itself.
// Bounded ring so a chatty job cannot grow memory without limit.
#pragma once
#include <deque>
#include <string>

namespace pliant::editor {

enum class LogLevel { Debug, Info, Warning, Error };
LogLevel parse_log_level(const std::string& s);
const char* log_level_name(LogLevel l);

struct LogLine {
  LogLevel level = LogLevel::Info;
  std::string source;  // "editor", "job 3"
  std::string message;
};

class LogBuffer {
 public:
  explicit LogBuffer(size_t max_lines = 5000) : max_(max_lines) {}
  void add(LogLevel level, const std::string& source, const std::string& message);
  void info(const std::string& m) { add(LogLevel::Info, "editor", m); }
  void warn(const std::string& m) { add(LogLevel::Warning, "editor", m); }
  void error(const std::string& m) { add(LogLevel::Error, "editor", m); }
  void clear() { lines_.clear(); }
  const std::deque<LogLine>& lines() const { return lines_; }
  // True if any line's message contains text.
  bool contains(const std::string& text) const;
  uint64_t added() const { return added_; }  // total ever added (auto-scroll trigger)

 private:
  std::deque<LogLine> lines_;
  size_t max_;
  uint64_t added_ = 0;
};

}  // namespace pliant::editor
