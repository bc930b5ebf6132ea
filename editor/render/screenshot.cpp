#include "render/screenshot.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <cstring>

namespace pliant::editor {

Image read_framebuffer(unsigned fbo, int x, int y, int w, int h) {
  Image img;
  if (w <= 0 || h <= 0) return img;
  img.width = w;
  img.height = h;
  img.rgba.resize(static_cast<size_t>(w) * h * 4);
  GLint prev_read = 0, prev_pack = 0;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
  glGetIntegerv(GL_PACK_ALIGNMENT, &prev_pack);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  if (fbo == 0) glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
  glPixelStorei(GL_PACK_ALIGNMENT, prev_pack);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(prev_read));
  // GL rows are bottom-up; flip to top-down.
  const size_t row = static_cast<size_t>(w) * 4;
  std::vector<uint8_t> tmp(row);
  for (int r = 0; r < h / 2; ++r) {
    uint8_t* a = &img.rgba[r * row];
    uint8_t* b = &img.rgba[(h - 1 - r) * row];
    std::memcpy(tmp.data(), a, row);
    std::memcpy(a, b, row);
    std::memcpy(b, tmp.data(), row);
  }
  return img;
}

bool write_png(const std::string& path, const Image& img, std::string* err) {
  if (img.empty() || img.rgba.size() != static_cast<size_t>(img.width) * img.height * 4) {
    if (err) *err = path + ": cannot write an empty or malformed image";
    return false;
  }
  if (!stbi_write_png(path.c_str(), img.width, img.height, 4, img.rgba.data(), img.width * 4)) {
    if (err) *err = path + ": could not write PNG (does the folder exist and is it writable?)";
    return false;
  }
  return true;
}

Image read_png(const std::string& path, std::string* err) {
  Image img;
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
  if (data == nullptr) {
    if (err) *err = path + ": could not read PNG (" + (stbi_failure_reason() ? stbi_failure_reason() : "unknown") + ")";
    return img;
  }
  img.width = w;
  img.height = h;
  img.rgba.assign(data, data + static_cast<size_t>(w) * h * 4);
  stbi_image_free(data);
  return img;
}

}  // namespace pliant::editor
