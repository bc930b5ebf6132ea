// Coverage images from files (stb_image, any format it reads: PNG, JPEG, BMP, TGA,
// ...) and bilinear sampling.
#include "pliant/geom/coverage_image.h"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

#include "pliant/geom/raster_grid.h"

namespace pliant::geom {

double CoverageImage::sample(double s, double t) const {
  if (width <= 0 || height <= 0 || s < 0 || s > 1 || t < 0 || t > 1) return 0.0;
  // Pixel centres at (x + 0.5) / width; clamp to the edge pixels inside the image.
  const double x = std::clamp(s * width - 0.5, 0.0, double(width - 1));
  const double y = std::clamp(t * height - 0.5, 0.0, double(height - 1));
  const int x0 = std::min(int(x), std::max(0, width - 2)), y0 = std::min(int(y), std::max(0, height - 2));
  const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const double fx = x - x0, fy = y - y0;
  const double a = at(x0, y0), b = at(x1, y0), c = at(x0, y1), d = at(x1, y1);
  return (1 - fy) * (a + fx * (b - a)) + fy * (c + fx * (d - c));
}

CoverageImage load_coverage_image(const std::filesystem::path& file, const std::string& label,
                                  ImageChannel channel) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw GeomError(label + ": cannot read image: file not found or not readable");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  int w = 0, h = 0, comp = 0;
  unsigned char* px = stbi_load_from_memory(bytes.data(), int(bytes.size()), &w, &h, &comp, 4);
  if (!px) {
    const char* why = stbi_failure_reason();
    throw GeomError(label + ": cannot read image: " + (why ? why : "unknown format"));
  }
  CoverageImage img;
  img.width = w;
  img.height = h;
  img.value.resize(size_t(w) * h);
  const bool has_alpha = comp == 2 || comp == 4;
  if (channel == ImageChannel::Alpha && !has_alpha) {
    stbi_image_free(px);
    throw GeomError(label + ": \"channel\": \"alpha\" but the image has no alpha channel; use \"luma\"");
  }
  for (size_t i = 0; i < img.value.size(); ++i) {
    const unsigned char* p = px + 4 * i;
    const double alpha = p[3] / 255.0;
    const double luma = (0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]) / 255.0;
    img.value[i] = float(channel == ImageChannel::Alpha ? alpha : luma * (has_alpha ? alpha : 1.0));
  }
  stbi_image_free(px);
  return img;
}

void threshold_coverage(CoverageImage& img, double threshold, const std::string& label) {
  bool any = false;
  for (float& v : img.value) {
    v = v >= threshold ? 1.0f : 0.0f;
    any = any || v > 0;
  }
  if (!any) throw GeomError(label + ": mask is empty after thresholding at " + std::to_string(threshold));
}

}  // namespace pliant::geom
