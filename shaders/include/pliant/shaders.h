// GLSL sources embedded at build time (shaders/embed_shaders.cmake).
#pragma once
#include <string_view>

namespace pliant::shaders {
// Source of the shader file `name` (e.g. "smoke2d.frag"); empty if unknown.
std::string_view get(std::string_view name);
}  // namespace pliant::shaders
