#include "pressure_projection.h"

#include <algorithm>
#include <cmath>

namespace pliant::smoke {
namespace {

// Fixed summation order (poisson.h): the same bits on any number of threads.
double dot(const double* a, const double* b, size_t n) {
  return fixed_order_block_sum(n, n >= kOmpMinCells, [a, b](size_t i0, size_t i1) {
    double s = 0;
    for (size_t i = i0; i < i1; ++i) s += a[i] * b[i];
    return s;
  });
}

}  // namespace

PoissonSolver::PoissonSolver(const MacGrid& g) {
  PoissonLevel shape;
  shape.dim = g.dim;
  shape.n = g.n;
  shape.periodic = g.periodic;
  for (;;) {
    Level L;
    L.shape = shape;
    const size_t n = shape.cells();
    L.x.assign(n, 0.0);
    L.b.assign(n, 0.0);
    L.r.assign(n, 0.0);
    levels_.push_back(std::move(L));
    if (!shape.coarsenable()) break;
    for (int a = 0; a < shape.dim; ++a) shape.n[a] /= 2;
  }
  // Coarsest level: enough symmetric sweeps to propagate information across it.
  Level& c = levels_.back();
  const int extent = *std::max_element(c.shape.n.begin(), c.shape.n.begin() + c.shape.dim);
  c.coarse_sweeps = std::min(100, 2 * extent + 4);
  const size_t n = cells();
  inv_diag_.resize(n);
  poisson_diagonal(levels_[0].shape, inv_diag_.data());
  for (double& d : inv_diag_) d = 1.0 / d;
  r_.assign(n, 0.0);
  z_.assign(n, 0.0);
  d_.assign(n, 0.0);
  q_.assign(n, 0.0);
}

void PoissonSolver::smooth(Level& L, int sweeps, bool forward) {
  if (!L.shape.red_black_ok()) {
    const double omega = 2.0 / 3.0;
    for (int s = 0; s < sweeps; ++s) poisson_jacobi_sweep(L.shape, L.b.data(), L.x.data(), L.r.data(), omega);
    return;
  }
  const int first = forward ? 0 : 1;
  for (int s = 0; s < sweeps; ++s) {
    poisson_gauss_seidel_colour(L.shape, L.b.data(), L.x.data(), first);
    poisson_gauss_seidel_colour(L.shape, L.b.data(), L.x.data(), 1 - first);
  }
}

void PoissonSolver::vcycle(int l) {
  Level& L = levels_[l];
  const size_t nl = L.shape.cells();
  double* lx = L.x.data();
#pragma omp parallel for schedule(static) if (nl >= kOmpMinCells)
  for (size_t c = 0; c < nl; ++c) lx[c] = 0.0;
  if (l + 1 == int(levels_.size())) {
    smooth(L, L.coarse_sweeps, true);
    smooth(L, L.coarse_sweeps, false);
    return;
  }
  smooth(L, pre_sweeps, true);
  poisson_residual(L.shape, L.b.data(), L.x.data(), L.r.data());
  Level& C = levels_[l + 1];
  poisson_restrict(L.shape, C.shape, L.r.data(), C.b.data());
  vcycle(l + 1);
  poisson_prolong_add(L.shape, C.shape, C.x.data(), L.x.data());
  smooth(L, post_sweeps, false);
}

void PoissonSolver::precondition(PoissonMethod method, const double* r, double* z) {
  const size_t n = cells();
  if (method == PoissonMethod::JacobiPCG) {
#pragma omp parallel for schedule(static)
    for (size_t c = 0; c < n; ++c) z[c] = r[c] * inv_diag_[c];
  } else {
    Level& L = levels_[0];
    double* lb = L.b.data();
#pragma omp parallel for schedule(static) if (n >= kOmpMinCells)
    for (size_t c = 0; c < n; ++c) lb[c] = r[c];
    remove_mean(lb, n);
    vcycle(0);
    const double* lx = L.x.data();
#pragma omp parallel for schedule(static) if (n >= kOmpMinCells)
    for (size_t c = 0; c < n; ++c) z[c] = lx[c];
  }
  remove_mean(z, n);  // keep the search directions out of the null space
}

PoissonStats PoissonSolver::solve(PoissonMethod method, double* b, double* x, double tolerance,
                                  int max_iterations) {
  const size_t n = cells();
  const PoissonLevel& shape = levels_[0].shape;
  remove_mean(b, n);
  PoissonStats st;
  const double bnorm = std::sqrt(dot(b, b, n));
  if (bnorm == 0.0 || !std::isfinite(bnorm)) {
    std::fill(x, x + n, bnorm == 0.0 ? 0.0 : std::nan(""));
    st.relative_residual = bnorm == 0.0 ? 0.0 : std::nan("");
    return st;
  }
  double* r = r_.data();
  double* z = z_.data();
  double* d = d_.data();
  double* q = q_.data();
  double rr = poisson_residual(shape, b, x, r);
  st.relative_residual = std::sqrt(rr) / bnorm;
  if (st.relative_residual <= tolerance) return st;
  precondition(method, r, z);
  std::copy(z, z + n, d);
  double rz = dot(r, z, n);
  for (int it = 1; it <= max_iterations; ++it) {
    poisson_apply(shape, d, q);
    const double alpha = rz / dot(d, q, n);
    rr = fixed_order_block_sum(n, n >= kOmpMinCells, [&](size_t i0, size_t i1) {
      double t = 0;
      for (size_t c = i0; c < i1; ++c) {
        x[c] += alpha * d[c];
        r[c] -= alpha * q[c];
        t += r[c] * r[c];
      }
      return t;
    });
    st.iterations = it;
    st.relative_residual = std::sqrt(rr) / bnorm;
    if (st.relative_residual <= tolerance || !std::isfinite(st.relative_residual)) break;
    precondition(method, r, z);
    const double rz_new = dot(r, z, n);
    const double beta = rz_new / rz;
    rz = rz_new;
#pragma omp parallel for schedule(static)
    for (size_t c = 0; c < n; ++c) d[c] = z[c] + beta * d[c];
  }
  remove_mean(x, n);
  return st;
}

ProjectionStats project(const MacGrid& g, PoissonSolver& solver, PoissonMethod method, double tolerance,
                        int max_iterations, FaceVelocityMut vel, double* phi, double* rhs) {
  ProjectionStats st;
  const size_t n = g.cells();
  divergence(g, vel, rhs);
  double m = 0;
  const double h2 = g.h * g.h;
#pragma omp parallel for schedule(static) reduction(max : m)
  for (size_t c = 0; c < n; ++c) {
    m = std::max(m, std::abs(rhs[c]));
    rhs[c] *= -h2;
  }
  st.max_divergence_before = m;
  const PoissonStats ps = solver.solve(method, rhs, phi, tolerance, max_iterations);
  st.iterations = ps.iterations;
  st.relative_residual = ps.relative_residual;
  subtract_gradient(g, phi, 1.0, vel);
  st.max_divergence_after = max_abs_divergence(g, vel);
  return st;
}

}  // namespace pliant::smoke
