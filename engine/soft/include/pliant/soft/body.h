// From a triangle mesh to a simulatable body: cheap repair (weld vertices, drop
// degenerate faces), then a hexahedral lattice fitted to the shape with the surface
// embedded by trilinear weights (ALGORITHMS.md section 3, "embedding is the robust
// default"). A cell is solid when the generalized winding number at its centre is
// above 1/2 (Jacobson et al. 2013; robust to open, non-manifold and self-intersecting
// meshes) or when the surface passes through it (thin sheets and open parts still get
// cells). Face-connected solid cells form pieces; the largest is kept, and vertices of
// the dropped pieces are attached to the nearest kept cell (reported).
#pragma once
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "pliant/geom/triangle_mesh.h"

namespace pliant::soft {

struct SurfaceMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

struct RepairReport {
  int welded_vertices = 0;     // vertices merged into an earlier one
  int dropped_triangles = 0;   // zero-area or repeated-index triangles
  int unused_vertices = 0;     // removed because no triangle uses them
};

// Welds vertices closer than weld_tol_rel times the bounding-box diagonal, drops
// degenerate triangles and unused vertices. Throws BodyError when no triangle with
// area is left or the extent is absurd (below 1e-4 m or above 1e4 m after scaling).
SurfaceMesh repair_mesh(const geom::TriangleMesh& in, RepairReport* report = nullptr,
                        double weld_tol_rel = 1e-7);

// Generalized winding number of a closed or open triangle soup at p (1 inside a
// closed outward-oriented mesh, 0 outside, fractional near holes).
double winding_number(const SurfaceMesh& m, const Eigen::Vector3d& p);

// Hexahedral lattice. Node a of a cell is corner (a&1, (a>>1)&1, (a>>2)&1).
struct Lattice {
  double cell_size_m = 0;
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();   // corner of grid cell (0,0,0)
  std::vector<Eigen::Vector3d> rest;                    // node rest positions
  std::vector<std::array<int, 8>> cells;                // node ids per cell
  std::vector<std::array<int, 3>> cell_ijk;
  std::vector<std::array<int, 4>> boundary_faces;       // quads, counter-clockwise seen from outside
  std::vector<double> node_mass_kg;                     // lumped
  // Surface embedding: vertex v = sum_a w[v][a] * node[cells[vertex_cell[v]][a]].
  std::vector<int> vertex_cell;
  std::vector<std::array<double, 8>> vertex_weight;
  int pieces_found = 0, pieces_dropped = 0;
  int nodes() const { return int(rest.size()); }
};

// `resolution` cells along the longest bounding-box axis (2..128). density in kg/m^3.
Lattice build_lattice(const SurfaceMesh& mesh, int resolution, double density_kg_per_m3);

// Surface vertex positions for lattice node positions x (3 * nodes, xyz per node).
void embed_surface(const Lattice& lat, const Eigen::VectorXd& x, std::vector<Eigen::Vector3d>& out);

// The transpose of the embedding for one vertex: adds a force (N) acting at surface
// vertex `vertex` to the nodal forces f (3 * nodes) as weight_a * force on the 8
// nodes of its cell. The weights sum to one and the vertex is the same weighted sum
// of those nodes, so the total force is `force` and its torque about the vertex is
// zero: the point force's force and moment, exactly, in any shape of the lattice
// (virtual work: f . dx = force . dvertex). f of the wrong size is resized to zeros
// (the only allocation). Throws std::out_of_range for a vertex not embedded.
void add_vertex_force(const Lattice& lat, int vertex, const Eigen::Vector3d& force, Eigen::VectorXd& f);

class BodyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace pliant::soft
