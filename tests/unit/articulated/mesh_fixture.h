// A closed box mesh written to a temporary OBJ file (mesh geom tests).
#pragma once
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace pliant::articulated::test {

// Box of half sizes (hx, hy, hz) centred at (cx, cy, cz), outward-facing triangles.
inline std::string write_box_obj(const std::string& stem, double hx, double hy, double hz, double cx = 0,
                                 double cy = 0, double cz = 0) {
  const auto path = std::filesystem::temp_directory_path() / (stem + "_" + std::to_string(::getpid()) + ".obj");
  std::ofstream out(path);
  for (int i = 0; i < 8; ++i)
    out << "v " << cx + (i & 1 ? hx : -hx) << " " << cy + (i & 2 ? hy : -hy) << " " << cz + (i & 4 ? hz : -hz) << "\n";
  // Faces (1-based), counter-clockwise seen from outside.
  const int f[12][3] = {{1, 3, 4}, {1, 4, 2}, {5, 6, 8}, {5, 8, 7}, {1, 2, 6}, {1, 6, 5},
                        {3, 7, 8}, {3, 8, 4}, {1, 5, 7}, {1, 7, 3}, {2, 4, 8}, {2, 8, 6}};
  for (const auto& t : f) out << "f " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return path.string();
}

}  // namespace pliant::articulated::test
