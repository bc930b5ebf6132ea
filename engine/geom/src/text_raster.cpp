// Text rendered with stb_truetype into a coverage image (one line, kerning applied,
// glyph bitmaps combined with max so overlapping glyphs do not exceed 1).
#include <stb/stb_truetype.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

#include "pliant/geom/coverage_image.h"
#include "pliant/geom/raster_grid.h"

namespace pliant::geom {
namespace {

// Minimal UTF-8 decoder (invalid bytes become U+FFFD).
std::vector<int> decode_utf8(const std::string& s) {
  std::vector<int> out;
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = s[i];
    int cp = 0xFFFD, len = 1;
    if (c < 0x80) cp = c;
    else if ((c >> 5) == 6) len = 2, cp = c & 0x1F;
    else if ((c >> 4) == 14) len = 3, cp = c & 0x0F;
    else if ((c >> 3) == 30) len = 4, cp = c & 0x07;
    if (len > 1) {
      if (i + len > s.size()) {
        cp = 0xFFFD;
        len = 1;
      } else {
        for (int k = 1; k < len; ++k) cp = (cp << 6) | (s[i + k] & 0x3F);
      }
    }
    out.push_back(cp);
    i += len;
  }
  return out;
}

}  // namespace

std::filesystem::path default_font_path(const std::filesystem::path& scene_dir) {
  const std::filesystem::path beside = scene_dir / ".." / "fonts" / "DejaVuSans-Bold.ttf";
  std::error_code ec;
  if (std::filesystem::exists(beside, ec)) return beside;
  return PLIANT_DEFAULT_FONT;
}

CoverageImage render_text(const std::string& text, const std::filesystem::path& font_file,
                          const std::string& font_label, int pixel_height) {
  if (text.empty()) throw GeomError("text \"\": empty text");
  std::ifstream in(font_file, std::ios::binary);
  if (!in) throw GeomError(font_label + ": cannot read font: file not found or not readable");
  const std::vector<unsigned char> font((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  stbtt_fontinfo info;
  const int offset = stbtt_GetFontOffsetForIndex(font.data(), 0);
  if (offset < 0 || !stbtt_InitFont(&info, font.data(), offset))
    throw GeomError(font_label + ": cannot read font: not a TrueType font");
  const float scale = stbtt_ScaleForPixelHeight(&info, float(pixel_height));
  int ascent = 0, descent = 0, gap = 0;
  stbtt_GetFontVMetrics(&info, &ascent, &descent, &gap);
  const std::vector<int> cps = decode_utf8(text);

  // Pass 1: pen positions and the ink bounding box (baseline at y = 0, y down).
  struct Glyph { int cp; double x; int x0, y0, x1, y1; };
  std::vector<Glyph> glyphs;
  double pen = 0;
  int bx0 = 1 << 30, by0 = 1 << 30, bx1 = -(1 << 30), by1 = -(1 << 30);
  for (size_t i = 0; i < cps.size(); ++i) {
    int adv = 0, lsb = 0;
    stbtt_GetCodepointHMetrics(&info, cps[i], &adv, &lsb);
    int x0, y0, x1, y1;
    stbtt_GetCodepointBitmapBox(&info, cps[i], scale, scale, &x0, &y0, &x1, &y1);
    const int px = int(std::floor(pen));
    glyphs.push_back({cps[i], pen, x0, y0, x1, y1});
    if (x1 > x0 && y1 > y0) {
      bx0 = std::min(bx0, px + x0);
      bx1 = std::max(bx1, px + x1);
      by0 = std::min(by0, y0);
      by1 = std::max(by1, y1);
    }
    pen += adv * scale;
    if (i + 1 < cps.size()) pen += scale * stbtt_GetCodepointKernAdvance(&info, cps[i], cps[i + 1]);
  }
  if (bx1 <= bx0 || by1 <= by0) throw GeomError("text \"" + text + "\": renders no visible glyphs");

  CoverageImage img;
  const int margin = 1;
  img.width = bx1 - bx0 + 2 * margin;
  img.height = by1 - by0 + 2 * margin;
  img.value.assign(size_t(img.width) * img.height, 0.0f);
  std::vector<unsigned char> bmp;
  for (const Glyph& gl : glyphs) {
    const int w = gl.x1 - gl.x0, h = gl.y1 - gl.y0;
    if (w <= 0 || h <= 0) continue;
    bmp.assign(size_t(w) * h, 0);
    const int px = int(std::floor(gl.x));
    stbtt_MakeCodepointBitmapSubpixel(&info, bmp.data(), w, h, w, scale, scale, float(gl.x - px), 0.0f, gl.cp);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int X = px + gl.x0 + x - bx0 + margin, Y = gl.y0 + y - by0 + margin;
        if (X < 0 || Y < 0 || X >= img.width || Y >= img.height) continue;
        float& v = img.value[size_t(Y) * img.width + X];
        v = std::max(v, bmp[size_t(y) * w + x] / 255.0f);
      }
  }
  return img;
}

}  // namespace pliant::geom
