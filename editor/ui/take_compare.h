// A/B compare: a second take drawn beside the shown one, at the same frame index
// and with the same camera (the viewport splits in two). B is the take of the
// previous job by default; Swap exchanges A and B.
#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "render/offscreen_target.h"
#include "pliant/core/take.h"
#include "render/renderer.h"

namespace pliant::editor {

class App;

struct TakeCompare {
  bool enabled = false;
  std::filesystem::path dir;  // take B
  std::unique_ptr<TakeReader> reader;
  Renderer renderer;
  bool renderer_ready = false;
  OffscreenTarget target;
  int shown_frame = -1;
  size_t shown_count = 0;
  std::string error;

  void open(const std::filesystem::path& take_dir);
  // Draws B at its frame `frame` (clamped) into [pos, pos + (w, h)] of the current window.
  void draw(App& app, float x, float y, int w, int h);
  void release_gl();
};

// The take B to compare against by default: the newest job take other than A, or "".
std::filesystem::path default_compare_take(App& app);

}  // namespace pliant::editor
