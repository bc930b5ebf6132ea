#include "poisson.h"

namespace pliant::smoke {
namespace {

// Sum of neighbour values and neighbour count of cell (i,j,k).
struct Neighbours {
  double sum;
  int count;
};
inline Neighbours neighbours(const PoissonLevel& L, const double* x, int i, int j, int k) {
  const int nx = L.n[0], ny = L.n[1], nz = L.n[2];
  const size_t sx = 1, sy = size_t(nx), sz = size_t(nx) * ny;
  const size_t c = i + sy * j + sz * k;
  double s = 0;
  int cnt = 0;
  auto axis = [&](int idx, int n, size_t stride) {
    if (idx > 0) {
      s += x[c - stride];
      ++cnt;
    } else if (L.periodic) {
      s += x[c + stride * (n - 1)];
      ++cnt;
    }
    if (idx < n - 1) {
      s += x[c + stride];
      ++cnt;
    } else if (L.periodic) {
      s += x[c - stride * (n - 1)];
      ++cnt;
    }
  };
  axis(i, nx, sx);
  axis(j, ny, sy);
  if (L.dim == 3) axis(k, nz, sz);
  return {s, cnt};
}

// Calls fn(c, neighbour_sum, neighbour_count) for the cells i = i_start, i_start +
// step, ... of row (j, k). Interior cells take a branch-free stencil; only rows and
// columns touching the boundary go through the general (wall/wrap) path.
template <class Fn>
inline void for_row(const PoissonLevel& L, const double* x, int j, int k, int i_start, int step, Fn&& fn) {
  const int nx = L.n[0], ny = L.n[1], nz = L.n[2];
  const size_t sy = size_t(nx), sz = size_t(nx) * ny;
  const size_t row = sy * j + sz * k;
  const bool inner = j > 0 && j < ny - 1 && (L.dim == 2 || (k > 0 && k < nz - 1));
  auto general = [&](int i) {
    const Neighbours nb = neighbours(L, x, i, j, k);
    fn(row + i, nb.sum, nb.count);
  };
  if (!inner || nx < 3) {
    for (int i = i_start; i < nx; i += step) general(i);
    return;
  }
  int i = i_start;
  if (i == 0) {
    general(0);
    i += step;
  }
  const int count = 2 * L.dim;
  if (L.dim == 2) {
    for (; i < nx - 1; i += step) {
      const size_t c = row + i;
      fn(c, x[c - 1] + x[c + 1] + x[c - sy] + x[c + sy], count);
    }
  } else {
    for (; i < nx - 1; i += step) {
      const size_t c = row + i;
      fn(c, x[c - 1] + x[c + 1] + x[c - sy] + x[c + sy] + x[c - sz] + x[c + sz], count);
    }
  }
  if (i == nx - 1) general(i);
}

}  // namespace

void poisson_apply(const PoissonLevel& L, const double* x, double* y) {
  const int ny = L.n[1], nz = L.n[2];
#pragma omp parallel for collapse(2) schedule(static) if (L.cells() >= kOmpMinCells)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for_row(L, x, j, k, 0, 1, [&](size_t c, double sum, int count) { y[c] = count * x[c] - sum; });
}

double poisson_residual(const PoissonLevel& L, const double* b, const double* x, double* r) {
  const int ny = L.n[1];
  const size_t rows = size_t(ny) * L.n[2];
  return fixed_order_block_sum(rows, L.cells() >= kOmpMinCells, [&](size_t r0, size_t r1) {
    double rr = 0;
    for (size_t row = r0; row < r1; ++row)
      for_row(L, x, int(row % ny), int(row / ny), 0, 1, [&](size_t c, double sum, int count) {
        r[c] = b[c] - (count * x[c] - sum);
        rr += r[c] * r[c];
      });
    return rr;
  });
}

void poisson_diagonal(const PoissonLevel& L, double* diag) {
  const int nx = L.n[0], ny = L.n[1], nz = L.n[2];
  auto count = [&](int idx, int n) { return L.periodic ? 2 : (idx > 0) + (idx < n - 1); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        diag[i + size_t(nx) * (j + size_t(ny) * k)] =
            count(i, nx) + count(j, ny) + (L.dim == 3 ? count(k, nz) : 0);
}

void poisson_gauss_seidel_colour(const PoissonLevel& L, const double* b, double* x, int colour) {
  const int ny = L.n[1], nz = L.n[2];
#pragma omp parallel for collapse(2) schedule(static) if (L.cells() >= kOmpMinCells)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for_row(L, x, j, k, (j + k + colour) & 1, 2,
              [&](size_t c, double sum, int count) { x[c] = (b[c] + sum) / count; });
}

void poisson_jacobi_sweep(const PoissonLevel& L, const double* b, double* x, double* tmp,
                          double omega) {
  const int ny = L.n[1], nz = L.n[2];
#pragma omp parallel for collapse(2) schedule(static) if (L.cells() >= kOmpMinCells)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for_row(L, x, j, k, 0, 1, [&](size_t c, double sum, int count) {
        tmp[c] = x[c] + omega * (b[c] - (count * x[c] - sum)) / count;
      });
  const size_t n = L.cells();
#pragma omp parallel for schedule(static) if (n >= kOmpMinCells)
  for (size_t c = 0; c < n; ++c) x[c] = tmp[c];
}

void poisson_restrict(const PoissonLevel& fine, const PoissonLevel& coarse, const double* r_fine,
                      double* b_coarse) {
  const int cx = coarse.n[0], cy = coarse.n[1], cz = coarse.n[2];
  const int fx = fine.n[0], fy = fine.n[1];
  const double scale = fine.dim == 2 ? 1.0 : 0.5;  // 4 / 2^dim
  const int kz = fine.dim == 3 ? 2 : 1;
#pragma omp parallel for collapse(2) schedule(static) if (fine.cells() >= kOmpMinCells)
  for (int k = 0; k < cz; ++k)
    for (int j = 0; j < cy; ++j)
      for (int i = 0; i < cx; ++i) {
        double s = 0;
        for (int dk = 0; dk < kz; ++dk)
          for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di)
              s += r_fine[(2 * i + di) + size_t(fx) * ((2 * j + dj) + size_t(fy) * (kz * k + dk))];
        b_coarse[i + size_t(cx) * (j + size_t(cy) * k)] = scale * s;
      }
}

void poisson_prolong_add(const PoissonLevel& fine, const PoissonLevel& coarse, const double* x_coarse,
                         double* x_fine) {
  const int fx = fine.n[0], fy = fine.n[1], fz = fine.n[2];
  const int cx = coarse.n[0], cy = coarse.n[1];
  const int kz = fine.dim == 3 ? 2 : 1;
#pragma omp parallel for collapse(2) schedule(static) if (fine.cells() >= kOmpMinCells)
  for (int k = 0; k < fz; ++k)
    for (int j = 0; j < fy; ++j)
      for (int i = 0; i < fx; ++i)
        x_fine[i + size_t(fx) * (j + size_t(fy) * k)] +=
            x_coarse[i / 2 + size_t(cx) * (j / 2 + size_t(cy) * (k / kz))];
}

void remove_mean(double* x, size_t n) {
  const double s = fixed_order_block_sum(n, n >= kOmpMinCells, [x](size_t i0, size_t i1) {
    double t = 0;
    for (size_t c = i0; c < i1; ++c) t += x[c];
    return t;
  });
  const double m = s / double(n);
#pragma omp parallel for schedule(static) if (n >= kOmpMinCells)
  for (size_t c = 0; c < n; ++c) x[c] -= m;
}

}  // namespace pliant::smoke
