// Advection operators on the MAC grid (plain functions over arrays; callers own
// every buffer, nothing here allocates).
//
// Semi-Lagrangian (Stam 1999): q_new(x) = q(x - dt u(x_mid)), midpoint (RK2)
// backtrace x_mid = x - dt/2 u(x); bilinear/trilinear sampling; backtraced points
// are clamped to the box (closed) or wrapped (periodic). Unconditionally stable,
// not conservative.
//
// Conservative first-order upwind (ALGORITHMS.md section 2, Eq. 3.2 of Pan's
// dissertation): q_new = q - dt div(F), F on each control-volume face = u_face *
// q_upwind. Fluxes through closed walls are zero, periodic fluxes wrap, so sum(q)
// is conserved to round-off. Positivity needs dt * (outflow of a cell)/h <= 1, so
// the step is split into sub-steps (see upwind_substeps).
#pragma once
#include "mac_grid.h"

namespace pliant::smoke {

// Cell-centred scalar: q_out = SL-advect(q_in) by `vel` over dt seconds.
void advect_semi_lagrangian_cells(const MacGrid& g, const FaceVelocity& vel, double dt,
                                  const float* q_in, float* q_out);
// Face velocity advected by itself: out = SL-advect(vel) (closed walls stay 0).
void advect_semi_lagrangian_velocity(const MacGrid& g, const FaceVelocity& vel, double dt,
                                     FaceVelocityMut out);

// Sub-steps so that every cell's outflow satisfies dt_sub * sum_out|u_f| / h <= 1
// (the exact positivity bound of the cell-centred upwind update; it implies the
// textbook dt_sub <= h / max|u| per axis). Capped at `max_substeps`.
int upwind_substeps(const MacGrid& g, const FaceVelocity& vel, double dt, int max_substeps = 1000);

// One upwind flux-form update of an array q with layout `l` (cells or one face
// component), advected by the frozen face velocity `vel` over dt (a single step:
// the caller sub-steps). `scratch` has l.count() values. For face layouts of a
// closed grid the wall faces are left unchanged.
void upwind_step(const MacGrid& g, const FieldLayout& l, const FaceVelocity& vel, double dt,
                 float* q, float* scratch);

// Full upwind advection of a cell-centred scalar over dt with automatic sub-steps.
// Returns the number of sub-steps used.
int advect_upwind_cells(const MacGrid& g, const FaceVelocity& vel, double dt, float* q,
                        float* scratch);
// Upwind advection of the face velocity by itself (frozen copy `vel`, result in
// `out`, which must hold a copy of vel on entry). Returns the sub-steps used.
int advect_upwind_velocity(const MacGrid& g, const FaceVelocity& vel, double dt, FaceVelocityMut out,
                           float* scratch);

}  // namespace pliant::smoke
