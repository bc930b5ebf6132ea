// The 3D keyframe editor's volume view: the keyframe being edited ray marched by
// its own Renderer (the same volume shader as 3D results) into its own FBO, with
// the painted slice (XY, XZ or YZ) outlined; drag it to orbit.
#pragma once
#include <cstdint>

#include "doc/volume_slice.h"
#include "render/offscreen_target.h"
#include "pliant/geom/painted_grid.h"
#include "render/orbit_camera.h"
#include "render/renderer.h"

namespace pliant::editor {

class App;

struct KeyframeVolumeView {
  Renderer renderer;
  bool ready = false;
  std::string error;
  OffscreenTarget target;
  OrbitCamera camera;
  uint64_t uploaded_version = ~uint64_t(0);
  bool dirty = true;  // re-render into the FBO (volume, size or camera changed)
};

// Draws `volume` (dim 3; version = KeyframeCanvasState::volume_version) into the
// rectangle (x, y, w, h) of the current window, with slice `slice` of orientation
// `axis` outlined.
void draw_keyframe_volume(KeyframeVolumeView& v, App& app, const geom::PaintedGrid& volume, uint64_t version,
                          SliceAxis axis, int slice, float x, float y, int w, int h);
void release_volume_view(KeyframeVolumeView& v);

}  // namespace pliant::editor
