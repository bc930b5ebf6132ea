// Running the real `pliant` binary from tests: to completion (stdout and
// stderr captured) or live (stdout read line by line, signals sent mid-run).
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pliant::test {

struct ProcessResult {
  int exit_code = -1;   // when it exited normally
  int term_signal = 0;  // when a signal ended it
  std::string out, err;
};

// Runs argv[0] with argv, extra "NAME=value" entries added to the environment.
// Kills it with SIGKILL after timeout_s (term_signal then says so).
ProcessResult run_process(const std::vector<std::string>& argv,
                          const std::vector<std::string>& extra_env = {},
                          double timeout_s = 120);

// A process whose stdout is read line by line; stderr goes to a file.
class LiveProcess {
 public:
  LiveProcess(const std::vector<std::string>& argv, const std::filesystem::path& stderr_file);
  ~LiveProcess();  // SIGKILLs and reaps it if still running
  LiveProcess(const LiveProcess&) = delete;
  LiveProcess& operator=(const LiveProcess&) = delete;

  // The next stdout line (without '\n'); nullopt at end of output or timeout.
  std::optional<std::string> read_line(double timeout_s);
  void send_signal(int sig);
  // Reads the rest of stdout (returned as lines), then reaps the process.
  ProcessResult finish(std::vector<std::string>* rest_lines, double timeout_s = 120);
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
  std::string buffer_;
  bool eof_ = false;
  bool reaped_ = false;
};

}  // namespace pliant::test
