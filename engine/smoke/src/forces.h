// Body forces and sources applied at the start of each sub-step (explicit Euler on
// the face velocities; smoke_step.cpp orders them before advection/projection).
#pragma once
#include "mac_grid.h"
#include "pliant/smoke/smoke.h"

namespace pliant::smoke {

// True when the point x (metres) lies inside the shape (only the first g.dim
// coordinates are used: a sphere is a circle in 2D).
bool shape_contains(const Shape& s, int dim, const std::array<double, 3>& x);

// Buoyancy along +y: v += dt * b * rho_face (rho averaged over the two cells of the
// face). Closed wall faces are skipped (they stay 0).
void add_buoyancy(const MacGrid& g, double buoyancy_m_per_s2, const float* density, double dt,
                  FaceVelocityMut vel);
// Uniform acceleration (gravity, uniform fields): every face component += dt * a.
void add_uniform_acceleration(const MacGrid& g, const std::array<double, 3>& a, double dt,
                              FaceVelocityMut vel);
// Vortex field: tangential acceleration |a| = strength^2 * d * (1 - d/R) at distance
// d < R from the axis (z axis in 2D, y axis in 3D), counter-clockwise for strength
// > 0. strength_per_s is the angular-rate scale of the swirl; the (1 - d/R) falloff
// makes the field vanish smoothly at the radius and at the centre.
void add_vortex(const MacGrid& g, const ForceField& f, double dt, FaceVelocityMut vel);
// Source: density += density_per_s * dt in the cells whose centres are inside, and
// the face velocities whose positions are inside set to velocity_m_per_s.
void apply_source(const MacGrid& g, const Source& s, double dt, float* density, FaceVelocityMut vel);
// Density 1 in the cells whose centres are inside `shape`.
void fill_shape(const MacGrid& g, const Shape& shape, float* density);

}  // namespace pliant::smoke
