#include "ui/take_view.h"

#include <algorithm>

namespace pliant::editor {

namespace fs = std::filesystem;

void TakeView::open(const fs::path& dir) {
  dir_ = dir;
  reader_.reset();
  error_.clear();
  frame = 0;
  playing = false;
  user_scrubbed = false;
  play_accum_ = 0;
  was_running_ = false;
}

void TakeView::close() {
  dir_.clear();
  reader_.reset();
  error_.clear();
}

int TakeView::frame_count() const {
  return reader_ ? static_cast<int>(reader_->frame_count()) : 0;
}

std::string TakeView::status() const { return reader_ ? reader_->manifest().status : ""; }

void TakeView::update(double dt_s) {
  if (dir_.empty()) return;
  if (!reader_) {
    std::error_code ec;
    if (!fs::exists(dir_ / "take.json", ec)) return;
    try {
      reader_ = std::make_unique<TakeReader>(dir_);
      error_.clear();
    } catch (const std::exception& e) {
      error_ = e.what();
      return;
    }
  } else {
    try {
      reader_->refresh();
    } catch (const std::exception& e) {
      error_ = e.what();
    }
  }
  int n = frame_count();
  if (n == 0) {
    frame = 0;
    return;
  }
  if (playing) {
    play_accum_ += dt_s * fps;
    while (play_accum_ >= 1.0) {
      play_accum_ -= 1.0;
      if (frame + 1 < n) {
        ++frame;
      } else if (loop) {
        frame = 0;
      } else {
        playing = false;
        play_accum_ = 0;
        break;
      }
    }
  } else if (!user_scrubbed && (status() == "running" || was_running_)) {
    frame = n - 1;  // follow the newest frame, once more when the job ends
  }
  was_running_ = status() == "running";
  frame = std::clamp(frame, 0, n - 1);
}

void TakeView::step(int delta) { set_frame(frame + delta); }

void TakeView::set_frame(int n) {
  user_scrubbed = true;
  int count = frame_count();
  frame = count > 0 ? std::clamp(n, 0, count - 1) : 0;
}

}  // namespace pliant::editor
