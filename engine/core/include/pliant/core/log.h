// Engine logging. Engine code never prints; it logs here. The default sink
// writes "pliant: LEVEL: message" to stderr; run_job routes logs into the job
// protocol as {"event":"log",...} lines; the editor installs its log panel.
#pragma once
#include <functional>
#include <string>

namespace pliant {

enum class LogLevel { Debug = 0, Info = 1, Warn = 2, Error = 3 };

using LogSink = std::function<void(LogLevel, const std::string&)>;

const char* log_level_name(LogLevel level);  // "debug", "info", "warn", "error"
// Replaces the sink (an empty function restores the stderr default); returns the old one.
LogSink set_log_sink(LogSink sink);
// Messages below `level` are dropped (default Info); returns the old level.
LogLevel set_log_level(LogLevel level);
// Thread-safe; sinks are called under a mutex, one message at a time (so a
// sink must not log itself).
void log(LogLevel level, const std::string& message);
inline void log_debug(const std::string& m) { log(LogLevel::Debug, m); }
inline void log_info(const std::string& m) { log(LogLevel::Info, m); }
inline void log_warn(const std::string& m) { log(LogLevel::Warn, m); }
inline void log_error(const std::string& m) { log(LogLevel::Error, m); }

}  // namespace pliant
