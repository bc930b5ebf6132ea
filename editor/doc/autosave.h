// Autosave and crash recovery. Each running editor owns a lock file
// (CONFIG/sessions/<pid>.lock) removed on clean exit, and writes its dirty
// document every interval to CONFIG/autosave/<pid>.json as
// {"file": original path or "", "scene": {...}, "saved_unix_s": t}.
// At start, a lock whose pid is dead, with an autosave newer than its file,
// is offered for recovery.
#pragma once
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "doc/document.h"

namespace pliant::editor {

struct RecoveryCandidate {
  int pid = 0;                        // the dead session
  std::filesystem::path file;         // the scene it belonged to ("" = unsaved)
  nlohmann::json scene;
  std::filesystem::path autosave_file, lock_file;
};

class Autosave {
 public:
  // interval_s <= 0: $PLIANT_AUTOSAVE_S or 30 s.
  explicit Autosave(std::filesystem::path config_dir, double interval_s = 0);
  ~Autosave();

  // Writes this process's lock file.
  void begin_session();
  // Clean exit: removes our lock and autosave.
  void end_session();
  // Saves when the document is dirty, changed since the last autosave and the
  // interval has passed. Returns true when it wrote.
  bool tick(const Document& doc, std::chrono::steady_clock::time_point now);
  bool write_now(const Document& doc);

  // The newest recoverable session from a dead process, if any.
  std::optional<RecoveryCandidate> find_recovery() const;
  // Removes a dead session's files (after Recover or Discard).
  static void forget(const RecoveryCandidate& c);

  double interval_s() const { return interval_s_; }
  std::filesystem::path autosave_file() const;
  std::filesystem::path lock_file() const;

 private:
  std::filesystem::path dir_;
  double interval_s_;
  bool session_ = false;
  uint64_t saved_revision_ = ~uint64_t(0);
  std::chrono::steady_clock::time_point last_;
  bool has_last_ = false;
};

// True if a process with this pid exists.
bool process_alive(int pid);

}  // namespace pliant::editor
