// Running UI scripts one UI frame at a time (see ui_script.h).
#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <thread>

#include "render/screenshot.h"
#include "ui/app.h"
#include "ui/ui_script.h"

namespace pliant::editor {

namespace fs = std::filesystem;

namespace {

enum class Step { Wait, Done, DoneInstant };

float num(const std::string& s) { return std::strtof(s.c_str(), nullptr); }

// Headless frames do not wait for vsync: while a job works, leave it the CPU.
void yield_cpu() { std::this_thread::sleep_for(std::chrono::milliseconds(15)); }

// "CTRL+SHIFT+Z" -> modifiers + key index; false if the key is unknown.
bool parse_key(const std::string& spec, InjectedInput& in, int* key) {
  std::string up = spec;
  std::transform(up.begin(), up.end(), up.begin(), [](unsigned char c) { return std::toupper(c); });
  std::vector<std::string> parts;
  std::stringstream ss(up);
  for (std::string p; std::getline(ss, p, '+');) parts.push_back(p);
  if (parts.empty()) return false;
  bool ctrl = false, shift = false, alt = false;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    if (parts[i] == "CTRL") ctrl = true;
    else if (parts[i] == "SHIFT") shift = true;
    else if (parts[i] == "ALT") alt = true;
    else return false;
  }
  *key = key_index_from_name(parts.back());
  if (*key < 0) return false;
  in.ctrl = ctrl;
  in.shift = shift;
  in.alt = alt;
  return true;
}

}  // namespace

ScriptRunner::ScriptRunner(Script script, fs::path tmp_dir)
    : script_(std::move(script)), tmp_(std::move(tmp_dir)) {}

void ScriptRunner::attach(App& app) {
  app.input.active = true;
  app.before_frame = [this](App& a) { step(a); };
  app.after_render = [this](App& a) { after_render(a); };
}

std::string ScriptRunner::resolve(const std::string& path) const {
  std::string p = path;
  for (size_t k; (k = p.find("$TMP")) != std::string::npos;) p.replace(k, 4, tmp_.string());
  fs::path fp(p);
  return fp.is_absolute() ? fp.string() : (script_.dir / fp).lexically_normal().string();
}

void ScriptRunner::fail(const ScriptCommand& c, const std::string& msg) {
  failed_ = true;
  error_ = script_.file + ":" + std::to_string(c.line) + ": " + c.op + ": " + msg;
}

void ScriptRunner::next() {
  ++pc_;
  phase_ = 0;
}

void ScriptRunner::step(App& app) {
  // Instant commands (expect, wait 0...) run back to back within one frame.
  for (int guard = 0; guard < 1000 && !finished(); ++guard) {
    const ScriptCommand& c = script_.commands[pc_];
    if (phase_ == 0) started_ = std::chrono::steady_clock::now();
    bool done = run_command(app, c);
    if (failed_) return;
    if (!done) {
      ++phase_;
      return;
    }
    bool instant = phase_ < 0;  // run_command marks instant completion with phase_ = -1
    next();
    if (!instant) return;
  }
}

bool ScriptRunner::run_command(App& app, const ScriptCommand& c) {
  InjectedInput& in = app.input;
  const auto& a = c.args;
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  };
  auto instant = [&] {
    phase_ = -1;
    return true;
  };
  // A click at (x0_, y0_): move, press, release (and again for a double click).
  auto click_phases = [&](int k, bool dbl) {
    if (k == 0) {
      in.mouse_x = x0_;
      in.mouse_y = y0_;
      return false;
    }
    bool press = k == 1 || (dbl && k == 3);
    in.mouse_down[button_] = press;
    return k >= (dbl ? 4 : 2);
  };
  auto drag_phases = [&](int k) {
    if (k == 0) {
      in.mouse_x = x0_;
      in.mouse_y = y0_;
      return false;
    }
    if (k == 1) {
      in.mouse_down[button_] = true;
      return false;
    }
    if (k <= frames_ + 1) {
      float t = static_cast<float>(k - 1) / frames_;
      in.mouse_x = x0_ + (x1_ - x0_) * t;
      in.mouse_y = y0_ + (y1_ - y0_) * t;
      return false;
    }
    in.mouse_down[button_] = false;
    return true;
  };
  // Finds a marked item, waiting a few frames for it to appear.
  // The rectangle must be the same on two frames in a row: windows that size
  // themselves (popups) settle over a couple of frames.
  auto locate = [&](const std::string& label, const UiRect** r) {
    *r = app.marks.find(label);
    if (*r) {
      const UiRect& q = **r;
      bool stable = phase_ > 0 && have_last_ && q.x0 == last_.x0 && q.y0 == last_.y0 &&
                    q.x1 == last_.x1 && q.y1 == last_.y1;
      last_ = q;
      have_last_ = true;
      if (!stable) *r = nullptr;
    } else {
      have_last_ = false;
    }
    if (!*r && phase_ > 30) {
      std::string known;
      for (const auto& [k, v] : app.marks.last_frame()) known += (known.empty() ? "" : ", ") + k;
      fail(c, "no item '" + label + "' in the last frame (marked items: " + known + ")");
    }
    return *r != nullptr;
  };

  if (c.op == "move") {
    in.mouse_x = num(a[0]);
    in.mouse_y = num(a[1]);
    return true;
  }
  if (c.op == "click") {
    if (phase_ == 0) {
      size_t first = 0;
      button_ = 0;
      if (a.size() == 1 || a.size() == 3) {
        button_ = a[0] == "right" ? 1 : a[0] == "middle" ? 2 : 0;
        first = 1;
      }
      x0_ = a.size() >= first + 2 ? num(a[first]) : in.mouse_x;
      y0_ = a.size() >= first + 2 ? num(a[first + 1]) : in.mouse_y;
    }
    return click_phases(phase_, false);
  }
  if (c.op == "drag") {
    if (phase_ == 0) {
      x0_ = num(a[0]), y0_ = num(a[1]), x1_ = num(a[2]), y1_ = num(a[3]);
      frames_ = std::max(1, a.size() > 4 ? static_cast<int>(num(a[4])) : 10);
      button_ = a.size() > 5 ? (a[5] == "right" ? 1 : a[5] == "middle" ? 2 : 0) : 0;
    }
    return drag_phases(phase_);
  }
  if (c.op == "scroll") {
    in.wheel = num(a[0]);
    return true;
  }
  if (c.op == "key") {
    if (phase_ == 0) {
      int k = -1;
      if (!parse_key(a[0], in, &k)) {
        fail(c, "unknown key '" + a[0] + "'");
        return false;
      }
      in.keys_down = {k};
      return false;
    }
    in.keys_down.clear();
    in.ctrl = in.shift = in.alt = false;
    return true;
  }
  if (c.op == "type") {
    in.chars = a[0];
    for (size_t k; (k = in.chars.find("$TMP")) != std::string::npos;) in.chars.replace(k, 4, tmp_.string());
    return true;
  }
  if (c.op == "wait") {
    return phase_ >= static_cast<int>(num(a[0])) ? instant() : false;
  }
  if (c.op == "wait_job") {
    double timeout = a.empty() ? 60 : num(a[0]);
    JobProcess* j = app.newest_job();
    if (!j) {
      fail(c, "no job was started");
      return false;
    }
    JobStatus st = j->snapshot();
    if (st.ended() && st.exit_code >= 0) return true;  // next frame: the app has logged it
    yield_cpu();
    if (elapsed() > timeout)
      fail(c, "job still " + std::string(job_state_name(st.state)) + " after " +
                  std::to_string(timeout) + " s");
    return false;
  }
  if (c.op == "wait_frames") {
    int n = static_cast<int>(num(a[0]));
    double timeout = a.size() > 1 ? num(a[1]) : 60;
    if (app.take.frame_count() >= n) return true;
    yield_cpu();
    if (elapsed() > timeout)
      fail(c, "the take has " + std::to_string(app.take.frame_count()) + " frames, not " + a[0] +
                  ", after " + std::to_string(timeout) + " s");
    return false;
  }
  if (c.op == "click_item") {
    // phase_ counts frames; base frames_ remembers when the item was found.
    if (phase_ == 0) frames_ = -1;
    if (frames_ < 0) {
      const UiRect* r;
      if (!locate(a[0], &r)) return false;
      frames_ = phase_;
      x0_ = r->cx();
      y0_ = r->cy();
      std::string kind = a.size() > 1 ? a[1] : "left";
      button_ = kind == "right" ? 1 : 0;
    }
    return click_phases(phase_ - frames_, a.size() > 1 && a[1] == "double");
  }
  if (c.op == "drag_item") {
    if (phase_ == 0) button_ = -1;
    if (button_ < 0) {
      const UiRect* r;
      if (!locate(a[0], &r)) return false;
      x0_ = r->cx();
      y0_ = r->cy();
      x1_ = x0_ + num(a[1]);
      y1_ = y0_ + num(a[2]);
      frames_ = std::max(1, a.size() > 3 ? static_cast<int>(num(a[3])) : 10);
      button_ = 0;
      y_base_ = phase_;
    }
    return drag_phases(phase_ - y_base_);
  }
  if (c.op == "drag_item_at" || c.op == "click_item_at") {
    const bool is_click = c.op == "click_item_at";
    if (phase_ == 0) button_ = -1;
    if (button_ < 0) {
      const UiRect* r;
      if (!locate(a[0], &r)) return false;
      auto px = [&](const std::string& f) { return r->x0 + (r->x1 - r->x0) * num(f); };
      auto py = [&](const std::string& f) { return r->y0 + (r->y1 - r->y0) * num(f); };
      x0_ = px(a[1]);
      y0_ = py(a[2]);
      x1_ = is_click ? x0_ : px(a[3]);
      y1_ = is_click ? y0_ : py(a[4]);
      frames_ = is_click ? 1 : std::max(1, a.size() > 5 ? static_cast<int>(num(a[5])) : 10);
      button_ = 0;
      y_base_ = phase_;
    }
    return is_click ? click_phases(phase_ - y_base_, false) : drag_phases(phase_ - y_base_);
  }
  if (c.op == "export") {
    // Through the menu's dialog: the same path a person takes.
    if (phase_ == 0) {
      app.open_file_dialog(a[0] == "png"         ? FileDialog::Mode::ExportPng
                           : a[0] == "mp4"       ? FileDialog::Mode::ExportMp4
                           : a[0] == "particles" ? FileDialog::Mode::ExportParticles
                           : a[0] == "obj"       ? FileDialog::Mode::ExportObj
                           : a[0] == "csv"       ? FileDialog::Mode::ExportCsv
                                                 : FileDialog::Mode::ExportVdb);
      std::snprintf(app.file_dialog.path, sizeof app.file_dialog.path, "%s", resolve(a[1]).c_str());
      return false;
    }
    if (phase_ < 3) return false;  // the popup opens
    const UiRect* r;
    if (phase_ == 3) frames_ = -1;
    if (frames_ < 0) {
      if (!locate("dialog_ok", &r)) return false;
      frames_ = phase_;
      x0_ = r->cx();
      y0_ = r->cy();
      button_ = 0;
    }
    return click_phases(phase_ - frames_, false);
  }
  if (c.op == "wait_export") {
    double timeout = a.empty() ? 60 : num(a[0]);
    if (!app.export_run) {
      fail(c, "no export was started");
      return false;
    }
    if (app.export_run->done()) {
      if (!app.export_run->ok()) fail(c, app.export_run->message());
      return !failed_;
    }
    yield_cpu();
    if (elapsed() > timeout) fail(c, "export still running after " + std::to_string(timeout) + " s");
    return false;
  }
  if (c.op == "set_frame") {
    int target = static_cast<int>(num(a[0]));
    if (phase_ == 0) {
      button_ = -1;
      y_base_ = 0;
    }
    if (button_ < 0) {
      const UiRect* r;
      if (!locate("frame_slider", &r)) return false;
      int n = app.take.frame_count();
      if (n <= 0) {
        fail(c, "the take has no frames");
        return false;
      }
      if (target < 0 || target >= n) {
        fail(c, "frame " + a[0] + " is outside 0.." + std::to_string(n - 1));
        return false;
      }
      float t = n > 1 ? static_cast<float>(target) / (n - 1) : 0;
      x0_ = r->x0 + 6;
      y0_ = r->cy();
      x1_ = r->x0 + 6 + (r->x1 - r->x0 - 12) * t;
      y1_ = y0_;
      frames_ = 8;
      button_ = 0;
      y_base_ = phase_;
    }
    int k = phase_ - y_base_;
    if (k <= frames_ + 2) {
      drag_phases(k);
      return false;
    }
    // Then arrow keys, as a person nudges the slider to the exact frame.
    int j = k - frames_ - 3;
    if (j % 2 == 1) {
      in.keys_down.clear();
      return false;
    }
    if (app.take.frame == target) return true;
    if (j > 200) {
      fail(c, "could not reach frame " + a[0] + " (at " + std::to_string(app.take.frame) + ")");
      return false;
    }
    in.keys_down = {key_index_from_name(app.take.frame < target ? "RIGHT" : "LEFT")};
    return false;
  }
  if (c.op == "screenshot") {
    pending_shot_ = resolve(a[0]);
    pending_viewport_ = a.size() > 1 || app.options().viewport_only;
    return true;
  }
  if (c.op == "drop") {
    std::vector<std::string> paths;
    for (const auto& p : a) paths.push_back(resolve(p));
    app.platform().inject_drop(paths);
    return true;
  }
  if (c.op == "expect") {
    if (app.log.contains(a[0]) || app.status().find(a[0]) != std::string::npos) return instant();
    fail(c, "no log line or status contains '" + a[0] + "' (status: '" + app.status() + "')");
    return false;
  }
  if (c.op == "expect_json") {
    auto want = nlohmann::json::parse(a[1]);
    nlohmann::json::json_pointer p(a[0]);
    if (!app.doc.scene().contains(p)) {
      fail(c, a[0] + " is missing");
      return false;
    }
    const auto& got = app.doc.scene().at(p);
    if (got != want) {
      fail(c, a[0] + " is " + got.dump() + ", expected " + want.dump());
      return false;
    }
    return instant();
  }
  if (c.op == "quit") {
    quit_ = true;
    app.request_quit();
    return true;
  }
  fail(c, "unknown command (the parser should have refused it)");
  return false;
}

void ScriptRunner::after_render(App& app) {
  if (pending_shot_.empty()) return;
  Image img = pending_viewport_ ? app.capture_viewport() : app.capture_window();
  std::string err;
  std::error_code ec;
  fs::create_directories(fs::path(pending_shot_).parent_path(), ec);
  if (img.empty()) {
    failed_ = true;
    error_ = "screenshot " + pending_shot_ + ": nothing to capture (no GL?)";
  } else if (!write_png(pending_shot_, img, &err)) {
    failed_ = true;
    error_ = "screenshot: " + err;
  } else {
    shots_.push_back(pending_shot_);
  }
  pending_shot_.clear();
}

}  // namespace pliant::editor
