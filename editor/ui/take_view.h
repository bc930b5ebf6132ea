// The take shown in the viewport and timeline: a TakeReader refreshed every UI
// frame (cheap when nothing changed), the current frame and playback state.
// While the take is running the view follows the newest frame until the user
// scrubs.
#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "pliant/core/take.h"

namespace pliant::editor {

class TakeView {
 public:
  // Points at a take folder; the reader opens once take.json exists.
  void open(const std::filesystem::path& dir);
  void close();
  // Opens/refreshes the reader; advances playback by dt_s. Returns true when
  // the frame to show changed (or new data arrived for it).
  void update(double dt_s);

  bool is_open() const { return reader_ != nullptr; }
  const std::filesystem::path& dir() const { return dir_; }
  TakeReader* reader() { return reader_.get(); }
  int frame_count() const;
  std::string status() const;  // manifest status or "" when not open

  int frame = 0;            // index into the take's frames
  bool playing = false;
  bool loop = true;
  float fps = 25.0f;
  bool user_scrubbed = false;  // stops following the newest frame
  void step(int delta);         // a user step (scrubs)
  void set_frame(int n);        // clamps; a user scrub
  const std::string& error() const { return error_; }

 private:
  std::filesystem::path dir_;
  std::unique_ptr<TakeReader> reader_;
  std::string error_;
  double play_accum_ = 0;
  bool was_running_ = false;
};

}  // namespace pliant::editor
