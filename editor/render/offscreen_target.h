// A framebuffer with a colour texture and a depth-stencil renderbuffer, sized on
// demand. Panels render into it and show the texture with ImGui::Image; the
// viewport, take compare, keyframe volume, character view and rendered export
// all use one.
#pragma once

namespace pliant::editor {

struct OffscreenTarget {
  unsigned fbo = 0, color_tex = 0, depth_rb = 0;
  int w = 0, h = 0;

  // Creates the target or resizes it to w x h (GL context current). Returns
  // true when storage was (re)allocated: the contents are then undefined.
  // Leaves the previously bound framebuffer bound.
  bool ensure(int width, int height);
  // Deletes the GL objects (no-op without a context, see Renderer's destructor).
  void release();
  // Binds the target's framebuffer with a full viewport.
  void bind() const;
};

}  // namespace pliant::editor
