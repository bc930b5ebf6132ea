#include "doc/export_run.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <sstream>

extern char** environ;

namespace pliant::editor {

namespace fs = std::filesystem;

namespace {

// Runs argv with stdout+stderr captured; returns the exit status (-1 when it
// could not start) and the tail of its output.
int run_capture(const std::vector<std::string>& args, std::string* out) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return -1;
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&fa, fds[1], STDERR_FILENO);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  std::vector<std::string> a = args;
  std::vector<char*> argv;
  for (auto& s : a) argv.push_back(s.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  int rc = posix_spawnp(&pid, a[0].c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    *out = "cannot start " + a[0] + ": " + std::strerror(rc);
    return -1;
  }
  char buf[4096];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    out->append(buf, size_t(n));
    if (out->size() > 16384) out->erase(0, out->size() - 8192);
  }
  ::close(fds[0]);
  int st = 0;
  while (::waitpid(pid, &st, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

}  // namespace

ExportRun::ExportRun(std::vector<std::vector<std::string>> commands, fs::path out_dir)
    : commands_(std::move(commands)), out_(std::move(out_dir)) {
  thread_ = std::thread([this] { run(); });
}

ExportRun::~ExportRun() { wait(); }

void ExportRun::wait() {
  if (thread_.joinable()) thread_.join();
}

std::string ExportRun::message() const {
  std::lock_guard<std::mutex> lock(mu_);
  return message_;
}

void ExportRun::run() {
  bool good = true;
  for (const auto& c : commands_) {
    std::string out;
    int rc = run_capture(c, &out);
    if (rc != 0) {
      // The last non-empty line says why.
      std::string last;
      std::istringstream in(out);
      for (std::string l; std::getline(in, l);)
        if (!l.empty()) last = l;
      std::lock_guard<std::mutex> lock(mu_);
      message_ = fs::path(c[0]).filename().string() + " failed (exit " + std::to_string(rc) + "): " + last;
      good = false;
      break;
    }
  }
  if (good) {
    std::lock_guard<std::mutex> lock(mu_);
    message_ = "exported to " + out_.string();
  }
  ok_ = good;
  done_ = true;
}

std::string find_ffmpeg() {
  if (const char* p = std::getenv("PLIANT_FFMPEG")) return p;  // "" disables (tests)
  const char* path = std::getenv("PATH");
  std::istringstream in(path ? path : "/usr/bin:/bin");
  for (std::string d; std::getline(in, d, ':');) {
    fs::path f = fs::path(d) / "ffmpeg";
    if (::access(f.c_str(), X_OK) == 0) return f.string();
  }
  return "";
}

}  // namespace pliant::editor
