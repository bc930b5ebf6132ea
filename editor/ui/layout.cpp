#include <algorithm>
#include <cmath>

#include "ui/panels.h"

namespace pliant::editor {

// Inspector on the left, jobs over log on the right, viewport over timeline in
// the middle; side columns shrink on small windows so 1280x720 still fits.
Layout compute_layout(float width, float height, float menu_h) {
  float left = std::clamp(width * 0.22f, 260.0f, 380.0f);
  float right = std::clamp(width * 0.22f, 260.0f, 380.0f);
  float timeline_h = 124.0f;  // slider + keyframe markers
  float top = menu_h, body_h = std::max(height - menu_h, 100.0f);
  float mid_w = std::max(width - left - right, 100.0f);
  float jobs_h = std::floor(body_h * 0.6f);  // room for the solve panel's curves
  Layout l;
  l.inspector = {0, top, left, body_h};
  l.viewport = {left, top, mid_w, body_h - timeline_h};
  l.timeline = {left, top + body_h - timeline_h, mid_w, timeline_h};
  l.jobs = {left + mid_w, top, right, jobs_h};
  l.log = {left + mid_w, top + jobs_h, right, body_h - jobs_h};
  return l;
}

}  // namespace pliant::editor
