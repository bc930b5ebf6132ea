// Between window pixels and the world under a camera's world-to-clip matrix: a
// world point's position in a viewport rectangle, and the mouse ray through a
// pixel (the gizmos, picking and drags of every kind share these).
#pragma once

#include "render/mat4.h"

namespace pliant::editor {

struct ScreenPoint {
  float x = 0, y = 0, depth = 0;  // window pixels; depth = NDC z
  bool ok = false;                // false behind the camera
};

// Window position of world point p in the viewport rectangle (x0, y0, w, h).
ScreenPoint project_to_screen(const Mat4& world_to_clip, const Vec3& p, float x0, float y0, float w, float h);

// The world points on the near (clip z = -1) and far (z = +1) planes under window
// point (sx, sy); false for an empty rectangle or a point at infinity.
bool screen_ray(const Mat4& world_to_clip, float sx, float sy, float x0, float y0, float w, float h, Vec3* near_pt,
                Vec3* far_pt);

// Where the ray through (sx, sy) meets the horizontal plane y = plane_y, beyond
// the near plane (false if parallel or behind).
bool screen_ray_plane_y(const Mat4& world_to_clip, float sx, float sy, float x0, float y0, float w, float h,
                        float plane_y, Vec3* hit);

}  // namespace pliant::editor
