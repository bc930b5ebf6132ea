// Reading pixels back from GL and PNG files in and out (stb_image / stb_image_write).
#pragma once
#include <string>

#include "render/image.h"

namespace pliant::editor {

// Reads RGBA8 pixels of framebuffer `fbo` (0 = window) in the rectangle with
// lower-left corner (x, y); the result has top-down rows. Needs a current GL context.
Image read_framebuffer(unsigned fbo, int x, int y, int w, int h);

// Writes an RGBA PNG; false with *err naming the path on failure. Creates no folders.
bool write_png(const std::string& path, const Image& img, std::string* err = nullptr);
// Reads a PNG (any channel count, converted to RGBA8); an empty Image with *err on failure.
Image read_png(const std::string& path, std::string* err = nullptr);

}  // namespace pliant::editor
