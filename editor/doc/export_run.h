// An export running beside the UI: a list of commands (`pliant export ...`, then
// optionally ffmpeg) run one after another on a thread, each a child process
// whose output is kept for the message. The UI polls done()/ok()/message().
#pragma once
#include <atomic>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace pliant::editor {

class ExportRun {
 public:
  // argv lists; every command must exit 0 for the next to run.
  ExportRun(std::vector<std::vector<std::string>> commands, std::filesystem::path out_dir);
  ~ExportRun();  // joins
  ExportRun(const ExportRun&) = delete;
  ExportRun& operator=(const ExportRun&) = delete;

  bool done() const { return done_.load(); }
  bool ok() const { return ok_.load(); }
  std::string message() const;
  const std::filesystem::path& out_dir() const { return out_; }
  void wait();

 private:
  void run();
  std::vector<std::vector<std::string>> commands_;
  std::filesystem::path out_;
  std::thread thread_;
  std::atomic<bool> done_{false}, ok_{false};
  mutable std::mutex mu_;
  std::string message_;
};

// The ffmpeg binary on PATH, or "" when it is not installed.
std::string find_ffmpeg();

}  // namespace pliant::editor
