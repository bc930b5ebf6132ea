// A 2D coverage image: width x height values in 0..1, row 0 at the TOP (image
// convention), sampled bilinearly. Built from an image file (grey or alpha
// channel, via stb_image) or from text (stb_truetype).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace pliant::geom {

struct CoverageImage {
  int width = 0, height = 0;
  std::vector<float> value;  // row-major, row 0 on top
  float at(int x, int y) const { return value[size_t(y) * width + x]; }
  // Bilinear sample at normalised (s, t) in [0,1]^2 (t = 0 on top); 0 outside.
  double sample(double s, double t) const;
};

enum class ImageChannel { Luma, Alpha };

// `label` is the path as the user wrote it (used in messages). Luma: Rec. 601 grey
// of RGB (times alpha when the image has one, so transparent pixels are empty).
CoverageImage load_coverage_image(const std::filesystem::path& file, const std::string& label,
                                  ImageChannel channel);
// Values >= threshold become 1, the others 0. Throws GeomError("<label>: mask is
// empty after thresholding at <t>") when nothing is left.
void threshold_coverage(CoverageImage& img, double threshold, const std::string& label);
// Renders `text` (UTF-8, one line) with the TrueType font at pixel_height pixels per
// em, tightly cropped with a 1-pixel margin. Throws GeomError on an empty text, an
// unreadable font or glyphs that render nothing.
// The shipped default font (assets/fonts/DejaVuSans-Bold.ttf): looked up beside a
// scene folder first (<scene_dir>/../fonts/), then in the source tree it was built from.
std::filesystem::path default_font_path(const std::filesystem::path& scene_dir);
CoverageImage render_text(const std::string& text, const std::filesystem::path& font_file,
                          const std::string& font_label, int pixel_height = 128);

}  // namespace pliant::geom
