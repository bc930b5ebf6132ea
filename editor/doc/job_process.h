// A `pliant run` child process (ARCHITECTURE.md, job protocol). Started with
// posix_spawn, stdout+stderr piped; a reader thread parses the JSON lines into
// a mutex-protected JobStatus and reaps the child after EOF. The UI thread only
// copies the status (snapshot()) and never blocks on the child.
#pragma once
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <sys/types.h>
#include <thread>
#include <vector>

namespace pliant::editor {

enum class JobState { Starting, Running, Done, Failed, Cancelled };
const char* job_state_name(JobState s);

struct JobLogLine {
  std::string level, message;
};

struct JobStatus {
  JobState state = JobState::Starting;
  std::string stage;
  int iter = 0, of = 0;
  std::vector<float> objective;  // history of "objective" values
  double eta_s = -1;
  int frames_expected = 0;
  int frames_seen = 0;
  int last_frame = -1;
  std::string last_message;  // newest log/error message
  std::string error;         // set when Failed
  int exit_code = -1;        // -1 until reaped
  nlohmann::json metrics;
  bool ended() const {
    return state == JobState::Done || state == JobState::Failed || state == JobState::Cancelled;
  }
};

struct JobSpec {
  std::filesystem::path pliant;  // the `pliant` binary
  std::filesystem::path scene;   // a saved scene file
  std::filesystem::path take;
  int threads = 0;
  bool resume = false;  // `pliant run --resume`: continue the take from its checkpoint
};

// dirname(/proc/self/exe)/pliant.
std::filesystem::path default_pliant_binary();
// "<scene>.takes/<YYYYmmdd-HHMMSS[-n]>" beside a saved scene, else under
// CONFIG/takes/.
std::filesystem::path default_take_dir(const std::filesystem::path& scene_file,
                                       const std::filesystem::path& config_dir);

class JobProcess {
 public:
  JobProcess() = default;
  ~JobProcess();  // cancels a running child and joins the reader
  JobProcess(const JobProcess&) = delete;
  JobProcess& operator=(const JobProcess&) = delete;

  // Spawns the child; false with *err on failure (no thread started).
  bool start(const JobSpec& spec, std::string* err);
  // SIGTERM: the job cancels at its next safe point.
  void cancel();
  JobStatus snapshot() const;
  // Log lines received since the last call (moved out).
  std::vector<JobLogLine> take_log();

  const JobSpec& spec() const { return spec_; }
  pid_t pid() const { return pid_; }
  int id = 0;  // display number

  // Parses one stdout line into the status (public for tests).
  static void apply_line(const std::string& line, JobStatus& st, std::vector<JobLogLine>& log);

 private:
  void reader_loop(int fd);
  JobSpec spec_;
  pid_t pid_ = -1;
  std::thread reader_;
  mutable std::mutex mu_;
  JobStatus status_;
  std::vector<JobLogLine> log_;
  bool cancel_requested_ = false;
};

}  // namespace pliant::editor
