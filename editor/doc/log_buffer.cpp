#include "doc/log_buffer.h"

namespace pliant::editor {

LogLevel parse_log_level(const std::string& s) {
  if (s == "debug") return LogLevel::Debug;
  if (s == "warn" || s == "warning") return LogLevel::Warning;
  if (s == "error") return LogLevel::Error;
  return LogLevel::Info;
}

const char* log_level_name(LogLevel l) {
  switch (l) {
    case LogLevel::Debug: return "debug";
    case LogLevel::Info: return "info";
    case LogLevel::Warning: return "warning";
    case LogLevel::Error: return "error";
  }
  return "?";
}

void LogBuffer::add(LogLevel level, const std::string& source, const std::string& message) {
  lines_.push_back({level, source, message});
  while (lines_.size() > max_) lines_.pop_front();
  ++added_;
}

bool LogBuffer::contains(const std::string& text) const {
  for (const auto& l : lines_)
    if (l.message.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace pliant::editor
