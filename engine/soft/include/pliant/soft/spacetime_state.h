// Checkpoint form of a spacetime run between iterations (spacetime.h: SpacetimeCarry
// and SpacetimeReport), beside the OptimizerState's own "PLSO" blob: with both, a
// killed spacetime job resumes bit for bit (spacetime_state.cpp has the layout).
#pragma once
#include <cstdint>
#include <vector>

#include "pliant/soft/spacetime.h"

namespace pliant::soft {

struct SpacetimeCheckpoint {
  int iteration = 0;  // OptimizerState::iteration it belongs to
  SpacetimeCarry carry;
  SpacetimeReport report;
};

// Versioned little-endian bytes, all doubles; `tag` is the caller's (a scene hash),
// returned by deserialize. deserialize throws std::runtime_error naming the problem
// and the byte (bad magic, version, CRC, sizes that disagree, truncation, trailing
// bytes); up to 3 zero bytes of padding may follow.
std::vector<uint8_t> spacetime_checkpoint_serialize(const SpacetimeCheckpoint& c, uint32_t tag = 0);
SpacetimeCheckpoint spacetime_checkpoint_deserialize(const std::vector<uint8_t>& bytes, uint32_t* tag = nullptr);

}  // namespace pliant::soft
