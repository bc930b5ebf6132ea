#pragma once
namespace pliant {
inline constexpr const char* kEngineVersion = "0.1.0";
}
