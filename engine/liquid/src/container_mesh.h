// Internal: a container given as a closed triangle mesh (assimp), sampled once
// into a signed distance grid and a cavity mask in the container's frame.
#pragma once
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "pliant/liquid/liquid.h"

namespace pliant::geom {
struct TriangleMesh;
}

namespace pliant::liquid {

// Bad mesh (not closed, no volume, no cavity open at the top): the message is
// the problem, without the file (the caller names it).
class MeshContainerError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MeshContainerField {
  double h = 0.005;                 // sample spacing (m)
  Vec3 lo{0, 0, 0};                 // container-frame position of sample (0, 0, 0)
  std::array<int, 3> n{1, 1, 1};
  std::vector<float> sdf;           // negative inside the material; |d| clamped to `band`
  std::vector<unsigned char> cavity;  // inside the cavity (below the rim)
  std::vector<unsigned char> open_column;  // per (i, k): the cavity reaches the rim there
  double band = 0.02;               // distances are exact within this band
  double reach_m = 0.1;             // bounding-sphere radius about the container origin
  double volume3 = 0, area2 = 0;    // cavity volume (m^3) and z = 0 section area (m^2)
  int index(int i, int j, int k) const { return i + n[0] * (j + n[1] * k); }
  // Trilinear SDF; outside the sampled box, the box value plus the distance to it.
  double distance(const Vec3& p) const;
  bool in_cavity(const Vec3& p) const;
  bool column_open(const Vec3& p) const;
};

// Samples `mesh` (metres after `scale`) at spacing `sample_m`. The container
// frame: origin at the centre of the opening's cavity section, on the cavity
// floor; +y up (the mesh's +y); rim at y = height. Fills shape.height_m,
// radius_m/depth_m (opening half widths), wall_m (wall at the rim, >= one
// sample), and shape.mesh. Throws MeshContainerError.
ContainerShape mesh_container(const geom::TriangleMesh& mesh, double scale, double sample_m);

}  // namespace pliant::liquid
