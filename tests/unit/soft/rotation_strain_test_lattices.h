// Lattices shared by the rotation-strain tests (test_rotation_strain*.cpp).
#pragma once
#include <Eigen/Core>

#include "pliant/geom/triangle_mesh.h"
#include "pliant/soft/body.h"
#include "pliant/soft/fem.h"

namespace pliant::soft::test {

// A 3 x 1 x 1 beam at resolution 6.
inline Lattice beam_lattice() {
  auto cube = pliant::geom::unit_cube_mesh();
  for (auto& v : cube.vertices) v[0] *= 3;  // a 3 x 1 x 1 beam
  return build_lattice(repair_mesh(cube), 6, 1000);
}

// Rest positions with the mass-weighted centroid at 0.
inline Eigen::VectorXd centred_rest(const Lattice& lat) {
  Eigen::VectorXd x(3 * lat.nodes());
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  double m = 0;
  for (int j = 0; j < lat.nodes(); ++j) c += lat.node_mass_kg[j] * lat.rest[j], m += lat.node_mass_kg[j];
  c /= m;
  for (int j = 0; j < lat.nodes(); ++j) x.segment<3>(3 * j) = lat.rest[j] - c;
  return x;
}

}  // namespace pliant::soft::test
