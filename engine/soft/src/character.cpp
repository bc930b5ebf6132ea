// Characters (see simulator.h): rest data and modal basis (linear, modal derivatives
// or POD of full-FEM snapshots), the optional rotation-strain map, and the local shape
// map q -> Xbar + U q (or the rotation-strain reconstruction).
#include "pliant/soft/simulator.h"

#include "pliant/soft/cubature.h"

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace pliant::soft {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

}  // namespace

Character make_character(SurfaceMesh surface, Lattice lattice, const Material& mat, int modes,
                         int derivative_modes, const PodTraining* pod) {
  Character ch;
  ch.surface = std::move(surface);
  ch.lattice = std::move(lattice);
  ch.material = mat;
  ch.lame = lame_from(mat);
  const int n = ch.lattice.nodes();
  ch.rest.resize(3 * n);
  ch.mass_kg = 0;
  for (int j = 0; j < n; ++j) {
    ch.rest.segment<3>(3 * j) = ch.lattice.rest[j];
    ch.rest_com += ch.lattice.node_mass_kg[j] * ch.lattice.rest[j];
    ch.mass_kg += ch.lattice.node_mass_kg[j];
  }
  ch.rest_com /= ch.mass_kg;
  ch.rest_local = ch.rest;
  for (int j = 0; j < n; ++j) ch.rest_local.segment<3>(3 * j) -= ch.rest_com;
  ch.basis = linear_modes(ch.lattice, ch.lame, modes);
  if (derivative_modes > 0) ch.basis = with_modal_derivatives(ch.lattice, ch.lame, ch.basis, derivative_modes);
  if (pod) {
    // Keep the lowest linear modes, POD of what the snapshots hold beyond them.
    const int keep = std::clamp(pod->linear_modes, 0, std::max(modes - 1, 0));
    const ModalBasis lin = ch.basis;
    std::vector<VectorXd> snaps = pod_snapshots(ch, *pod);
    VectorXd m(3 * n);
    for (int j = 0; j < n; ++j) m.segment<3>(3 * j).setConstant(ch.lattice.node_mass_kg[j]);
    const MatrixXd Uk = lin.U.leftCols(keep);
    for (auto& u : snaps) u -= Uk * (Uk.transpose() * (m.asDiagonal() * u));
    const ModalBasis extra = pod_basis(ch.lattice, ch.lame, snaps, modes - keep);
    MatrixXd B(3 * n, keep + extra.r());
    B << Uk, extra.U;
    ch.basis = rayleigh_ritz(ch.lattice, ch.lame, B);
  }
  ch.mode_scale.resize(ch.basis.r());
  for (int k = 0; k < ch.basis.r(); ++k) {
    double mx = 0;
    for (int j = 0; j < n; ++j) mx = std::max(mx, ch.basis.U.block<3, 1>(3 * j, k).norm());
    ch.mode_scale[k] = mx;
  }
  return ch;
}

void enable_rotation_strain(Character& ch, bool reduced, const RsReductionSettings& settings, int reduction_poses) {
  auto rs = std::make_shared<RotationStrain>(rotation_strain_build(ch.lattice, ch.basis.U));
  if (reduced && ch.basis.r() > 0) {
    const auto poses = training_poses(ch, reduction_poses, rotation_strain_training_amplitude, 5);
    rs->reduced = rotation_strain_reduce(ch.lattice, *rs, ch.basis.U, ch.rest_local, poses, settings);
  }
  ch.rotation_strain = rs;
}

void local_shape(const Character& ch, const VectorXd& q, VectorXd& local, MatrixXd* jacobian) {
  if (ch.rotation_strain) {
    if (ch.rotation_strain->reduced)
      rotation_strain_reduced_positions(*ch.rotation_strain->reduced, q, local, jacobian);
    else
      rotation_strain_positions(ch.lattice, *ch.rotation_strain, q, local, jacobian);
    return;
  }
  local = ch.rest_local;
  if (ch.basis.r() > 0) local.noalias() += ch.basis.U * q;
  if (jacobian) *jacobian = ch.basis.U;
}

std::vector<VectorXd> pod_snapshots(const Character& ch, const PodTraining& t) {
  const Lattice& lat = ch.lattice;
  const int n = lat.nodes();
  Vector3d lo = ch.rest.segment<3>(0), hi = lo;
  for (int j = 0; j < n; ++j) lo = lo.cwiseMin(lat.rest[j]), hi = hi.cwiseMax(lat.rest[j]);
  const Vector3d ext = (hi - lo).cwiseMax(lat.cell_size_m);
  // Force per unit mass that holds the first linear mode at strain x diagonal.
  const double w2 = ch.basis.r() > 0 ? ch.basis.omega2[0] : linear_modes(lat, ch.lame, 1).omega2[0];
  const double accel = t.strain * ext.norm() * w2;
  Environment env;
  env.gravity_m_per_s2.setZero();
  SimParams sp;
  sp.dt_s = t.dt_s;
  sp.modal_damping_s = 0;
  std::mt19937 rng(t.seed);
  std::uniform_real_distribution<double> uni(0, 1);
  std::normal_distribution<double> nd(0, 1);
  std::vector<VectorXd> out;
  for (int run = 0; run < t.runs; ++run) {
    VectorXd f = VectorXd::Zero(3 * n);
    for (int w = 0; w < 3; ++w) {
      const Vector3d d = Vector3d(nd(rng), nd(rng), nd(rng)).normalized();
      const Vector3d k = M_PI * Vector3d(2 * uni(rng), 2 * uni(rng), 2 * uni(rng)).cwiseQuotient(ext);
      const double phase = 2 * M_PI * uni(rng);
      for (int j = 0; j < n; ++j)
        f.segment<3>(3 * j) += lat.node_mass_kg[j] * accel * std::cos(k.dot(lat.rest[j] - lo) + phase) * d;
    }
    VectorXd x = ch.rest, xp = ch.rest;
    for (int k = 0; k < t.frames; ++k) {
      full_step(ch, env, sp, f, x, xp);
      // Best rigid fit (Kabsch) of x to the rest shape, removed.
      Vector3d cx = Vector3d::Zero();
      for (int j = 0; j < n; ++j) cx += lat.node_mass_kg[j] * x.segment<3>(3 * j);
      cx /= ch.mass_kg;
      Matrix3d C = Matrix3d::Zero();
      for (int j = 0; j < n; ++j)
        C += lat.node_mass_kg[j] * (x.segment<3>(3 * j) - cx) * ch.rest_local.segment<3>(3 * j).transpose();
      Eigen::JacobiSVD<Matrix3d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Matrix3d U = svd.matrixU();
      if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) *= -1;
      const Matrix3d R = U * svd.matrixV().transpose();
      VectorXd u(3 * n);
      for (int j = 0; j < n; ++j)
        u.segment<3>(3 * j) = R.transpose() * (x.segment<3>(3 * j) - cx) - ch.rest_local.segment<3>(3 * j);
      out.push_back(std::move(u));
    }
  }
  return out;
}

}  // namespace pliant::soft
