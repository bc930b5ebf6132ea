// Gaits as motion primitives, RRT* (OMPL), closed-loop execution
// (see navigation.h).
#include "pliant/soft/navigation.h"

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

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

// Pose after a body-frame motion (forward, side, yaw) from pose (x, z, yaw).
Eigen::Vector3d compose(const Eigen::Vector3d& pose, const Gait& g) {
  const double c = std::cos(pose[2]), s = std::sin(pose[2]);
  return {pose[0] + c * g.forward_m - s * g.side_m, pose[1] + s * g.forward_m + c * g.side_m,
          wrap(pose[2] + g.yaw_rad)};
}

double clearance(const NavSettings& nav, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& o : nav.obstacles) best = std::min(best, (p - o.center_m).norm() - o.radius_m);
  return best;
}

int period_frames(const Problem& p) { return std::max(1, int(std::lround(p.dmp.period_s / p.sim.dt_s))); }

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
  o.turn_speed_m_per_s = nav.speed_m_per_s;
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

NavResult navigate(const Problem& p, const std::vector<Gait>& gaits, const NavSettings& nav,
                   const std::function<void(const SoftState&, int)>& on_frame) {
  const Character& ch = *p.character;
  NavResult res;
  // Dubins radius from the turning gaits: speed over yaw rate, per period.
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
  res.planned = plan_dubins_path(planar_pose(s, nav.body_axis), nav, rho, inflate);
  std::vector<double> arclen(res.planned.size(), 0.0);
  for (size_t i = 1; i < res.planned.size(); ++i)
    arclen[i] = arclen[i - 1] + (res.planned[i].head<2>() - res.planned[i - 1].head<2>()).norm();
  double step = 0;
  for (const auto& g : gaits) step = std::max(step, std::abs(g.forward_m));
  const double lookahead = std::max(3 * step, radius);

  DmpState d = dmp_init(p.dmp);
  const double a_max = max_activation_m(ch, p.dmp);
  res.com.push_back(s.c);
  res.min_clearance_m = clearance(nav, Eigen::Vector2d(s.c[0], s.c[2]));
  size_t idx = 0;
  int frame = 0;
  auto at_goal = [&] { return std::hypot(s.c[0] - nav.goal_m[0], s.c[2] - nav.goal_m[1]) <= nav.goal_tolerance_m; };
  while (frame < nav.max_frames && !at_goal()) {
    // Closest path point ahead of the last one, then the look-ahead target.
    const Eigen::Vector3d pose = planar_pose(s, nav.body_axis);
    size_t best = idx;
    for (size_t i = idx; i < res.planned.size() && arclen[i] <= arclen[idx] + 4 * lookahead; ++i)
      if ((res.planned[i].head<2>() - pose.head<2>()).norm() < (res.planned[best].head<2>() - pose.head<2>()).norm())
        best = i;
    idx = best;
    size_t t = idx;
    while (t + 1 < res.planned.size() && arclen[t] < arclen[idx] + lookahead) ++t;
    const Eigen::Vector3d target = res.planned[t];
    // Pure pursuit: the heading change that points at the target, and the gait whose
    // yaw per period is closest to it (gaits that would end inside an inflated
    // obstacle are avoided).
    int choice = 0;
    double best_score = std::numeric_limits<double>::infinity();
    for (size_t g = 0; g < gaits.size(); ++g) {
      const Eigen::Vector3d q = compose(pose, gaits[g]);
      // Heading error at the predicted pose towards the target (the forward gait then
      // carries the body along its heading), plus the distance left.
      double score = std::abs(wrap(std::atan2(target[1] - q[1], target[0] - q[0]) - q[2])) +
                     (q.head<2>() - target.head<2>()).norm() / std::max(lookahead, 1e-9);
      if (clearance(nav, q.head<2>()) < radius) score += 10;
      if (score < best_score) best_score = score, choice = int(g);
    }
    res.gait_sequence.push_back(choice);
    for (int f = 0; f < P && frame < nav.max_frames; ++f) {
      const Eigen::VectorXd& y = dmp_step(p.dmp, gaits[choice].theta, p.sim.dt_s, d);
      reduced_step(ch, p.env, p.sim, control_force(ch, y, a_max), s);
      ++frame;
      res.com.push_back(s.c);
      res.min_clearance_m = std::min(res.min_clearance_m, clearance(nav, Eigen::Vector2d(s.c[0], s.c[2])));
      if (on_frame) on_frame(s, choice);
      if (at_goal()) break;
    }
  }
  res.final_distance_m = std::hypot(s.c[0] - nav.goal_m[0], s.c[2] - nav.goal_m[1]);
  res.reached = at_goal();
  return res;
}

}  // namespace pliant::soft
