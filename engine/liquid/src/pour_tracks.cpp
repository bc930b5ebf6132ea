// Streamline recording and the quadratic-streamline objective C_OBJ (Eq. 2.6).
#include "pliant/liquid/pour_tracks.h"

#include <Eigen/Dense>
#include <cmath>

namespace pliant::liquid {

PourTracks::PourTracks(const LiquidModel& m, const LiquidState& s) : m_(m) {
  const size_t n = s.count();
  tracks_.resize(n);
  in_source_.resize(n);
  last_.resize(n);
  const Pose pose = source_pose_at(m, s.time_s);
  for (size_t p = 0; p < n; ++p) {
    last_[p] = {s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]};
    in_source_[p] = m.has_source && m.source.shape.in_cavity(pose.to_local(last_[p]), m.dim);
  }
  last_time_ = s.time_s;
}

Vec3 PourTracks::opening_centre(double t) const {
  return target_pose_at(m_, t).to_world({0, m_.target.shape.height_m, 0});
}

void PourTracks::record(const LiquidState& s) {
  const Pose pose = source_pose_at(m_, s.time_s);
  // Rim height now and one frame ago (a FOLLOW target may move vertically too).
  const double rim = opening_centre(s.time_s)[1], rim_last = opening_centre(last_time_)[1];
  const size_t n = tracks_.size();
  for (size_t p = 0; p < n && p < s.count(); ++p) {
    const Vec3 x{s.x[3 * p], s.x[3 * p + 1], s.x[3 * p + 2]};
    Track& t = tracks_[p];
    const bool in = m_.has_source && m_.source.shape.in_cavity(pose.to_local(x), m_.dim);
    if (in_source_[p] && !in && t.leave_time < 0) {
      t.leave_time = s.time_s;
      t.flight.push_back({s.time_s, x[0], x[1], x[2]});
    } else if (t.leave_time >= 0 && !t.landed) {
      const double h1 = x[1] - rim, h0 = last_[p][1] - rim_last;
      if (h1 < 0 && h0 >= 0) {
        const double a = h0 / std::max(1e-12, h0 - h1);
        t.landed = true;
        for (int c = 0; c < 3; ++c) t.landing[c] = last_[p][c] + a * (x[c] - last_[p][c]);
        t.landing_time = last_time_ + a * (s.time_s - last_time_);
        // The miss is measured against the opening where it is at that time.
        const Vec3 oc = opening_centre(t.landing_time);
        for (int c = 0; c < 3; ++c) t.landing_offset[c] = t.landing[c] - oc[c];
      } else if (h1 >= 0) {
        t.flight.push_back({s.time_s, x[0], x[1], x[2]});
      }
    }
    in_source_[p] = in;
    last_[p] = x;
  }
  last_time_ = s.time_s;
}

double PourTracks::objective(double eps, int* useful) const {
  double sum = 0;
  int count = 0;
  for (const Track& t : tracks_) {
    const size_t k = t.flight.size();
    if (k < 3) continue;
    // Least-squares quadratic per axis in time.
    Eigen::MatrixXd A(k, 3);
    Eigen::MatrixXd B(k, 3);
    const double t0 = t.flight[0][0];
    for (size_t i = 0; i < k; ++i) {
      const double dt = t.flight[i][0] - t0;
      A(i, 0) = 1, A(i, 1) = dt, A(i, 2) = dt * dt;
      for (int c = 0; c < 3; ++c) B(i, c) = t.flight[i][1 + c];
    }
    const Eigen::MatrixXd coef = A.colPivHouseholderQr().solve(B);
    const double rms = std::sqrt((A * coef - B).squaredNorm() / double(k));
    if (rms > eps) continue;  // not a free-flight streamline (still sliding, splashing)
    // Crossing of the rim height: y(t) = rim on the descending branch (the rim
    // where the target is when the particle left; FOLLOW targets move
    // horizontally in the generator).
    const Vec3 oc0 = opening_centre(t0);
    const double a = coef(2, 1), b = coef(1, 1), c = coef(0, 1) - oc0[1];
    double tc;
    if (std::abs(a) < 1e-12) {
      if (std::abs(b) < 1e-12) continue;
      tc = -c / b;
    } else {
      const double disc = b * b - 4 * a * c;
      if (disc < 0) continue;
      tc = (-b - std::sqrt(disc)) / (2 * a);  // a < 0 under gravity: the later root
      if (a > 0) tc = (-b + std::sqrt(disc)) / (2 * a);
    }
    Vec3 q;
    for (int ax = 0; ax < 3; ++ax) q[ax] = coef(0, ax) + coef(1, ax) * tc + coef(2, ax) * tc * tc;
    // Distance to the opening centre where the target is at the crossing time.
    const Vec3 centre = opening_centre(t0 + tc);
    double d2 = 0;
    for (int ax = 0; ax < m_.dim; ++ax)
      if (ax != 1) d2 += (q[ax] - centre[ax]) * (q[ax] - centre[ax]);
    sum += std::sqrt(d2);
    ++count;
  }
  if (useful) *useful = count;
  return sum;
}

}  // namespace pliant::liquid
