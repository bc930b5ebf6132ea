// Gaits as motion primitives and closed-loop execution (see navigation.h); the
// primitives' cost to go is in navigation_primitives.h, the RRT* route in
// navigation_rrt.cpp.
#include "pliant/soft/navigation.h"

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "navigation_primitives.h"
#include "pliant/soft/dmp.h"

namespace pliant::soft {

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
