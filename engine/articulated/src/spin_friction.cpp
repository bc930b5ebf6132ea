// Torsional and rolling friction (condim 4 / 6) as dissipation potentials on the
// bodies' rotation over the step (sim_internal.h); the rotational counterpart of the
// sliding friction's mu f_n (sqrt(|s_t|^2 + eps^2) - eps) in pbad_energy.cpp.
#include <cmath>

#include "sim_internal.h"

namespace pliant::articulated {

bool any_spin_friction(const Model& m) {
  for (const Geom& g : m.geoms)
    if (g.condim > 3) return true;
  for (const ContactPair& p : m.contact_pairs)
    if (p.condim > 3) return true;
  return false;
}

Vec3 rotation_increment(const Mat3& r, const Mat3& r0, Mat3* jac) {
  const Mat3 mm = r * r0.transpose();
  // d/dtheta of axial(M) for M -> exp([dtheta]x) M: 1/2 (tr(M) I - M), from the identity
  // [w]x A + A^T [w]x = [(tr(A) I - A) w]x.
  if (jac) *jac = 0.5 * (mm.trace() * Mat3::Identity() - mm);
  return 0.5 * Vec3(mm(2, 1) - mm(1, 2), mm(0, 2) - mm(2, 0), mm(1, 0) - mm(0, 1));
}

double spin_friction(double fn, const Vec3& n, const Vec3& phi, double mu_t, double mu_r, double eps, Vec3* grad,
                     Mat3* hess) {
  const double pn = n.dot(phi);
  const Vec3 pt = phi - pn * n;
  const double rn = std::sqrt(pn * pn + eps * eps);
  const double gn = mu_t * fn / rn;
  double e = mu_t * fn * (rn - eps);
  *grad = gn * pn * n;
  if (hess) *hess = gn * n * n.transpose();
  if (mu_r > 0) {  // condim 6
    const double rt = std::sqrt(pt.squaredNorm() + eps * eps);
    const double gt = mu_r * fn / rt;
    e += mu_r * fn * (rt - eps);
    *grad += gt * pt;
    if (hess) *hess += gt * (Mat3::Identity() - n * n.transpose());
  }
  return e;
}

}  // namespace pliant::articulated
