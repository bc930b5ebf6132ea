// Fixed-seed generator of random liquid-transfer problems (section 2.6's
// dataset and the benchmark): container shape, fill, target offset and size,
// viscosity. Every fifth problem (id % 5 == 0) belongs to the held-out split
// that training and tuning never see, in both families:
// - TRANSFER+ZERO: static target, liquid starting at rest;
// - TRANSFER+FOLLOW: the same problem (same draws) with the target moving at a
//   constant horizontal velocity of 1.5..4 cm/s, away from the domain edge it
//   is nearer to, so it stays inside the domain for the whole run.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pliant/liquid/liquid.h"

namespace pliant::liquid {

enum class Family { Zero, Follow };
const char* family_name(Family f);  // "transfer_zero" | "transfer_follow"

struct TransferProblem {
  int id = 0;
  std::string family = "transfer_zero";
  bool held_out = false;
  LiquidModel model;  // planner unset (None); frames cover pour and settling
};

// Problem `id` of the sequence for `seed` (independent of the others, so a
// sweep shard can generate just its own).
TransferProblem generate_problem(int id, uint64_t seed, int dim = 2, Family family = Family::Zero);
std::vector<TransferProblem> held_out_problems(int count, uint64_t seed, int dim = 2,
                                               Family family = Family::Zero);

}  // namespace pliant::liquid
