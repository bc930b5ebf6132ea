// posix_spawn + pipes + poll; the child inherits the environment.
#include "subprocess.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace pliant::test {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<char*> c_strings(std::vector<std::string>& v) {
  std::vector<char*> out;
  for (auto& s : v) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

// Spawns argv with stdout -> out_fd and stderr -> err_fd (both in the child).
pid_t spawn(std::vector<std::string> argv, const std::vector<std::string>& extra_env, int out_fd,
            int err_fd, const char* err_path) {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) env.emplace_back(*e);
  for (const auto& e : extra_env) env.push_back(e);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, out_fd, 1);
  if (err_path) {
    posix_spawn_file_actions_addopen(&fa, 2, err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  } else {
    posix_spawn_file_actions_adddup2(&fa, err_fd, 2);
  }
  auto args = c_strings(argv);
  auto envp = c_strings(env);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, args[0], &fa, nullptr, args.data(), envp.data());
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error("posix_spawn " + argv[0] + ": " + std::strerror(rc));
  return pid;
}

void make_pipe(int fds[2]) {
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed");
}

void decode_status(int status, ProcessResult* r) {
  if (WIFEXITED(status)) r->exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r->term_signal = WTERMSIG(status);
}

Clock::time_point deadline_after(double seconds) {
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

double seconds_left(Clock::time_point deadline) {
  return std::chrono::duration<double>(deadline - Clock::now()).count();
}

}  // namespace

ProcessResult run_process(const std::vector<std::string>& argv,
                          const std::vector<std::string>& extra_env, double timeout_s) {
  int out[2], err[2];
  make_pipe(out);
  make_pipe(err);
  const pid_t pid = spawn(argv, extra_env, out[1], err[1], nullptr);
  ::close(out[1]);
  ::close(err[1]);
  ProcessResult r;
  const auto deadline = deadline_after(timeout_s);
  pollfd fds[2] = {{out[0], POLLIN, 0}, {err[0], POLLIN, 0}};
  std::string* sinks[2] = {&r.out, &r.err};
  int open_count = 2;
  while (open_count > 0) {
    const double left = seconds_left(deadline);
    if (left <= 0) {
      ::kill(pid, SIGKILL);
      break;
    }
    if (::poll(fds, 2, int(left * 1000) + 1) < 0) continue;
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      char buf[65536];
      const ssize_t n = ::read(fds[i].fd, buf, sizeof buf);
      if (n > 0) {
        sinks[i]->append(buf, size_t(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_count;
      }
    }
  }
  for (auto& f : fds)
    if (f.fd >= 0) ::close(f.fd);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  decode_status(status, &r);
  return r;
}

LiveProcess::LiveProcess(const std::vector<std::string>& argv,
                         const std::filesystem::path& stderr_file) {
  int out[2];
  make_pipe(out);
  pid_ = spawn(argv, {}, out[1], -1, stderr_file.c_str());
  ::close(out[1]);
  out_fd_ = out[0];
}

LiveProcess::~LiveProcess() {
  if (!reaped_ && pid_ > 0) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  if (out_fd_ >= 0) ::close(out_fd_);
}

std::optional<std::string> LiveProcess::read_line(double timeout_s) {
  const auto deadline = deadline_after(timeout_s);
  while (true) {
    const size_t nl = buffer_.find('\n');
    if (nl != std::string::npos) {
      std::string line = buffer_.substr(0, nl);
      buffer_.erase(0, nl + 1);
      return line;
    }
    if (eof_) return std::nullopt;
    const double left = seconds_left(deadline);
    if (left <= 0) return std::nullopt;
    pollfd p{out_fd_, POLLIN, 0};
    if (::poll(&p, 1, int(left * 1000) + 1) <= 0) continue;
    char buf[4096];
    const ssize_t n = ::read(out_fd_, buf, sizeof buf);
    if (n > 0) {
      buffer_.append(buf, size_t(n));
    } else if (n == 0 || errno != EINTR) {
      eof_ = true;
    }
  }
}

void LiveProcess::send_signal(int sig) { ::kill(pid_, sig); }

ProcessResult LiveProcess::finish(std::vector<std::string>* rest_lines, double timeout_s) {
  const auto deadline = deadline_after(timeout_s);
  while (auto line = read_line(std::max(0.0, seconds_left(deadline)))) {
    if (rest_lines) rest_lines->push_back(*line);
  }
  if (!buffer_.empty() && rest_lines) rest_lines->push_back(buffer_);  // unterminated last line
  buffer_.clear();
  if (!eof_) ::kill(pid_, SIGKILL);  // timed out
  ProcessResult r;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  reaped_ = true;
  decode_status(status, &r);
  return r;
}

}  // namespace pliant::test
