// Linear modes (see modes.h).
#include "pliant/soft/modes.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <algorithm>
#include <random>
#include <stdexcept>

namespace pliant::soft {
namespace {

// M-Gram-Schmidt of the columns of A against themselves (twice for stability).
void m_orthonormalize(Eigen::MatrixXd& A, const Eigen::VectorXd& m) {
  for (int pass = 0; pass < 2; ++pass)
    for (int j = 0; j < A.cols(); ++j) {
      for (int i = 0; i < j; ++i) A.col(j) -= A.col(i) * A.col(i).dot(m.asDiagonal() * A.col(j));
      const double nrm = std::sqrt(A.col(j).dot(m.asDiagonal() * A.col(j)));
      if (nrm > 0) A.col(j) /= nrm;
    }
}

void deflate(Eigen::MatrixXd& X, const Eigen::MatrixXd& rigid, const Eigen::VectorXd& m) {
  X -= rigid * (rigid.transpose() * (m.asDiagonal() * X));
}

}  // namespace

Eigen::MatrixXd rigid_modes(const Lattice& lat) {
  const int n = lat.nodes();
  Eigen::VectorXd m(3 * n);
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  double mass = 0;
  for (int i = 0; i < n; ++i) {
    m.segment<3>(3 * i).setConstant(lat.node_mass_kg[i]);
    com += lat.node_mass_kg[i] * lat.rest[i];
    mass += lat.node_mass_kg[i];
  }
  com /= mass;
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(3 * n, 6);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = lat.rest[i] - com;
    for (int a = 0; a < 3; ++a) {
      R(3 * i + a, a) = 1;
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[a] = 1;
      R.block<3, 1>(3 * i, 3 + a) = e.cross(d);
    }
  }
  m_orthonormalize(R, m);
  return R;
}

ModalBasis linear_modes(const Lattice& lat, const Lame& lame, int r) {
  const int n3 = 3 * lat.nodes();
  r = std::clamp(r, 0, n3 - 6);
  ModalBasis out;
  if (r == 0) {
    out.U.resize(n3, 0);
    return out;
  }
  Eigen::VectorXd x(n3), m(n3);
  for (int i = 0; i < lat.nodes(); ++i) {
    x.segment<3>(3 * i) = lat.rest[i];
    m.segment<3>(3 * i).setConstant(lat.node_mass_kg[i]);
  }
  Eigen::SparseMatrix<double> K;
  elastic_energy(lat, lame, x, CellWeights{}, nullptr, &K);
  const Eigen::MatrixXd rigid = rigid_modes(lat);
  if (n3 <= 900) {
    const Eigen::VectorXd s = m.cwiseSqrt().cwiseInverse();
    Eigen::MatrixXd A = s.asDiagonal() * Eigen::MatrixXd(K) * s.asDiagonal();
    // Shift the rigid subspace far up so the 6 zero modes are not among the lowest.
    const Eigen::MatrixXd Rm = m.cwiseSqrt().asDiagonal() * rigid;  // orthonormal
    const double big = 10 * A.diagonal().maxCoeff() * n3;
    A += big * Rm * Rm.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
    out.U = s.asDiagonal() * es.eigenvectors().leftCols(r);
    out.omega2 = es.eigenvalues().head(r);
    return out;
  }
  // Shift-invert subspace iteration (Bathe): X <- (K + sigma M)^-1 M X, Rayleigh-Ritz.
  const double sigma = 1e-3 * (K.diagonal().array() / m.array()).mean();
  Eigen::SparseMatrix<double> A = K;
  for (int i = 0; i < n3; ++i) A.coeffRef(i, i) += sigma * m[i];
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> llt(A);
  if (llt.info() != Eigen::Success) throw std::runtime_error("modes: CHOLMOD factorization of K + sigma M failed");
  const int p = std::min(n3 - 6, std::max(2 * r, r + 8));
  std::mt19937 rng(7);
  std::normal_distribution<double> nd;
  Eigen::MatrixXd X(n3, p);
  for (int j = 0; j < p; ++j)
    for (int i = 0; i < n3; ++i) X(i, j) = nd(rng);
  deflate(X, rigid, m);
  Eigen::VectorXd prev = Eigen::VectorXd::Zero(r);
  for (int it = 0; it < 200; ++it) {
    Eigen::MatrixXd Y = llt.solve(m.asDiagonal() * X);
    deflate(Y, rigid, m);
    m_orthonormalize(Y, m);
    const Eigen::MatrixXd KY = K * Y;
    Eigen::MatrixXd Kr = Y.transpose() * KY;
    Kr = 0.5 * (Kr + Kr.transpose()).eval();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Kr);  // Y is M-orthonormal: Mr = I
    X = Y * es.eigenvectors();
    const Eigen::VectorXd ev = es.eigenvalues().head(r);
    const double change = ((ev - prev).array().abs() / ev.array().abs().max(1e-30)).maxCoeff();
    prev = ev;
    if (it > 2 && change < 1e-10) break;
  }
  out.U = X.leftCols(r);
  out.omega2 = prev;
  return out;
}

ModalBasis with_modal_derivatives(const Lattice& lat, const Lame& lame, const ModalBasis& b, int k) {
  k = std::min(k, b.r());
  if (k <= 0) return b;
  const int n3 = 3 * lat.nodes();
  Eigen::VectorXd x(n3), m(n3);
  for (int i = 0; i < lat.nodes(); ++i) {
    x.segment<3>(3 * i) = lat.rest[i];
    m.segment<3>(3 * i).setConstant(lat.node_mass_kg[i]);
  }
  Eigen::SparseMatrix<double> K;
  elastic_energy(lat, lame, x, CellWeights{}, nullptr, &K);
  const double sigma = 1e-6 * (K.diagonal().array() / m.array()).mean();
  Eigen::SparseMatrix<double> A = K;
  for (int i = 0; i < n3; ++i) A.coeffRef(i, i) += sigma * m[i];
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> llt(A);
  if (llt.info() != Eigen::Success) throw std::runtime_error("modal derivatives: CHOLMOD factorization failed");
  const Eigen::MatrixXd rigid = rigid_modes(lat);
  std::vector<Eigen::VectorXd> extra;
  for (int i = 0; i < k; ++i) {
    const Eigen::VectorXd phi = b.U.col(i);
    double mx = 0;
    for (int j = 0; j < lat.nodes(); ++j) mx = std::max(mx, phi.segment<3>(3 * j).norm());
    const double eps = 1e-4 * lat.cell_size_m / mx;
    Eigen::SparseMatrix<double> Kp, Km;
    elastic_energy(lat, lame, x + eps * phi, CellWeights{}, nullptr, &Kp);
    elastic_energy(lat, lame, x - eps * phi, CellWeights{}, nullptr, &Km);
    const Eigen::SparseMatrix<double> dK = (Kp - Km) / (2 * eps);
    for (int j = i; j < k; ++j) {
      Eigen::MatrixXd rhs = -(dK * b.U.col(j));
      rhs -= m.asDiagonal() * rigid * (rigid.transpose() * rhs);  // self-equilibrated load
      Eigen::MatrixXd psi = llt.solve(rhs);
      deflate(psi, rigid, m);
      extra.push_back(psi.col(0));
    }
  }
  // M-Gram-Schmidt (twice), skipping vectors already in the span.
  std::vector<Eigen::VectorXd> cols;
  for (int c = 0; c < b.r(); ++c) cols.push_back(b.U.col(c));
  for (auto& e : extra) cols.push_back(e);
  std::vector<Eigen::VectorXd> basis;
  for (auto v : cols) {
    const double n0 = std::sqrt(v.dot(m.asDiagonal() * v));
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& u : basis) v -= u * u.dot(m.asDiagonal() * v);
    const double n1 = std::sqrt(v.dot(m.asDiagonal() * v));
    if (n1 > 1e-8 * n0 && n1 > 0) basis.push_back(v / n1);
  }
  Eigen::MatrixXd Bk(n3, basis.size());
  for (size_t c = 0; c < basis.size(); ++c) Bk.col(c) = basis[c];
  Eigen::MatrixXd Kr = Bk.transpose() * (K * Bk);
  Kr = 0.5 * (Kr + Kr.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Kr);
  ModalBasis out;
  out.U = Bk * es.eigenvectors();
  out.omega2 = es.eigenvalues();
  return out;
}

ModalBasis pod_basis(const Lattice& lat, const Lame& lame, const std::vector<Eigen::VectorXd>& snapshots, int r) {
  const int n3 = 3 * lat.nodes();
  Eigen::VectorXd x(n3), m(n3);
  for (int i = 0; i < lat.nodes(); ++i) {
    x.segment<3>(3 * i) = lat.rest[i];
    m.segment<3>(3 * i).setConstant(lat.node_mass_kg[i]);
  }
  Eigen::MatrixXd S(n3, snapshots.size());
  for (size_t c = 0; c < snapshots.size(); ++c) S.col(Eigen::Index(c)) = snapshots[c];
  deflate(S, rigid_modes(lat), m);
  // Method of snapshots: C = S^T M S = V L V^T, principal directions S V L^(-1/2).
  Eigen::MatrixXd C = S.transpose() * (m.asDiagonal() * S);
  C = 0.5 * (C + C.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(C);
  const Eigen::VectorXd& ev = es.eigenvalues();
  const int ns = int(ev.size());
  std::vector<int> keep;
  for (int i = ns - 1; i >= 0 && int(keep.size()) < r; --i)
    if (ev[i] > 1e-12 * ev[ns - 1] && ev[i] > 0) keep.push_back(i);
  Eigen::MatrixXd B(n3, keep.size());
  for (size_t c = 0; c < keep.size(); ++c) B.col(Eigen::Index(c)) = S * es.eigenvectors().col(keep[c]);
  return rayleigh_ritz(lat, lame, std::move(B));
}

ModalBasis rayleigh_ritz(const Lattice& lat, const Lame& lame, Eigen::MatrixXd B) {
  const int n3 = 3 * lat.nodes();
  Eigen::VectorXd x(n3), m(n3);
  for (int i = 0; i < lat.nodes(); ++i) {
    x.segment<3>(3 * i) = lat.rest[i];
    m.segment<3>(3 * i).setConstant(lat.node_mass_kg[i]);
  }
  deflate(B, rigid_modes(lat), m);
  m_orthonormalize(B, m);
  Eigen::SparseMatrix<double> K;
  elastic_energy(lat, lame, x, CellWeights{}, nullptr, &K);
  Eigen::MatrixXd Kr = B.transpose() * (K * B);
  Kr = 0.5 * (Kr + Kr.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> rr(Kr);
  ModalBasis out;
  out.U = B * rr.eigenvectors();
  out.omega2 = rr.eigenvalues();
  return out;
}

}  // namespace pliant::soft
