// Internals of the soft navigation (navigation.cpp, navigation_rrt.cpp): planar-pose
// helpers, the gait primitives' planar motion and their cost to go over a
// (x, z, yaw, gait layer) lattice, which the executor (navigate) follows.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "pliant/soft/navigation.h"

namespace pliant::soft {

inline double wrap(double a) { return std::remainder(a, 2 * M_PI); }

// Progress speed of the turning gaits relative to the forward gait's.
constexpr double kTurnSpeedFraction = 0.3;

// The executor aims for (the cost to go's goal cells) and stops in a disc of this
// fraction of the goal tolerance, so a run ends well inside the tolerance rather
// than where the COM first grazes its edge (0.198 m of 0.2 before). Once inside the
// tolerance disc it plays only gaits that keep the COM inside, for at most
// kApproachPeriods periods.
constexpr double kArriveFraction = 0.5;
constexpr int kApproachPeriods = 8;

inline double clearance(const NavSettings& nav, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& o : nav.obstacles) best = std::min(best, (p - o.center_m).norm() - o.radius_m);
  return best;
}

inline int period_frames(const Problem& p) { return std::max(1, int(std::lround(p.dmp.period_s / p.sim.dt_s))); }

// Planar motion of one controller period in the body frame at its start.
struct Primitive {
  double forward_m = 0, side_m = 0, yaw_rad = 0;
};

// Cost to go of the gait primitives: periods needed to reach the goal disc from a
// planar pose (x, z, yaw) and the gait history. The gaits are not stationary: the
// period after a switch moves differently from a held gait (the DMP activations lag
// the parameters; the spider's right gait turns 0.15 rad right in the period after
// forward, then barely turns), and switching back and forth every period does not
// move the body as any held-gait primitive predicts. So the lattice has one layer
// per (gait, settled or just switched): a settled gait may be held (its measured
// primitive) or switched (the transition primitive measured after holding it); a
// just-switched gait is held one more period (the held primitive) and is then
// settled. Cells are about a third of a step in x and z, 72 yaw bins. A
// breadth-first search backwards from the goal cells gives the number of periods
// (edges all cost one period): the primitives' optimal policy from every pose at
// once, so the executor can replan from wherever the re-simulated body actually is
// without running a planner again.
class PrimitiveCostToGo {
 public:
  // Layers: g (gait g settled), G + g (gait g just switched to).
  static int settled(int g) { return g; }
  int fresh(int g) const { return G_ + g; }
  // held[g]: gait g held; trans[prev * G + g]: gait g in the period after settled prev.
  PrimitiveCostToGo(const std::vector<Primitive>& held, const std::vector<Primitive>& trans, const NavSettings& nav,
                    const Eigen::Vector2d& start, double inflate, double step)
      : G_(int(held.size())), L_(2 * int(held.size())) {
    Eigen::Vector2d lo = start.cwiseMin(nav.goal_m), hi = start.cwiseMax(nav.goal_m);
    for (const auto& o : nav.obstacles) {
      lo = lo.cwiseMin(o.center_m - Eigen::Vector2d::Constant(o.radius_m));
      hi = hi.cwiseMax(o.center_m + Eigen::Vector2d::Constant(o.radius_m));
    }
    const double margin = 2 * inflate + nav.goal_tolerance_m + 8 * step;  // room to loop around
    lo_ = lo - Eigen::Vector2d::Constant(margin);
    const Eigen::Vector2d ext = hi - lo + Eigen::Vector2d::Constant(2 * margin);
    h_ = std::max(0.35 * step, std::sqrt(ext[0] * ext[1] / 12000.0));  // at most ~12k cells per yaw bin
    nx_ = int(std::ceil(ext[0] / h_)) + 1;
    nz_ = int(std::ceil(ext[1] / h_)) + 1;
    const int plane = nx_ * nz_, layer = plane * kYaw, n = layer * L_;
    std::vector<char> free(size_t(plane), 0);
    for (int c = 0; c < plane; ++c) {
      const Eigen::Vector2d x(lo_[0] + (c % nx_) * h_, lo_[1] + (c / nx_) * h_);
      free[size_t(c)] = clearance(nav, x) > inflate;
    }
    // Per (yaw bin, layer, gait): the edge's offset in x and z, its end yaw bin and
    // layer (-1: no such edge); the same for every cell of a plane.
    struct Edge {
      double dx = 0, dz = 0;
      int a = 0, layer = -1;
    };
    std::vector<Edge> edges(size_t(kYaw) * L_ * G_);
    for (int a = 0; a < kYaw; ++a)
      for (int l = 0; l < L_; ++l)
        for (int g = 0; g < G_; ++g) {
          const int from = l % G_;
          const bool is_fresh = l >= G_;
          if (is_fresh && g != from) continue;
          const Primitive& m = g == from ? held[size_t(g)] : trans[size_t(from * G_ + g)];
          const double yaw = a * 2 * M_PI / kYaw, cs = std::cos(yaw), sn = std::sin(yaw);
          int b = int(std::lround((yaw + m.yaw_rad) / (2 * M_PI / kYaw))) % kYaw;
          if (b < 0) b += kYaw;
          edges[(size_t(a) * L_ + size_t(l)) * G_ + size_t(g)] = {cs * m.forward_m - sn * m.side_m,
                                                                   sn * m.forward_m + cs * m.side_m, b,
                                                                   g == from ? settled(g) : fresh(g)};
        }
    // Successor of cell c under gait g (-1: no edge, blocked or off the lattice).
    auto successor = [&](int c, int g) {
      const int i = c % nx_, k = (c / nx_) % nz_, a = (c / plane) % kYaw, l = c / layer;
      const Edge& e = edges[(size_t(a) * L_ + size_t(l)) * G_ + size_t(g)];
      if (e.layer < 0 || !free[size_t(k * nx_ + i)]) return -1;
      const double x = lo_[0] + i * h_ + e.dx, z = lo_[1] + k * h_ + e.dz;
      const int ii = int(std::lround((x - lo_[0]) / h_)), kk = int(std::lround((z - lo_[1]) / h_));
      if (ii < 0 || kk < 0 || ii >= nx_ || kk >= nz_ || !free[size_t(kk * nx_ + ii)]) return -1;
      // The step's midpoint must be free too (steps are a few cells long).
      const int im = int(std::lround((x - 0.5 * e.dx - lo_[0]) / h_)), km = int(std::lround((z - 0.5 * e.dz - lo_[1]) / h_));
      if (im < 0 || km < 0 || im >= nx_ || km >= nz_ || !free[size_t(km * nx_ + im)]) return -1;
      return ((e.layer * kYaw + e.a) * nz_ + kk) * nx_ + ii;
    };
    // Reverse edges in CSR form (who reaches cell j with one primitive); successors
    // are recomputed in the second pass rather than stored, and start_of counts
    // down to each range's start while it is filled.
    // Both passes run in parallel: the order of a cell's predecessors varies, the
    // breadth-first distances do not.
    std::vector<int> start_of(size_t(n) + 1, 0);
#pragma omp parallel for schedule(static)
    for (int c = 0; c < n; ++c)
      for (int g = 0; g < G_; ++g) {
        const int j = successor(c, g);
        if (j >= 0) {
#pragma omp atomic
          ++start_of[size_t(j)];
        }
      }
    for (int j = 0; j < n; ++j) start_of[size_t(j) + 1] += start_of[size_t(j)];
    std::vector<int> pred(static_cast<size_t>(start_of[size_t(n)]));
#pragma omp parallel for schedule(static)
    for (int c = 0; c < n; ++c)
      for (int g = 0; g < G_; ++g) {
        const int j = successor(c, g);
        if (j < 0) continue;
        int at;
#pragma omp atomic capture
        at = --start_of[size_t(j)];
        pred[size_t(at)] = c;
      }
    cost_.assign(size_t(n), kUnreached);
    std::vector<int> queue;
    queue.reserve(size_t(n));
    // Goal cells: centre inside the arrival disc (half the tolerance; the
    // re-simulated motion differs from the primitives by a few centimetres per period).
    for (int c = 0; c < n; ++c) {
      const Eigen::Vector2d x(lo_[0] + (c % nx_) * h_, lo_[1] + ((c / nx_) % nz_) * h_);
      if ((x - nav.goal_m).norm() <= kArriveFraction * nav.goal_tolerance_m) cost_[size_t(c)] = 0, queue.push_back(c);
    }
    for (size_t q = 0; q < queue.size(); ++q) {
      const int j = queue[q];
      for (int e = start_of[size_t(j)]; e < start_of[size_t(j) + 1]; ++e) {
        const int c = pred[size_t(e)];
        if (cost_[size_t(c)] == kUnreached) cost_[size_t(c)] = cost_[size_t(j)] + 1, queue.push_back(c);
      }
    }
  }
  // Periods to the goal from pose (x, z, yaw) in layer l. The lattice's cell, or
  // where that is unreached (the body is often between the primitives' poses), the
  // cheapest cell with another yaw (one period per 0.1 rad of difference, about the
  // turning gaits' rate) or a neighbouring position (half a period); infinity when
  // none is reached or the pose is off the lattice.
  double operator()(const Eigen::Vector3d& pose, int l) const {
    const int c = cell(pose, l);
    if (c < 0) return std::numeric_limits<double>::infinity();
    if (cost_[size_t(c)] != kUnreached) return cost_[size_t(c)];
    const int i = c % nx_, k = (c / nx_) % nz_, a = (c / (nx_ * nz_)) % kYaw;
    double best = std::numeric_limits<double>::infinity();
    for (int da = -kYaw / 2; da <= kYaw / 2; ++da)
      for (int dk = -1; dk <= 1; ++dk)
        for (int di = -1; di <= 1; ++di) {
          const int ii = i + di, kk = k + dk, aa = ((a + da) % kYaw + kYaw) % kYaw;
          if (ii < 0 || kk < 0 || ii >= nx_ || kk >= nz_) continue;
          const int v = cost_[size_t(((l * kYaw + aa) * nz_ + kk) * nx_ + ii)];
          if (v != kUnreached)
            best = std::min(best, v + std::abs(da) * (2 * M_PI / kYaw) / 0.1 + ((di || dk) ? 0.5 : 0.0));
        }
    return best;
  }

 private:
  static constexpr int kYaw = 180;
  static constexpr int kUnreached = std::numeric_limits<int>::max();
  int cell(const Eigen::Vector3d& pose, int l) const {
    const int i = int(std::lround((pose[0] - lo_[0]) / h_)), k = int(std::lround((pose[1] - lo_[1]) / h_));
    if (i < 0 || k < 0 || i >= nx_ || k >= nz_ || l < 0 || l >= L_) return -1;
    int a = int(std::lround(pose[2] / (2 * M_PI / kYaw))) % kYaw;
    if (a < 0) a += kYaw;
    return ((l * kYaw + a) * nz_ + k) * nx_ + i;
  }
  int G_, L_;
  Eigen::Vector2d lo_;
  double h_ = 0;
  int nx_ = 0, nz_ = 0;
  std::vector<int> cost_;
};

}  // namespace pliant::soft
