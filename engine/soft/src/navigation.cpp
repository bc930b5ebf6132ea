// Gaits as motion primitives, RRT* (OMPL), closed-loop execution
// (see navigation.h).
#include "pliant/soft/navigation.h"

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "pliant/soft/dmp.h"

#ifdef PLIANT_SOFT_HAVE_OMPL
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/terminationconditions/IterationTerminationCondition.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>
#endif

namespace pliant::soft {
namespace {

double wrap(double a) { return std::remainder(a, 2 * M_PI); }

// Progress speed of the turning gaits relative to the forward gait's.
constexpr double kTurnSpeedFraction = 0.3;

// The executor aims for (the cost to go's goal cells) and stops in a disc of this
// fraction of the goal tolerance, so a run ends well inside the tolerance rather
// than where the COM first grazes its edge (0.198 m of 0.2 before). Once inside the
// tolerance disc it plays only gaits that keep the COM inside, for at most
// kApproachPeriods periods.
constexpr double kArriveFraction = 0.5;
constexpr int kApproachPeriods = 8;

double clearance(const NavSettings& nav, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& o : nav.obstacles) best = std::min(best, (p - o.center_m).norm() - o.radius_m);
  return best;
}

int period_frames(const Problem& p) { return std::max(1, int(std::lround(p.dmp.period_s / p.sim.dt_s))); }

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

#ifdef PLIANT_SOFT_HAVE_OMPL
namespace ob = ompl::base;
namespace og = ompl::geometric;

// Goal: the disc of radius `tol` around (gx, gz); samples its centre.
class DiscGoal : public ob::GoalSampleableRegion {
 public:
  DiscGoal(const ob::SpaceInformationPtr& si, double gx, double gz, double tol)
      : ob::GoalSampleableRegion(si), gx_(gx), gz_(gz) {
    setThreshold(tol);
  }
  double distanceGoal(const ob::State* st) const override {
    const auto* s = st->as<ob::RealVectorStateSpace::StateType>();
    return std::hypot(s->values[0] - gx_, s->values[1] - gz_);
  }
  void sampleGoal(ob::State* st) const override {
    auto* s = st->as<ob::RealVectorStateSpace::StateType>();
    s->values[0] = gx_;
    s->values[1] = gz_;
  }
  unsigned int maxSampleCount() const override { return 1u << 30; }

 private:
  double gx_, gz_;
};
#endif

}  // namespace

bool navigation_available() {
#ifdef PLIANT_SOFT_HAVE_OMPL
  return true;
#else
  return false;
#endif
}

Objectives gait_objectives(const NavSettings& nav, int k) {
  Objectives o;
  o.w_turn = 10;
  o.turn_axis = nav.body_axis;
  // Turning gaits turn nearly in place (30% of the walking speed): with the full
  // speed the spider's turns were crab-like arcs of radius 0.6 m that brought it
  // beside the goal facing away (0.43 m short); in place it turns to face the goal.
  o.turn_speed_m_per_s = k == 0 ? nav.speed_m_per_s : kTurnSpeedFraction * nav.speed_m_per_s;
  o.turn_rate_rad_per_s = k == 0 ? 0.0 : k == 1 ? nav.turn_rate_rad_per_s : -nav.turn_rate_rad_per_s;
  return o;
}

Eigen::Vector3d planar_pose(const SoftState& s, const Eigen::Vector3d& body_axis) {
  return {s.c[0], s.c[2], heading_yaw(s, body_axis)};
}

double body_radius_m(const Character& ch) {
  double r = 0;
  for (int j = 0; j < ch.lattice.nodes(); ++j) {
    const Eigen::Vector3d d = ch.rest_local.segment<3>(3 * j);
    r = std::max(r, std::hypot(d[0], d[2]));
  }
  return r;
}

bool mirror_gait(const Problem& p, const Eigen::VectorXd& theta, Eigen::VectorXd* mirrored) {
  const Character& ch = *p.character;
  const Lattice& lat = ch.lattice;
  const int n = lat.nodes();
  const double h = lat.cell_size_m, zc = ch.rest_com[2];
  // Nodes sit on a grid: key positions by quarter cells.
  auto key = [h](const Eigen::Vector3d& x) {
    return std::make_tuple(std::llround(4 * x[0] / h), std::llround(4 * x[1] / h), std::llround(4 * x[2] / h));
  };
  std::map<std::tuple<long long, long long, long long>, int> index;
  for (int j = 0; j < n; ++j) index[key(lat.rest[j])] = j;
  std::vector<int> mirror(n);
  for (int j = 0; j < n; ++j) {
    Eigen::Vector3d y = lat.rest[j];
    y[2] = 2 * zc - y[2];
    const auto it = index.find(key(y));
    if (it == index.end() || (lat.rest[it->second] - y).norm() > 1e-6 * h) return false;
    mirror[j] = it->second;
  }
  const int K = p.dmp.kernels + 1;
  *mirrored = theta;
  for (int k = 0; k < p.dmp.modes; ++k) {
    const Eigen::VectorXd u = ch.basis.U.col(k);
    double parity = 0;
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector3d a = u.segment<3>(3 * j), b = u.segment<3>(3 * mirror[j]);
      parity += lat.node_mass_kg[j] * (a[0] * b[0] + a[1] * b[1] - a[2] * b[2]);
    }
    if (std::abs(std::abs(parity) - 1) > 0.05) return false;  // mode mixes under the mirror
    if (parity < 0) mirrored->segment(k * K, K) *= -1;
  }
  return true;
}

Gait measure_gait(const Problem& p, const std::string& name, const Eigen::VectorXd& theta,
                  const Eigen::Vector3d& body_axis, int warmup, int periods) {
  const int P = period_frames(p);
  std::vector<Eigen::Vector3d> poses;
  int frame = 0;
  simulate(p, theta, P * (warmup + periods), [&](const SoftState& s) {
    ++frame;
    if (frame % P == 0 && frame >= P * warmup) poses.push_back(planar_pose(s, body_axis));
  });
  Gait g;
  g.name = name;
  g.theta = theta;
  for (size_t k = 0; k + 1 < poses.size(); ++k) {
    const Eigen::Vector3d a = poses[k], b = poses[k + 1];
    const double c = std::cos(a[2]), s = std::sin(a[2]);
    const double dx = b[0] - a[0], dz = b[1] - a[1];
    g.forward_m += (c * dx + s * dz) / periods;
    g.side_m += (-s * dx + c * dz) / periods;
    g.yaw_rad += wrap(b[2] - a[2]) / periods;
  }
  return g;
}

std::vector<Eigen::Vector3d> plan_dubins_path(const Eigen::Vector3d& start, const NavSettings& nav, double rho,
                                              double inflate, unsigned seed) {
#ifndef PLIANT_SOFT_HAVE_OMPL
  (void)start, (void)nav, (void)rho, (void)inflate, (void)seed;
  throw std::runtime_error("navigation needs OMPL (libompl-dev); this build has none");
#else
  ompl::msg::setLogLevel(ompl::msg::LOG_ERROR);
  static bool seeded = false;  // OMPL's seed can be set once, before its first RNG
  if (!seeded) {
    ompl::RNG::setSeed(seed);
    seeded = true;
  }
  // RRT* over positions (straight edges, symmetric cost as RRT* needs); the
  // curvature limit of the gaits is left to the pure-pursuit executor. Planning in
  // OMPL's Dubins space was tried: the symmetric variant returned paths with
  // backwards loops and the forward-only one rarely found a path in the budget.
  (void)rho;
  auto space = std::make_shared<ob::RealVectorStateSpace>(2);
  Eigen::Vector2d lo = start.head<2>().cwiseMin(nav.goal_m), hi = start.head<2>().cwiseMax(nav.goal_m);
  for (const auto& o : nav.obstacles) {
    lo = lo.cwiseMin(o.center_m - Eigen::Vector2d::Constant(o.radius_m));
    hi = hi.cwiseMax(o.center_m + Eigen::Vector2d::Constant(o.radius_m));
  }
  const double margin = 2 * inflate + nav.goal_tolerance_m;
  ob::RealVectorBounds b(2);
  b.setLow(0, lo[0] - margin), b.setHigh(0, hi[0] + margin);
  b.setLow(1, lo[1] - margin), b.setHigh(1, hi[1] + margin);
  space->setBounds(b);
  og::SimpleSetup ss(space);
  const ob::SpaceInformationPtr si = ss.getSpaceInformation();
  // Raw pointer: capturing the shared_ptr would make a cycle (si owns the checker).
  const ob::SpaceInformation* sip = si.get();
  ss.setStateValidityChecker([&nav, inflate, sip](const ob::State* st) {
    const auto* s = st->as<ob::RealVectorStateSpace::StateType>();
    return sip->satisfiesBounds(st) && clearance(nav, Eigen::Vector2d(s->values[0], s->values[1])) > inflate;
  });
  si->setStateValidityCheckingResolution(0.002);
  ob::ScopedState<ob::RealVectorStateSpace> s0(space);
  s0[0] = start[0];
  s0[1] = start[1];
  ss.setStartState(s0);
  ss.setGoal(std::make_shared<DiscGoal>(si, nav.goal_m[0], nav.goal_m[1], nav.goal_tolerance_m * 0.5));
  auto planner = std::make_shared<og::RRTstar>(si);
  ss.setPlanner(planner);
  ss.setup();
  const ob::PlannerTerminationCondition ptc = ob::plannerOrTerminationCondition(
      ob::timedPlannerTerminationCondition(nav.planning_time_s), ob::IterationTerminationCondition(20000));
  ss.solve(ptc);
  if (!ss.haveExactSolutionPath())
    throw std::runtime_error("navigation: RRT* found no path to the goal around the obstacles (turning radius " +
                             std::to_string(rho) + " m, obstacles inflated by " + std::to_string(inflate) + " m)");
  og::PathGeometric path = ss.getSolutionPath();
  ss.getPathSimplifier()->shortcutPath(path);  // straight shortcuts where collision-free
  path.interpolate(std::max(50, int(path.length() / 0.01)));
  std::vector<Eigen::Vector3d> out;
  for (const ob::State* st : path.getStates()) {
    const auto* s = st->as<ob::RealVectorStateSpace::StateType>();
    out.emplace_back(s->values[0], s->values[1], start[2]);
  }
  for (size_t i = 0; i + 1 < out.size(); ++i)  // heading of the path
    out[i][2] = std::atan2(out[i + 1][1] - out[i][1], out[i + 1][0] - out[i][0]);
  if (out.size() > 1) out.back()[2] = out[out.size() - 2][2];
  return out;
#endif
}

namespace {

// Motion of one period in the body frame of its start pose a.
Primitive relative_motion(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::cos(a[2]), s = std::sin(a[2]);
  const double dx = b[0] - a[0], dz = b[1] - a[1];
  return {c * dx + s * dz, -s * dx + c * dz, wrap(b[2] - a[2])};
}

}  // namespace

std::vector<Eigen::Vector3d> transition_primitives(const Problem& p, const std::vector<Gait>& gaits,
                                                   const Eigen::Vector3d& body_axis, int warmup) {
  const Character& ch = *p.character;
  const int G = int(gaits.size()), P = period_frames(p);
  const double a_max = max_activation_m(ch, p.dmp);
  std::vector<Eigen::Vector3d> out(size_t(G) * G);
  auto play = [&](const Eigen::VectorXd& theta, SoftState& s, DmpState& d) {
    for (int f = 0; f < P; ++f) {
      const Eigen::VectorXd& y = dmp_step(p.dmp, theta, p.sim.dt_s, d);
      reduced_step(ch, p.env, p.sim, control_force(ch, y, a_max), s);
    }
  };
#pragma omp parallel for schedule(dynamic, 1) if (G > 1)
  for (int prev = 0; prev < G; ++prev) {
    SoftState s = initial_state(ch, p.start_offset_m, Eigen::Vector3d::Zero(), p.sim.dt_s);
    DmpState d = dmp_init(p.dmp);
    for (int k = 0; k < warmup; ++k) play(gaits[size_t(prev)].theta, s, d);
    const Eigen::Vector3d from = planar_pose(s, body_axis);
    for (int g = 0; g < G; ++g) {
      SoftState x = s;
      DmpState e = d;
      play(gaits[size_t(g)].theta, x, e);
      const Primitive m = relative_motion(from, planar_pose(x, body_axis));
      out[size_t(prev * G + g)] = {m.forward_m, m.side_m, m.yaw_rad};
    }
  }
  return out;
}

namespace {

// One node of the executor's search: the state after a sequence of re-simulated
// periods that starts with gait `first` and ends with gait `gait`.
struct SearchNode {
  SoftState s;
  DmpState dmp;
  int first = 0, gait = 0, layer = 0;  // layer of the cost to go (PrimitiveCostToGo)
  std::vector<SoftState> states;  // frames of the first period (depth-1 nodes only)
  double min_clearance = std::numeric_limits<double>::infinity();
  int goal_frame = -1;  // frame of the search (from 0) at which the arrival disc was entered
  double max_goal_distance = 0;  // largest COM-to-goal distance over `states`
  double score = std::numeric_limits<double>::infinity();
};

}  // namespace

NavResult navigate(const Problem& p, const std::vector<Gait>& gaits, const NavSettings& nav,
                   const std::function<void(const SoftState&, int)>& on_frame) {
  const Character& ch = *p.character;
  const int G = int(gaits.size());
  NavResult res;
  // Turning radius from the turning gaits: speed over yaw rate, per period.
  double rho = 0;
  int turns = 0;
  for (size_t k = 1; k < gaits.size(); ++k)
    if (std::abs(gaits[k].yaw_rad) > 1e-6) {
      rho += std::hypot(gaits[k].forward_m, gaits[k].side_m) / std::abs(gaits[k].yaw_rad);
      ++turns;
    }
  const double radius = body_radius_m(ch);
  rho = turns ? std::max(rho / turns, 0.1 * radius) : 10 * radius;
  res.turning_radius_m = rho;
  const double inflate = radius + nav.clearance_m;

  const int P = period_frames(p);
  SoftState s = initial_state(ch, p.start_offset_m, Eigen::Vector3d::Zero(), p.sim.dt_s);
  const Eigen::Vector3d pose_start = planar_pose(s, nav.body_axis);
  const std::vector<Eigen::Vector3d> path = plan_dubins_path(pose_start, nav, rho, inflate);
  res.planned = path;
  double step = 0;
  for (const auto& g : gaits) step = std::max(step, std::hypot(g.forward_m, g.side_m));
  if (step <= 1e-6) throw std::runtime_error("navigation: no gait moves the body (primitives of zero length)");
  // The RRT* path is the route's plan; execution replans every period from the
  // re-simulated pose through the primitives' cost to go (also heading-aware: a
  // body facing away must turn first).
  // The COM keeps half the body radius (plus the clearance) from an obstacle's
  // footprint: legs may brush the rock (it is simulated too, and a quarter radius
  // let the spider walk into it and stick); with the whole radius a wide body
  // such as the spider (radius 0.52 m, turning radius 0.6 m) has no primitive
  // sequence around the rock from its start pose.
  const double keep_out = 0.5 * radius + nav.clearance_m;
  // Edges: the held gaits' measured primitives, and for a switch the period after
  // it measured from a held previous gait.
  std::vector<Primitive> held(static_cast<size_t>(G)), trans(static_cast<size_t>(G * G));
  {
    const std::vector<Eigen::Vector3d> tr = transition_primitives(p, gaits, nav.body_axis);
    for (int g = 0; g < G; ++g) held[size_t(g)] = {gaits[size_t(g)].forward_m, gaits[size_t(g)].side_m, gaits[size_t(g)].yaw_rad};
    for (size_t k = 0; k < tr.size(); ++k) trans[k] = {tr[k][0], tr[k][1], tr[k][2]};
  }
  const PrimitiveCostToGo cost_to_go(held, trans, nav, pose_start.head<2>(), keep_out, step);

  DmpState d = dmp_init(p.dmp);
  const double a_max = max_activation_m(ch, p.dmp);
  const Eigen::Vector2d goal = nav.goal_m;
  auto planar = [](const SoftState& x) { return Eigen::Vector2d(x.c[0], x.c[2]); };
  // Final approach: entering the tolerance disc does not end the run (the COM
  // may graze its edge, and a different compiler's rounding would move it just
  // outside); execution goes on, with only gaits whose whole period stays inside
  // the disc, until the COM is within `arrive`, no gait stays inside, or
  // kApproachPeriods periods have been played inside the disc. So once inside,
  // the run ends inside.
  const double arrive = kArriveFraction * nav.goal_tolerance_m;
  int approach_periods = 0;
  res.com.push_back(s.c);
  res.min_clearance_m = clearance(nav, planar(s));
  int frame = 0;
  // Re-simulates one period of gait g from node `from` into `to`.
  auto expand = [&](const SearchNode& from, int g, int frames_left, int frames_before, bool keep, SearchNode& to) {
    to.s = from.s;
    to.dmp = from.dmp;
    to.gait = g;
    to.min_clearance = from.min_clearance;
    to.goal_frame = from.goal_frame;
    to.states.clear();
    to.max_goal_distance = 0;
    for (int f = 0; f < std::min(P, frames_left) && to.goal_frame < 0; ++f) {
      const Eigen::VectorXd& y = dmp_step(p.dmp, gaits[size_t(g)].theta, p.sim.dt_s, to.dmp);
      reduced_step(ch, p.env, p.sim, control_force(ch, y, a_max), to.s);
      if (keep) to.states.push_back(to.s);
      to.min_clearance = std::min(to.min_clearance, clearance(nav, planar(to.s)));
      const double dist = (planar(to.s) - goal).norm();
      if (!(dist <= to.max_goal_distance)) to.max_goal_distance = dist;  // NaN propagates
      if (dist <= arrive) to.goal_frame = frames_before + f;
    }
  };
  // Score of a leaf: periods to go (plus the distance to the goal in steps / 10 to
  // break ties); a sequence that brings the COM closer than keep_out to an
  // obstacle's footprint is penalized; one that enters the goal disc wins, the
  // sooner the better.
  auto score = [&](const SearchNode& n) {
    if (n.goal_frame >= 0) return -1e6 + n.goal_frame;
    const Eigen::Vector3d q = planar_pose(n.s, nav.body_axis);
    if (!std::isfinite(q.sum())) return std::numeric_limits<double>::infinity();
    const double dist = (q.head<2>() - goal).norm() / step;
    const double ctg = cost_to_go(q, n.layer);
    double v = (std::isfinite(ctg) ? ctg : 1000 + dist) + 0.1 * dist;
    if (n.min_clearance < keep_out) v += 1e4 * (1 + (keep_out - n.min_clearance) / keep_out);
    return v;
  };
  std::vector<SearchNode> level1(static_cast<size_t>(G));
  SearchNode root;
  int last = -1;           // gait of the previous period (-1: at rest)
  bool last_fresh = false;  // it was a switch
  while (frame < nav.max_frames && (planar(s) - goal).norm() > arrive) {
    const bool inside = (planar(s) - goal).norm() <= nav.goal_tolerance_m;
    if (inside && approach_periods++ >= kApproachPeriods) break;
    // Every allowed gait is re-simulated for a period from the current state (the
    // DMP keeps its phase and activations across switches); the one whose end pose
    // has the smallest cost to go is played. A switch is held for at least two
    // periods (switching every period does not move the body as the primitives say).
    const int frames_left = nav.max_frames - frame;
    root.s = s;
    root.dmp = d;
    root.min_clearance = std::numeric_limits<double>::infinity();
    root.goal_frame = -1;
#pragma omp parallel for schedule(dynamic, 1) if (G > 1)
    for (int g = 0; g < G; ++g) {
      SearchNode& n = level1[size_t(g)];
      n.first = g;
      n.states.clear();
      n.score = std::numeric_limits<double>::infinity();
      if (last_fresh && g != last && !inside) continue;
      expand(root, g, frames_left, 0, true, n);
      if (inside && !(n.max_goal_distance <= nav.goal_tolerance_m)) continue;  // would leave the disc
      n.layer = g == last ? PrimitiveCostToGo::settled(g) : cost_to_go.fresh(g);
      n.score = score(n);
    }
    int choice = 0;
    for (int g = 1; g < G; ++g)
      if (level1[size_t(g)].score < level1[size_t(choice)].score) choice = g;
    const SearchNode& c = level1[size_t(choice)];
    if (inside && !std::isfinite(c.score)) break;  // every gait would leave the disc: stay
    if (c.states.empty() || !std::isfinite(c.states.back().c.sum()))
      throw std::runtime_error("navigation: the reduced simulation diverged at frame " + std::to_string(frame));
    res.gait_sequence.push_back(choice);
    for (const SoftState& x : c.states) {
      ++frame;
      res.com.push_back(x.c);
      res.min_clearance_m = std::min(res.min_clearance_m, clearance(nav, planar(x)));
      if (on_frame) on_frame(x, choice);
    }
    last_fresh = choice != last;
    last = choice;
    s = c.states.back();
    d = c.dmp;
  }
  res.final_distance_m = (planar(s) - goal).norm();
  res.reached = res.final_distance_m <= nav.goal_tolerance_m;
  return res;
}

}  // namespace pliant::soft
