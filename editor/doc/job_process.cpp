#include "doc/job_process.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace pliant::editor {

namespace fs = std::filesystem;

const char* job_state_name(JobState s) {
  switch (s) {
    case JobState::Starting: return "starting";
    case JobState::Running: return "running";
    case JobState::Done: return "done";
    case JobState::Failed: return "failed";
    case JobState::Cancelled: return "cancelled";
  }
  return "?";
}

fs::path default_pliant_binary() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "pliant";
  return exe.parent_path() / "pliant";
}

fs::path default_take_dir(const fs::path& scene_file, const fs::path& config_dir) {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
  fs::path base = scene_file.empty()
                      ? config_dir / "takes"
                      : fs::path(scene_file.string() + ".takes");
  fs::path dir = base / stamp;
  std::error_code ec;
  for (int n = 2; fs::exists(dir, ec); ++n) dir = base / (std::string(stamp) + "-" + std::to_string(n));
  return dir;
}

JobProcess::~JobProcess() {
  if (!reader_.joinable()) return;
  cancel();
  // A job cancels at its next safe point; one that does not within 5 s is killed
  // so quitting the editor never hangs on it.
  for (int i = 0; i < 500; ++i) {
    if (snapshot().exit_code >= 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  {
    std::lock_guard<std::mutex> lk(mu_);
    if (status_.exit_code < 0 && pid_ > 0) ::kill(pid_, SIGKILL);
  }
  reader_.join();
}

bool JobProcess::start(const JobSpec& spec, std::string* err) {
  spec_ = spec;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    *err = std::string("pipe: ") + std::strerror(errno);
    return false;
  }
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&fa, fds[1], STDERR_FILENO);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);

  std::vector<std::string> args{spec.pliant.string(), "run", spec.scene.string(), "--take",
                                spec.take.string()};
  if (spec.threads > 0) {
    args.push_back("--threads");
    args.push_back(std::to_string(spec.threads));
  }
  if (spec.resume) args.push_back("--resume");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  pid_t pid = -1;
  int rc = posix_spawn(&pid, args[0].c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    *err = "cannot start " + args[0] + ": " + std::strerror(rc);
    return false;
  }
  pid_ = pid;
  {
    std::lock_guard<std::mutex> lk(mu_);
    status_ = JobStatus{};
  }
  reader_ = std::thread([this, fd = fds[0]] { reader_loop(fd); });
  return true;
}

void JobProcess::cancel() {
  std::lock_guard<std::mutex> lk(mu_);
  // Only signal a child we have not reaped yet (its pid cannot have been reused).
  if (pid_ > 0 && status_.exit_code < 0 && !cancel_requested_) {
    ::kill(pid_, SIGTERM);
    cancel_requested_ = true;
  }
}

JobStatus JobProcess::snapshot() const {
  std::lock_guard<std::mutex> lk(mu_);
  return status_;
}

std::vector<JobLogLine> JobProcess::take_log() {
  std::lock_guard<std::mutex> lk(mu_);
  std::vector<JobLogLine> out;
  out.swap(log_);
  return out;
}

void JobProcess::apply_line(const std::string& line, JobStatus& st, std::vector<JobLogLine>& log) {
  if (line.empty()) return;
  auto j = nlohmann::json::parse(line, nullptr, false);
  if (!j.is_object() || !j.contains("event") || !j["event"].is_string()) {
    // stderr or a foreign line: keep it visible in the log.
    log.push_back({"info", line});
    return;
  }
  const std::string ev = j["event"];
  auto num = [&](const char* k, double d) {
    return j.contains(k) && j[k].is_number() ? j[k].get<double>() : d;
  };
  auto str = [&](const char* k) {
    return j.contains(k) && j[k].is_string() ? j[k].get<std::string>() : std::string();
  };
  if (ev == "start") {
    st.state = JobState::Running;
    st.frames_expected = static_cast<int>(num("frames", 0));
  } else if (ev == "progress") {
    st.state = JobState::Running;
    const std::string stage = str("stage");
    // A stage on another grid level ("admm 32x32" -> "admm"; the level is what
    // follows the first blank) starts a new objective curve: objectives of
    // different resolutions are not comparable. "admm" -> "lbfgs" (the polish
    // on the same grid) continues it.
    auto level = [](const std::string& s) {
      const size_t b = s.find(' ');
      return b == std::string::npos ? std::string() : s.substr(b + 1);
    };
    if (j.contains("objective") && !st.stage.empty() && level(stage) != level(st.stage)) st.objective.clear();
    st.stage = stage;
    st.iter = static_cast<int>(num("iter", 0));
    st.of = static_cast<int>(num("of", 0));
    st.eta_s = num("eta_s", -1);
    if (j.contains("objective") && j["objective"].is_number())
      st.objective.push_back(j["objective"].get<float>());
  } else if (ev == "frame") {
    st.state = JobState::Running;
    ++st.frames_seen;
    st.last_frame = static_cast<int>(num("index", st.last_frame + 1));
  } else if (ev == "log") {
    std::string level = str("level");
    st.last_message = str("message");
    log.push_back({level.empty() ? "info" : level, st.last_message});
  } else if (ev == "done") {
    st.state = JobState::Done;
    if (j.contains("metrics")) st.metrics = j["metrics"];
    st.last_message = "done";
  } else if (ev == "error") {
    st.state = JobState::Failed;
    st.error = str("message");
    st.last_message = st.error;
    log.push_back({"error", st.error});
  } else if (ev == "cancelled") {
    st.state = JobState::Cancelled;
    st.last_message = "cancelled";
  }
}

void JobProcess::reader_loop(int fd) {
  std::string buf;
  char chunk[4096];
  for (;;) {
    ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    buf.append(chunk, static_cast<size_t>(n));
    size_t pos;
    while ((pos = buf.find('\n')) != std::string::npos) {
      std::string line = buf.substr(0, pos);
      buf.erase(0, pos + 1);
      std::lock_guard<std::mutex> lk(mu_);
      apply_line(line, status_, log_);
    }
  }
  ::close(fd);
  int wst = 0;
  pid_t r;
  do r = ::waitpid(pid_, &wst, 0);
  while (r < 0 && errno == EINTR);
  std::lock_guard<std::mutex> lk(mu_);
  if (!buf.empty()) apply_line(buf, status_, log_);
  int code = r < 0 ? 1 : WIFEXITED(wst) ? WEXITSTATUS(wst) : 128 + WTERMSIG(wst);
  status_.exit_code = code;
  // The exit status is the final word (ARCHITECTURE.md: 0 done, 3 cancelled).
  if (code == 0) {
    status_.state = JobState::Done;
  } else if (code == 3 || (cancel_requested_ && WIFSIGNALED(wst))) {
    status_.state = JobState::Cancelled;
    status_.last_message = "cancelled";
  } else {
    status_.state = JobState::Failed;
    if (status_.error.empty())
      status_.error = "pliant exited with status " + std::to_string(code);
    status_.last_message = status_.error;
  }
}

}  // namespace pliant::editor
