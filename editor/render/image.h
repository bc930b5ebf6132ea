// An 8-bit RGBA image in memory, rows top-down (the order PNG files use).
#pragma once
#include <cstdint>
#include <vector>

namespace pliant::editor {

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4, row 0 is the top row

  bool empty() const { return width <= 0 || height <= 0; }
  const uint8_t* pixel(int x, int y) const { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
  uint8_t* pixel(int x, int y) { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
};

}  // namespace pliant::editor
