// Soft character takes (issue 5): what the soft drawer knows about a take
// beyond the frame it is given. Soft takes store "triangles" in frame 0 only
// and the COM trail needs every frame, so the soft panels (which hold the take
// reader) hand the drawer frame 0 and the trail once per take; the drawer also
// keeps the triangles of any frame it uploads that has them. UI thread only.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/mat4.h"

namespace pliant::editor {

struct SoftTakeData {
  std::vector<uint32_t> triangles;          // frame 0's triangles, 3 per triangle
  std::vector<float> rest_vertices;         // frame 0's vertices (xyz), for pin targets
  std::vector<std::array<float, 3>> com;    // "com" per frame index (trail)
};

// Key of a take's scene copy (the manifest's scene): the drawer looks its data up
// by the scene it is given.
uint64_t soft_scene_key(const nlohmann::json& take_scene);
void soft_drawer_set_take_data(uint64_t scene_key, SoftTakeData data);
// Null when nothing was registered under the key.
const SoftTakeData* soft_drawer_take_data(uint64_t scene_key);

// The world -> clip matrix and viewport size of the last draw by the first soft
// drawer alive (the main viewport's renderer; A/B and others come later), for
// gizmos drawn over the result. False before it has drawn.
bool soft_drawer_primary_view(Mat4* world_to_clip, int* w, int* h);

}  // namespace pliant::editor
