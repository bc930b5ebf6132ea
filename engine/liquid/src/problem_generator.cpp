// Random transfer problems, drawn from a per-problem seeded generator.
#include "pliant/liquid/problem_generator.h"

#include <cmath>
#include <random>

namespace pliant::liquid {

const char* family_name(Family f) { return f == Family::Follow ? "transfer_follow" : "transfer_zero"; }

TransferProblem generate_problem(int id, uint64_t seed, int dim, Family family) {
  std::mt19937_64 rng(seed * 1000003ULL + uint64_t(id) * 7919ULL + 17);
  std::uniform_real_distribution<double> U(0, 1);
  auto uni = [&](double a, double b) { return a + (b - a) * U(rng); };
  TransferProblem p;
  p.id = id;
  p.held_out = id % 5 == 0;
  LiquidModel& m = p.model;
  m.dim = dim;
  m.cell_size_m = dim == 3 ? 0.01 : 0.006;
  m.domain_min_m = {-0.15, 0, dim == 3 ? -0.1 : 0.0};
  m.domain_max_m = {0.45, 0.42, dim == 3 ? 0.1 : 0.0};
  for (int a = 0; a < 3; ++a)
    m.n[a] = a < dim ? int(std::ceil((m.domain_max_m[a] - m.domain_min_m[a]) / m.cell_size_m - 1e-9)) : 1;
  m.dt_s = 0.02;
  m.frames = 130;
  const ContainerShape::Type types[] = {ContainerShape::Cylinder, ContainerShape::Box, ContainerShape::Oval,
                                        ContainerShape::Cup, ContainerShape::Bottle};
  ContainerShape& c = m.source.shape;
  c.type = types[int(U(rng) * 5) % 5];
  c.radius_m = uni(0.035, 0.05);
  c.depth_m = c.type == ContainerShape::Oval ? 0.7 * c.radius_m : c.radius_m;
  c.height_m = uni(0.1, 0.14);
  c.wall_m = 0.012;
  c.neck_radius_m = 0.45 * c.radius_m;
  c.body_height_m = 0.65 * c.height_m;
  m.source.pose.position_m = {0, 0.2, 0};
  m.fill_fraction = uni(0.3, 0.7);
  m.viscosity_pa_s = std::exp(uni(std::log(0.001), std::log(0.5)));
  m.target.shape.type = ContainerShape::Cylinder;
  m.target.shape.radius_m = uni(0.055, 0.08);
  m.target.shape.depth_m = m.target.shape.radius_m;
  m.target.shape.height_m = uni(0.06, 0.09);
  m.target.shape.wall_m = 0.012;
  m.target.pose.position_m = {uni(0.17, 0.27), 0, 0};
  m.planner.pour_time_s = 2.0;
  m.planner.iterations = 4;
  m.seed = uint64_t(id) + 1;
  // FOLLOW draws after every ZERO draw, so problem id of both families differs
  // only by the target's motion (side-by-side comparison).
  const double speed = uni(0.015, 0.04);
  if (family == Family::Follow) {
    p.family = family_name(family);
    m.target_velocity_mps = {m.target.pose.position_m[0] < 0.22 ? speed : -speed, 0, 0};
  }
  return p;
}

std::vector<TransferProblem> held_out_problems(int count, uint64_t seed, int dim, Family family) {
  std::vector<TransferProblem> out;
  for (int id = 0; int(out.size()) < count; id += 5) out.push_back(generate_problem(id, seed, dim, family));
  return out;
}

}  // namespace pliant::liquid
