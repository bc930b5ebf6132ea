// Stable neo-Hookean hexahedral FEM (see fem.h).
#include "pliant/soft/fem.h"

#include <Eigen/Dense>
#include <array>
#include <atomic>
#include <cmath>

namespace pliant::soft {
namespace {

using Eigen::Matrix3d;
using Mat9 = Eigen::Matrix<double, 9, 9>;

// dN_a/dxi at the 8 Gauss points of the unit cube (for cell size h divide by h).
struct GaussTable {
  std::array<std::array<Eigen::Vector3d, 8>, 8> dN;  // [qp][node]
  GaussTable() {
    const double g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
    for (int q = 0; q < 8; ++q) {
      const double xi[3] = {g[q & 1], g[(q >> 1) & 1], g[(q >> 2) & 1]};
      for (int a = 0; a < 8; ++a) {
        const int b[3] = {a & 1, (a >> 1) & 1, (a >> 2) & 1};
        double f[3], df[3];
        for (int d = 0; d < 3; ++d) {
          f[d] = b[d] ? xi[d] : 1 - xi[d];
          df[d] = b[d] ? 1 : -1;
        }
        dN[q][a] = Eigen::Vector3d(df[0] * f[1] * f[2], f[0] * df[1] * f[2], f[0] * f[1] * df[2]);
      }
    }
  }
};
const GaussTable& gauss() {
  static const GaussTable t;
  return t;
}

Matrix3d cofactor(const Matrix3d& F) {
  Matrix3d C;
  C.col(0) = F.col(1).cross(F.col(2));
  C.col(1) = F.col(2).cross(F.col(0));
  C.col(2) = F.col(0).cross(F.col(1));
  return C;
}

// dN/dX at every Gauss point as 8x3 matrices for cell size h (cached per h).
struct ScaledTable {
  double h = -1;
  std::array<Eigen::Matrix<double, 8, 3>, 8> G;
};
const std::array<Eigen::Matrix<double, 8, 3>, 8>& scaled_table(double h) {
  thread_local ScaledTable t;
  if (t.h != h) {
    for (int q = 0; q < 8; ++q)
      for (int a = 0; a < 8; ++a) t.G[q].row(a) = gauss().dN[q][a].transpose() / h;
    t.h = h;
  }
  return t.G;
}

Eigen::Matrix<double, 3, 8> gather(const Lattice& lat, const Eigen::VectorXd& x, int cell) {
  Eigen::Matrix<double, 3, 8> X;
  for (int a = 0; a < 8; ++a) X.col(a) = x.segment<3>(3 * lat.cells[cell][a]);
  return X;
}

Matrix3d deformation_gradient(const Lattice& lat, const Eigen::VectorXd& x, int cell, int q) {
  return gather(lat, x, cell) * scaled_table(lat.cell_size_m)[q];
}


// Per-thread cache of D_q = B_q U_e (elastic_reduced): one slot per cubature cell,
// holding the cell's 24 rows of U it was built from. 9 x 24 B_q has three nonzeros
// per row, so D's row 3c+s = sum_a G_q(a, c) U_e(3a+s, :).
struct ReducedCellCache {
  struct Cell {
    Eigen::Matrix<double, 24, Eigen::Dynamic> Ue;
    std::array<Eigen::Matrix<double, 9, Eigen::Dynamic>, 8> D;
  };
  double h = -1;
  int r = -1;
  std::vector<Cell> cells;
  Cell scratch;  // bodies too large to cache (see reduced_cache_limit)
};

// Cache at most this many doubles per thread (kept cells x 96 r); larger bodies
// rebuild D per call in one scratch cell, as before the cache.
std::atomic<size_t> reduced_cache_limit{size_t(4) << 20};  // 32 MB

ReducedCellCache& reduced_cell_cache(double h, int r) {
  thread_local ReducedCellCache c;
  if (c.h != h || c.r != r) c.cells.clear(), c.h = h, c.r = r;
  return c;
}

void build_cell_d(const std::array<Eigen::Matrix<double, 8, 3>, 8>& G,
                  const Eigen::Matrix<double, 24, Eigen::Dynamic>& Ue, ReducedCellCache::Cell& cell) {
  const int r = int(Ue.cols());
  cell.Ue = Ue;
  for (int q = 0; q < 8; ++q) {
    auto& D = cell.D[q];
    D.resize(9, r);
    for (int j = 0; j < r; ++j)
      for (int c = 0; c < 3; ++c)
        for (int s = 0; s < 3; ++s) {
          double acc = 0;
          for (int a = 0; a < 8; ++a) acc += G[q](a, c) * Ue(3 * a + s, j);
          D(3 * c + s, j) = acc;
        }
  }
}

}  // namespace

Lame lame_from(const Material& m) {
  Lame l;
  l.mu = m.young_pa / (2 * (1 + m.poisson));
  const double lambda = m.young_pa * m.poisson / ((1 + m.poisson) * (1 - 2 * m.poisson));
  l.lam = lambda + l.mu;
  return l;
}

double snh_energy(const Lame& l, const Matrix3d& F) {
  const double alpha = 1 + l.mu / l.lam;
  const double J = F.determinant();
  return 0.5 * l.mu * (F.squaredNorm() - 3) + 0.5 * l.lam * (J - alpha) * (J - alpha);
}

Matrix3d snh_stress(const Lame& l, const Matrix3d& F) {
  const double alpha = 1 + l.mu / l.lam;
  return l.mu * F + l.lam * (F.determinant() - alpha) * cofactor(F);
}

Mat9 snh_stress_derivative(const Lame& l, const Matrix3d& F) {
  const double alpha = 1 + l.mu / l.lam;
  const double J = F.determinant();
  const Matrix3d C = cofactor(F);
  Eigen::Matrix<double, 9, 1> g;
  for (int c = 0; c < 3; ++c) g.segment<3>(3 * c) = C.col(c);
  Mat9 H = l.mu * Mat9::Identity() + l.lam * g * g.transpose();
  // d(cof F) / dF: dc0 = df1 x f2 + f1 x df2 etc. (columns f_i of F).
  const double s = l.lam * (J - alpha);
  const Matrix3d X0 = cross_matrix(F.col(0)), X1 = cross_matrix(F.col(1)), X2 = cross_matrix(F.col(2));
  H.block<3, 3>(0, 3) += -s * X2;
  H.block<3, 3>(0, 6) += s * X1;
  H.block<3, 3>(3, 0) += s * X2;
  H.block<3, 3>(3, 6) += -s * X0;
  H.block<3, 3>(6, 0) += -s * X1;
  H.block<3, 3>(6, 3) += s * X0;
  return H;
}

void cell_force(const Lattice& lat, const Lame& l, const Eigen::VectorXd& x, int cell, double* f24) {
  const double h = lat.cell_size_m, w = h * h * h / 8;
  for (int i = 0; i < 24; ++i) f24[i] = 0;
  for (int q = 0; q < 8; ++q) {
    const Matrix3d P = snh_stress(l, deformation_gradient(lat, x, cell, q));
    for (int a = 0; a < 8; ++a) {
      const Eigen::Vector3d fa = -w * P * (gauss().dN[q][a] / h);
      for (int d = 0; d < 3; ++d) f24[3 * a + d] += fa[d];
    }
  }
}

const std::array<Eigen::Matrix<double, 8, 3>, 8>& gauss_shape_gradients(double h) { return scaled_table(h); }

double elastic_energy(const Lattice& lat, const Lame& l, const Eigen::VectorXd& x, const CellWeights& cw,
                      Eigen::VectorXd* grad, Eigen::SparseMatrix<double>* hess) {
  const double h = lat.cell_size_m, vol_q = h * h * h / 8, inv_h = 1.0 / h;
  const int ncell = cw.all() ? int(lat.cells.size()) : int(cw.cells.size());
  if (grad) grad->setZero(x.size());
  std::vector<Eigen::Triplet<double>> trip;
  if (hess) trip.reserve(size_t(ncell) * 576);
  double energy = 0;
  for (int k = 0; k < ncell; ++k) {
    const int e = cw.all() ? k : cw.cells[k];
    const double we = cw.all() ? 1.0 : cw.weights[k];
    const auto& ids = lat.cells[e];
    Eigen::Matrix<double, 24, 24> Ke;
    if (hess) Ke.setZero();
    const Eigen::Matrix<double, 3, 8> X = gather(lat, x, e);
    const auto& G = scaled_table(h);
    Eigen::Matrix<double, 3, 8> gcell = Eigen::Matrix<double, 3, 8>::Zero();
    for (int q = 0; q < 8; ++q) {
      const Matrix3d F = X * G[q];
      energy += we * vol_q * snh_energy(l, F);
      if (grad) gcell.noalias() += (we * vol_q) * snh_stress(l, F) * G[q].transpose();
      if (hess) {
        const Mat9 A = snh_stress_derivative(l, F);
        // dvec(F)/dx_{a,s} = e_s (x) G_a: entry (3c+s) = G_a[c].
        Eigen::Matrix<double, 9, 24> B = Eigen::Matrix<double, 9, 24>::Zero();
        for (int a = 0; a < 8; ++a)
          for (int c = 0; c < 3; ++c)
            for (int s = 0; s < 3; ++s) B(3 * c + s, 3 * a + s) = gauss().dN[q][a][c] * inv_h;
        Ke.noalias() += (we * vol_q) * B.transpose() * A * B;
      }
    }
    if (grad)
      for (int a = 0; a < 8; ++a) grad->segment<3>(3 * ids[a]) += gcell.col(a);
    if (hess)
      for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b)
          for (int s = 0; s < 3; ++s)
            for (int t = 0; t < 3; ++t) trip.emplace_back(3 * ids[a] + s, 3 * ids[b] + t, Ke(3 * a + s, 3 * b + t));
  }
  if (hess) {
    hess->resize(x.size(), x.size());
    hess->setFromTriplets(trip.begin(), trip.end());
  }
  return energy;
}

double elastic_reduced(const Lattice& lat, const Lame& l, const Eigen::VectorXd& x, const CellWeights& cw,
                       const Eigen::MatrixXd& U, Eigen::VectorXd* grad, Eigen::MatrixXd* hess) {
  const double h = lat.cell_size_m, vol_q = h * h * h / 8;
  const int r = int(U.cols());
  const int ncell = cw.all() ? int(lat.cells.size()) : int(cw.cells.size());
  if (grad) grad->setZero(r);
  if (hess) hess->setZero(r, r);
  const auto& G = scaled_table(h);
  // D_q = dvec(F)/dq = B_q U_e (9 x r) per cell and Gauss point. It depends only on
  // the cell's 24 rows of U, so each thread keeps the last D of every cell slot with
  // the rows it came from: with a constant basis (linear modes, POD) every later call
  // reuses it; a changed U (rotation-strain Jacobian, another character) is detected
  // by comparing the rows and rebuilds that cell.
  ReducedCellCache& cache = reduced_cell_cache(h, r);
  const bool cacheable = size_t(ncell) * 96 * size_t(r) <= reduced_cache_limit.load(std::memory_order_relaxed);
  if (cacheable && int(cache.cells.size()) < ncell) cache.cells.resize(ncell);
  thread_local Eigen::Matrix<double, 24, Eigen::Dynamic> Ue;
  thread_local Eigen::Matrix<double, 9, Eigen::Dynamic> AD;
  if (Ue.cols() != r) Ue.resize(24, r), AD.resize(9, r);
  // B_q = dvec(F)/dx_cell (9 x 24), the same for every cell, for the gradient.
  thread_local std::array<Eigen::Matrix<double, 9, 24>, 8> B;
  thread_local double B_h = -1;
  if (B_h != h) {
    for (int q = 0; q < 8; ++q) {
      B[q].setZero();
      for (int a = 0; a < 8; ++a)
        for (int c = 0; c < 3; ++c)
          for (int s = 0; s < 3; ++s) B[q](3 * c + s, 3 * a + s) = G[q](a, c);
    }
    B_h = h;
  }
  Eigen::Matrix<double, 24, 1> gcell;
  double energy = 0;
  for (int k = 0; k < ncell; ++k) {
    const int e = cw.all() ? k : cw.cells[k];
    const double we = (cw.all() ? 1.0 : cw.weights[k]) * vol_q;
    const auto& ids = lat.cells[e];
    const Eigen::Matrix<double, 3, 8> X = gather(lat, x, e);
    const bool need_d = grad || hess;
    ReducedCellCache::Cell* cc = nullptr;
    if (need_d) {
      for (int a = 0; a < 8; ++a) Ue.middleRows<3>(3 * a) = U.middleRows<3>(3 * ids[a]);
      if (cacheable) {
        cc = &cache.cells[k];
        if (cc->Ue.cols() != r || cc->Ue != Ue) build_cell_d(G, Ue, *cc);
      } else {
        cc = &cache.scratch;
        build_cell_d(G, Ue, *cc);
      }
    }
    if (grad) gcell.setZero();
    for (int q = 0; q < 8; ++q) {
      const Matrix3d F = X * G[q];
      energy += we * snh_energy(l, F);
      if (!need_d) continue;
      const auto& D = cc->D[q];
      if (grad) {
        // Same arithmetic as the nodal gradient (U_e^T sum_q w B_q^T vec P): the
        // reduced force, hence the step's root, is unchanged bit for bit.
        const Matrix3d P = snh_stress(l, F);
        gcell.noalias() += we * B[q].transpose() * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(P.data());
      }
      if (hess) {
        // Lower triangle of w D^T A D only (symmetric; the LDLT reads the lower one),
        // mirrored after the loop.
        AD.noalias() = snh_stress_derivative(l, F).lazyProduct(D);
        for (int j = 0; j < r; ++j)
          for (int i = j; i < r; ++i) (*hess)(i, j) += we * D.col(i).dot(AD.col(j));
      }
    }
    if (grad) grad->noalias() += Ue.transpose().lazyProduct(gcell);
  }
  if (hess) hess->triangularView<Eigen::StrictlyUpper>() = hess->transpose();
  return energy;
}

size_t set_reduced_cache_limit(size_t doubles) { return reduced_cache_limit.exchange(doubles); }

double lattice_volume(const Lattice& lat, const Eigen::VectorXd& x) {
  const double h = lat.cell_size_m;
  const auto& G = gauss_shape_gradients(h);
  double v = 0;
  for (const auto& ids : lat.cells) {
    Eigen::Matrix<double, 3, 8> X;
    for (int a = 0; a < 8; ++a) X.col(a) = x.segment<3>(3 * ids[a]);
    for (int q = 0; q < 8; ++q) v += h * h * h / 8 * (X * G[q]).determinant();
  }
  return v;
}

}  // namespace pliant::soft
