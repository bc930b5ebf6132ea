#include "render_test_util.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include "render/screenshot.h"

namespace pliant::test {

std::string golden_path(const std::string& name) { return std::string(PLIANT_RENDER_GOLDEN_DIR) + "/" + name + ".png"; }
std::string diff_path(const std::string& name) { return std::string(PLIANT_RENDER_OUT_DIR) + "/" + name + "_diff.png"; }

editor::Image render_frame(editor::Platform& platform, editor::Renderer& renderer, const Record& frame,
                           const editor::OrbitCamera& cam, const editor::ViewSettings& view) {
  int w = 0, h = 0;
  platform.framebuffer_size(&w, &h);
  glBindFramebuffer(GL_FRAMEBUFFER, platform.default_framebuffer());
  renderer.set_frame(frame);
  renderer.render(cam, view, w, h);
  return editor::read_framebuffer(platform.default_framebuffer(), 0, 0, w, h);
}

float luma(const editor::Image& img, int x, int y) {
  const uint8_t* p = img.pixel(x, y);
  return 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2];
}

float mean_luma(const editor::Image& img, int x0, int y0, int x1, int y1) {
  double s = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) s += luma(img, x, y);
  return static_cast<float>(s / (double(x1 - x0) * (y1 - y0)));
}

editor::ViewSettings golden_view() {
  editor::ViewSettings v;
  v.density_scale = 1.0f;
  v.show_grid = true;
  v.show_velocity = false;
  v.background = {0.08f, 0.09f, 0.11f};
  v.smoke_color = {0.95f, 0.95f, 1.0f};
  return v;
}

}  // namespace pliant::test
