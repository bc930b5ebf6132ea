// Greedy NNLS cubature (see cubature.h). Written here rather than taken from
// pliant_optim so the fit stays next to the force model it approximates.
#include "pliant/soft/cubature.h"

#include <Eigen/Dense>
#include <algorithm>
#include <random>

#include "pliant/soft/simulator.h"

namespace pliant::soft {

Eigen::VectorXd nnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, int max_iterations) {
  const int n = int(A.cols());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> passive(n, false);
  for (int it = 0; it < max_iterations; ++it) {
    const Eigen::VectorXd w = A.transpose() * (b - A * x);
    int best = -1;
    double wmax = 1e-12 * std::max(1.0, w.cwiseAbs().maxCoeff());
    for (int j = 0; j < n; ++j)
      if (!passive[j] && w[j] > wmax) wmax = w[j], best = j;
    if (best < 0) break;
    passive[best] = true;
    for (int inner = 0; inner < 3 * n + 10; ++inner) {
      std::vector<int> P;
      for (int j = 0; j < n; ++j)
        if (passive[j]) P.push_back(j);
      Eigen::MatrixXd Ap(A.rows(), P.size());
      for (size_t k = 0; k < P.size(); ++k) Ap.col(k) = A.col(P[k]);
      const Eigen::VectorXd z = Ap.colPivHouseholderQr().solve(b);
      bool feasible = true;
      for (size_t k = 0; k < P.size(); ++k) feasible &= z[k] > 0;
      if (feasible) {
        x.setZero();
        for (size_t k = 0; k < P.size(); ++k) x[P[k]] = z[k];
        break;
      }
      // Step back to the boundary and drop the variables that hit zero.
      double alpha = 1;
      for (size_t k = 0; k < P.size(); ++k)
        if (z[k] <= 0) alpha = std::min(alpha, x[P[k]] / (x[P[k]] - z[k]));
      for (size_t k = 0; k < P.size(); ++k) {
        x[P[k]] += alpha * (z[k] - x[P[k]]);
        if (x[P[k]] <= 1e-14) passive[P[k]] = false, x[P[k]] = 0;
      }
    }
  }
  return x;
}

std::vector<Eigen::VectorXd> training_poses(const Character& ch, int count, double amplitude_rel, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd;
  const Eigen::Vector3d lo = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>>(ch.rest.data(), 3,
                                                                                        ch.lattice.nodes())
                                 .rowwise()
                                 .minCoeff(),
                        hi = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>>(ch.rest.data(), 3,
                                                                                        ch.lattice.nodes())
                                 .rowwise()
                                 .maxCoeff();
  const double size = (hi - lo).maxCoeff();
  const int r = ch.basis.r();
  std::vector<Eigen::VectorXd> poses;
  for (int p = 0; p < count; ++p) {
    Eigen::VectorXd q(r);
    // Lower modes get larger amplitudes (as in dynamics, amplitude ~ 1 / omega).
    for (int k = 0; k < r; ++k) q[k] = nd(rng) / ch.mode_scale[k] * std::sqrt(ch.basis.omega2[0] / ch.basis.omega2[k]);
    const Eigen::VectorXd u = ch.basis.U * q;
    double mx = 0;
    for (int j = 0; j < ch.lattice.nodes(); ++j) mx = std::max(mx, u.segment<3>(3 * j).norm());
    poses.push_back(q * (amplitude_rel * size / std::max(mx, 1e-300)) * (0.3 + 0.7 * (p + 1.0) / count));
  }
  return poses;
}

Eigen::VectorXd reduced_force(const Character& ch, const Eigen::VectorXd& q, const CellWeights& w) {
  Eigen::VectorXd g;
  if (ch.rotation_strain) {
    Eigen::VectorXd x;
    Eigen::MatrixXd J;
    local_shape(ch, q, x, &J);
    elastic_energy(ch.lattice, ch.lame, x, w, &g, nullptr);
    return -(J.transpose() * g);
  }
  const Eigen::VectorXd x = ch.rest + ch.basis.U * q;
  elastic_energy(ch.lattice, ch.lame, x, w, &g, nullptr);
  return -(ch.basis.U.transpose() * g);
}

CellWeights greedy_cubature(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double tolerance, int max_cells,
                            double* fit_error) {
  const int E = int(A.cols());
  const Eigen::VectorXd norms = A.colwise().norm().transpose().cwiseMax(1e-300);
  std::vector<int> S;
  Eigen::VectorXd w, res = b;
  std::vector<bool> in(E, false);
  while (int(S.size()) < std::min(max_cells, E)) {
    const Eigen::VectorXd score = (A.transpose() * res).cwiseQuotient(norms);
    int best = -1;
    double bs = 0;
    for (int e = 0; e < E; ++e)
      if (!in[e] && score[e] > bs) bs = score[e], best = e;
    if (best < 0) break;
    in[best] = true;
    S.push_back(best);
    Eigen::MatrixXd As(A.rows(), S.size());
    for (size_t k = 0; k < S.size(); ++k) As.col(k) = A.col(S[k]);
    w = nnls(As, b);
    res = b - As * w;
    if (res.norm() <= tolerance * b.norm()) break;
  }
  CellWeights cw;
  for (size_t k = 0; k < S.size(); ++k)
    if (w[k] > 0) cw.cells.push_back(S[k]), cw.weights.push_back(w[k]);
  if (fit_error) *fit_error = res.norm() / std::max(b.norm(), 1e-300);
  return cw;
}

CellWeights fit_cubature(const Character& ch, const std::vector<Eigen::VectorXd>& given_poses, double tolerance,
                         int max_cells, CubatureReport* report) {
  std::vector<Eigen::VectorXd> poses = given_poses;
  if (ch.rotation_strain) {
    // Rotation-strain coordinates rotate at large amplitude: train there too.
    const auto big = training_poses(ch, std::max<int>(24, 2 * int(given_poses.size())), rotation_strain_training_amplitude, 23);
    poses.insert(poses.end(), big.begin(), big.end());
  }
  const int r = ch.basis.r(), P = int(poses.size()), E = int(ch.lattice.cells.size());
  Eigen::VectorXd b(P * r);
  Eigen::MatrixXd A(P * r, E);
  Eigen::VectorXd x;
  Eigen::MatrixXd J;
  for (int p = 0; p < P; ++p) {
    if (ch.rotation_strain) {
      local_shape(ch, poses[p], x, &J);
    } else {
      x = ch.rest + ch.basis.U * poses[p];
    }
    const Eigen::MatrixXd& Jq = ch.rotation_strain ? J : ch.basis.U;
    const Eigen::VectorXd bp = reduced_force(ch, poses[p], CellWeights{});
    const double scale = 1.0 / std::max(bp.norm(), 1e-300);  // every pose counts equally
    b.segment(p * r, r) = bp * scale;
#pragma omp parallel for
    for (int e = 0; e < E; ++e) {
      double f[24];
      cell_force(ch.lattice, ch.lame, x, e, f);
      Eigen::VectorXd col = Eigen::VectorXd::Zero(r);
      for (int a = 0; a < 8; ++a)
        col += Jq.middleRows(3 * ch.lattice.cells[e][a], 3).transpose() *
               Eigen::Vector3d(f[3 * a], f[3 * a + 1], f[3 * a + 2]);
      A.block(p * r, e, r, 1) = col * scale;
    }
  }
  double err = 0;
  CellWeights cw = greedy_cubature(A, b, tolerance, max_cells, &err);
  if (report) {
    report->cells = int(cw.cells.size());
    report->kept_fraction = double(cw.cells.size()) / E;
    report->training_error = err;
  }
  return cw;
}

}  // namespace pliant::soft
