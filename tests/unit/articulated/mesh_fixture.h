// A closed box mesh written to a temporary OBJ file (mesh geom tests).
#pragma once
#include <array>
#include <filesystem>
#include <map>
#include <sstream>
#include <fstream>
#include <string>
#include <unistd.h>

#include "pliant/articulated/model.h"

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

// A closed heightfield block in memory: top z = h(x, y) over an n x n grid on
// [-0.5, 0.5]^2 (each cell split along its (i, j)-(i+1, j+1) diagonal), flat bottom
// at z = -0.2, vertical sides; 4 n^2 + 8 n triangles, outward-facing.
template <class Height>
MeshShape terrain_mesh(int n, Height h) {
  MeshShape mesh;
  const auto at = [n](int i) { return -0.5 + double(i) / n; };
  for (int layer = 0; layer < 2; ++layer)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) mesh.vertices.push_back(Vec3(at(i), at(j), layer ? -0.2 : h(at(i), at(j))));
  const auto id = [n](int layer, int i, int j) { return layer * (n + 1) * (n + 1) + j * (n + 1) + i; };
  const auto quad = [&mesh](int a, int b, int c, int d) {  // counter-clockwise from outside
    mesh.triangles.push_back({a, b, c});
    mesh.triangles.push_back({a, c, d});
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      quad(id(0, i, j), id(0, i + 1, j), id(0, i + 1, j + 1), id(0, i, j + 1));
      quad(id(1, i, j), id(1, i, j + 1), id(1, i + 1, j + 1), id(1, i + 1, j));
    }
  for (int i = 0; i < n; ++i) {
    quad(id(1, i, 0), id(1, i + 1, 0), id(0, i + 1, 0), id(0, i, 0));
    quad(id(1, i + 1, n), id(1, i, n), id(0, i, n), id(0, i + 1, n));
    quad(id(1, 0, i + 1), id(1, 0, i), id(0, 0, i), id(0, 0, i + 1));
    quad(id(1, n, i), id(1, n, i + 1), id(0, n, i + 1), id(0, n, i));
  }
  return mesh;
}

}  // namespace pliant::articulated::test
