#include "pliant/core/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace pliant {
namespace {
std::mutex& sink_mutex() {
  static std::mutex mu;
  return mu;
}
LogSink& current_sink() {
  static LogSink sink;
  return sink;
}
std::atomic<int> g_min_level{static_cast<int>(LogLevel::Info)};
}  // namespace

const char* log_level_name(LogLevel level) {
  switch (level) {
    case LogLevel::Debug: return "debug";
    case LogLevel::Info: return "info";
    case LogLevel::Warn: return "warn";
    case LogLevel::Error: return "error";
  }
  return "info";
}

LogSink set_log_sink(LogSink sink) {
  std::lock_guard<std::mutex> lock(sink_mutex());
  LogSink old = std::move(current_sink());
  current_sink() = std::move(sink);
  return old;
}

LogLevel set_log_level(LogLevel level) {
  return static_cast<LogLevel>(g_min_level.exchange(static_cast<int>(level)));
}

void log(LogLevel level, const std::string& message) {
  if (static_cast<int>(level) < g_min_level.load()) return;
  std::lock_guard<std::mutex> lock(sink_mutex());
  if (current_sink()) {
    current_sink()(level, message);
  } else {
    std::fprintf(stderr, "pliant: %s: %s\n", log_level_name(level), message.c_str());
  }
}

}  // namespace pliant
