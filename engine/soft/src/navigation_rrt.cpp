// Route planning for the soft navigation (see navigation.h): RRT* (OMPL) over planar
// positions around the inflated obstacles. Without OMPL, plan_dubins_path throws and
// navigation_available() is false.
#include "pliant/soft/navigation.h"

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

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

#include "navigation_primitives.h"

namespace pliant::soft {
namespace {

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

}  // namespace pliant::soft
