#include "doc/autosave.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <unistd.h>

#include "pliant/core/scene.h"

namespace pliant::editor {

namespace fs = std::filesystem;

bool process_alive(int pid) {
  if (pid <= 0) return false;
  return ::kill(pid, 0) == 0 || errno == EPERM;
}

Autosave::Autosave(fs::path config_dir, double interval_s) : dir_(std::move(config_dir)) {
  if (interval_s <= 0) {
    interval_s = 30;
    if (const char* e = std::getenv("PLIANT_AUTOSAVE_S"); e && *e) {
      double v = std::atof(e);
      if (v > 0) interval_s = v;
    }
  }
  interval_s_ = interval_s;
}

Autosave::~Autosave() {
  // Deliberately no end_session() here: only a clean, explicit exit removes the lock.
}

fs::path Autosave::autosave_file() const {
  return dir_ / "autosave" / (std::to_string(::getpid()) + ".json");
}
fs::path Autosave::lock_file() const {
  return dir_ / "sessions" / (std::to_string(::getpid()) + ".lock");
}

void Autosave::begin_session() {
  std::error_code ec;
  fs::create_directories(dir_ / "sessions", ec);
  std::ofstream(lock_file()) << ::getpid() << "\n";
  session_ = true;
}

void Autosave::end_session() {
  if (!session_) return;
  std::error_code ec;
  fs::remove(autosave_file(), ec);
  fs::remove(lock_file(), ec);
  session_ = false;
}

bool Autosave::write_now(const Document& doc) {
  std::error_code ec;
  fs::create_directories(dir_ / "autosave", ec);
  nlohmann::json j{{"file", doc.path().string()},
                   {"scene", doc.scene()},
                   {"saved_unix_s", std::chrono::duration<double>(
                                        std::chrono::system_clock::now().time_since_epoch())
                                        .count()}};
  try {
    save_json_atomic(autosave_file(), j);
  } catch (const std::exception&) {
    return false;
  }
  saved_revision_ = doc.revision();
  return true;
}

bool Autosave::tick(const Document& doc, std::chrono::steady_clock::time_point now) {
  if (!has_last_) {
    last_ = now;
    has_last_ = true;
  }
  if (!doc.dirty() || doc.revision() == saved_revision_) return false;
  if (std::chrono::duration<double>(now - last_).count() < interval_s_) return false;
  last_ = now;
  return write_now(doc);
}

std::optional<RecoveryCandidate> Autosave::find_recovery() const {
  std::error_code ec;
  std::optional<RecoveryCandidate> best;
  fs::file_time_type best_time{};
  for (const auto& e : fs::directory_iterator(dir_ / "sessions", ec)) {
    if (e.path().extension() != ".lock") continue;
    int pid = std::atoi(e.path().stem().c_str());
    if (pid == ::getpid() || process_alive(pid)) continue;
    fs::path as = dir_ / "autosave" / (std::to_string(pid) + ".json");
    if (!fs::exists(as, ec)) continue;
    std::ifstream in(as);
    auto j = nlohmann::json::parse(in, nullptr, false);
    if (!j.is_object() || !j.contains("scene") || !j["scene"].is_object()) continue;
    RecoveryCandidate c;
    c.pid = pid;
    c.file = j.value("file", std::string());
    c.scene = j["scene"];
    c.autosave_file = as;
    c.lock_file = e.path();
    auto t = fs::last_write_time(as, ec);
    // An autosave older than its file was overtaken by a later save.
    if (!c.file.empty() && fs::exists(c.file, ec) && fs::last_write_time(c.file, ec) > t) continue;
    if (!best || t > best_time) {
      best = c;
      best_time = t;
    }
  }
  return best;
}

void Autosave::forget(const RecoveryCandidate& c) {
  std::error_code ec;
  fs::remove(c.autosave_file, ec);
  fs::remove(c.lock_file, ec);
}

}  // namespace pliant::editor
