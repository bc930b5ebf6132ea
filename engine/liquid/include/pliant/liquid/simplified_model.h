// The simplified dynamic model of section 2.5: the liquid in the source is
// described by its tilt theta and volume vol only.
//
// Lookup tables per container (built by voxelising the cavity in the container
// frame; for each tilt the voxels are sorted by world height, so the water
// level holding a volume is found exactly by bisection on the sorted heights;
// above the held volume the level rises over the lip, giving the head):
//   dh(theta, vol): height of the free surface above the lowest lip point,
//   A(theta, vol):  area (2D: length) of the opening below the free surface,
//   W(theta, vol):  weir integral over that part of the opening,
//                   int sqrt(2 |g| (level - z)) dA (Torricelli per area element),
//   vmax(theta):    volume held without spilling.
// Outflow: d vol/dt = -Cd W (Bernoulli; Cd is the fitted correction
// coefficient). Outflow parcels leave the lip with speed W / A along the world
// horizontal for theta < 90 deg, else along the wall tangent, plus the lip's
// velocity, and then fly ballistically to the target's rim height.
#pragma once
#include <vector>

#include "pliant/liquid/liquid.h"

namespace pliant::liquid {

struct OutflowTables {
  int dim = 2;
  int n_theta = 0, n_vol = 0;
  double max_theta = 0;   // radians; samples are uniform in [0, max_theta]
  double capacity = 0;    // cavity volume up to the opening (m^3; 2D m^2)
  double g = 9.81;
  // Indexed [it * n_vol + iv], vol = capacity * iv / (n_vol - 1).
  std::vector<double> dh, area, weir;
  std::vector<double> vmax;  // per theta
  // Bilinear look-ups; vol in m^3 (2D m^2), clamped to the table.
  double lookup(const std::vector<double>& t, double theta, double vol) const;
  double max_volume(double theta) const;
};

OutflowTables build_outflow_tables(const ContainerShape& c, int dim, double g, double max_theta_rad,
                                   int n_theta = 61, int n_vol = 41);

struct SimplifiedResult {
  double transferred = 0;  // fraction of the initial volume landing in the target opening
  double spilled = 0;      // fraction poured that misses it
  double remaining = 0;    // fraction left in the source at the end
  double collision = 0;    // penalty: source below the target rim over the target (m^2 s)
};

// Integrates the simplified model along the source trajectory for `duration_s`.
SimplifiedResult simulate_simplified(const LiquidModel& m, const OutflowTables& t, const Trajectory& path,
                                     double duration_s, double discharge_coefficient, double dt_s = 0.01);

}  // namespace pliant::liquid
