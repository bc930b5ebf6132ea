// Small 2D scenes shared by the liquid tests.
#pragma once
#include "pliant/liquid/liquid.h"

namespace pliant::liquid::test {

// A 2D cylinder (cross-section: a U) at rest, filled to `fill` of its height.
inline LiquidModel still_container_2d(double h = 0.01, double fill = 0.6) {
  LiquidModel m;
  m.dim = 2;
  m.domain_min_m = {-0.12, 0, 0};
  m.domain_max_m = {0.12, 0.2, 0};
  m.cell_size_m = h;
  m.n = {int(0.24 / h + 0.5), int(0.2 / h + 0.5), 1};
  m.has_target = false;
  m.source.shape.type = ContainerShape::Cylinder;
  m.source.shape.radius_m = 0.06;
  m.source.shape.height_m = 0.12;
  m.source.shape.wall_m = 0.015;
  m.source.pose.position_m = {0, 0.03, 0};
  m.fill_fraction = fill;
  m.dt_s = 0.02;
  return m;
}

}  // namespace pliant::liquid::test
