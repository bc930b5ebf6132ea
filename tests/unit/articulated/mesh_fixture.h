// A closed box mesh written to a temporary OBJ file (mesh geom tests).
#pragma once
#include <array>
#include <filesystem>
#include <map>
#include <sstream>
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

// Box of half sizes (hx, hy, hz) about the origin, each face an n x n grid of cells
// (12 n^2 triangles, vertices shared), outward-facing: a finer mesh for mesh-mesh tests.
inline std::string write_grid_box_obj(const std::string& stem, double hx, double hy, double hz, int n) {
  const auto path = std::filesystem::temp_directory_path() / (stem + "_" + std::to_string(::getpid()) + ".obj");
  std::ofstream out(path);
  std::map<std::array<int, 3>, int> index;  // lattice point (0..n per axis) -> 1-based vertex
  const double h[3] = {hx, hy, hz};
  const auto vertex = [&](std::array<int, 3> l) {
    auto it = index.find(l);
    if (it != index.end()) return it->second;
    const int id = static_cast<int>(index.size()) + 1;
    index[l] = id;
    out << "v";
    for (int a = 0; a < 3; ++a) out << " " << h[a] * (2.0 * l[a] / n - 1);
    out << "\n";
    return id;
  };
  std::ostringstream faces;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;  // e_u x e_v = e_a
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          int c[4];
          const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            std::array<int, 3> l;
            l[a] = side * n;
            l[u] = i + di[k];
            l[v] = j + dj[k];
            c[k] = vertex(l);
          }
          if (side == 1)
            faces << "f " << c[0] << " " << c[1] << " " << c[2] << "\nf " << c[0] << " " << c[2] << " " << c[3] << "\n";
          else
            faces << "f " << c[0] << " " << c[2] << " " << c[1] << "\nf " << c[0] << " " << c[3] << " " << c[2] << "\n";
        }
    }
  out << faces.str();
  return path.string();
}

}  // namespace pliant::articulated::test
