// Shared pieces of the render tests: golden/output paths, rendering one frame
// into the bound platform framebuffer, pixel helpers.
#pragma once
#include <string>

#include "platform/platform.h"
#include "render/image.h"
#include "render/orbit_camera.h"
#include "render/renderer.h"

namespace pliant::test {

inline constexpr int kWidth = 320, kHeight = 240;

std::string golden_path(const std::string& name);  // tests/render/golden/<name>.png
std::string diff_path(const std::string& name);    // <build>/tests/render/out/<name>_diff.png

// Binds the platform's framebuffer, draws `frame` and reads the pixels back.
editor::Image render_frame(editor::Platform& platform, editor::Renderer& renderer, const Record& frame,
                           const editor::OrbitCamera& cam, const editor::ViewSettings& view);

// Rec. 601 luma of a pixel, 0..255.
float luma(const editor::Image& img, int x, int y);
// Mean luma over [x0, x1) x [y0, y1) (top-down rows).
float mean_luma(const editor::Image& img, int x0, int y0, int x1, int y1);

// The settings every golden uses, so goldens do not move when defaults change.
editor::ViewSettings golden_view();

}  // namespace pliant::test
