// Soft scene helpers; defaults mirror engine/soft/src/soft_compile.cpp.
#include "doc/soft_scene.h"

#include <algorithm>
#include <cmath>

namespace pliant::editor {

using nlohmann::json;

namespace {

const json* child(const json& j, const char* key) {
  if (!j.is_object()) return nullptr;
  auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}
const json* object(const json& j, const char* key) {
  const json* c = child(j, key);
  return c && c->is_object() ? c : nullptr;
}
double number(const json* j, const char* key, double def) {
  const json* c = j ? child(*j, key) : nullptr;
  return c && c->is_number() && std::isfinite(c->get<double>()) ? c->get<double>() : def;
}
SoftVec3 vec3(const json* j, const char* key, const SoftVec3& def) {
  const json* c = j ? child(*j, key) : nullptr;
  if (!c || !c->is_array() || c->size() != 3) return def;
  SoftVec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!(*c)[i].is_number()) return def;
    v[i] = (*c)[i].get<double>();
  }
  return v;
}
SoftVec3 unit(const SoftVec3& v, const SoftVec3& def) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(n > 1e-12)) return def;
  return {v[0] / n, v[1] / n, v[2] / n};
}
bool same(const SoftVec3& a, const SoftVec3& b) {
  for (int i = 0; i < 3; ++i)
    if (std::abs(a[i] - b[i]) > 1e-9) return false;
  return true;
}

}  // namespace

bool is_soft_scene(const json& scene) {
  return scene.is_object() && scene.value("kind", std::string()) == "soft";
}

SoftSceneInfo soft_scene_info(const json& scene) {
  SoftSceneInfo in;
  if (const json* e = object(scene, "environment")) {
    const json* t = child(*e, "type");
    in.water = t && t->is_string() && t->get<std::string>() == "water";
    const json* g = child(*e, "ground");
    in.ground = g && g->is_boolean() ? g->get<bool>() : !in.water;
    in.ground_y = number(e, "ground_height_m", 0);
    if (const json* obs = child(*e, "obstacles"); obs && obs->is_array())
      for (const json& o : *obs) {
        const json* t2 = child(o, "type");
        const std::string type = t2 && t2->is_string() ? t2->get<std::string>() : "sphere";
        const double r = number(&o, "radius_m", 0);
        if (type == "sphere" && r > 0) in.spheres.push_back({vec3(&o, "center_m", {0, 0, 0}), r});
      }
  }
  if (const json* s = object(scene, "simulation")) {
    in.dt_s = number(s, "dt_s", in.dt_s);
    in.frames = std::max(1, int(number(s, "frames", in.frames)));
    in.start_offset = vec3(s, "start_offset_m", in.start_offset);
  }
  in.horizon = std::min(in.frames, 60);
  if (const json* o = object(scene, "optimizer")) in.horizon = std::max(1, int(number(o, "horizon_frames", in.horizon)));
  if (const json* o = object(scene, "objectives")) {
    if (const json* t = object(*o, "position")) {
      in.has_position = true;
      in.position_target = vec3(t, "target_m", {0, 0, 0});
    }
    if (const json* t = object(*o, "velocity")) {
      in.has_velocity = true;
      in.velocity_target = vec3(t, "target_m_per_s", {0, 0, 0});
    }
    if (const json* t = object(*o, "heading")) {
      in.has_heading = true;
      in.heading_axis = unit(vec3(t, "body_axis", {1, 0, 0}), {1, 0, 0});
      in.heading_direction = unit(vec3(t, "direction", {1, 0, 0}), {1, 0, 0});
    }
    if (const json* t = object(*o, "jump")) {
      in.has_jump = true;
      in.jump_height = number(t, "height_m", 0);
    }
    if (const json* t = object(*o, "distance")) {
      in.has_distance = true;
      in.distance = number(t, "distance_m", 0);
      in.distance_direction = unit(vec3(t, "direction", {1, 0, 0}), {1, 0, 0});
    }
  }
  return in;
}

SoftVec3 soft_goal(const SoftSceneInfo& in, const SoftVec3& start) {
  if (in.has_position) return in.position_target;
  SoftVec3 g = start;
  if (in.has_velocity) {
    const double t = in.frames * in.dt_s;
    for (int i = 0; i < 3; ++i) g[i] += in.velocity_target[i] * t;
  } else if (in.has_distance) {
    for (int i = 0; i < 3; ++i) g[i] += in.distance * in.distance_direction[i];
  }
  return g;
}

std::vector<SoftPin> soft_pins(const json& scene) {
  std::vector<SoftPin> out;
  const json* o = object(scene, "objectives");
  const json* k = o ? object(*o, "keyframes") : nullptr;
  const json* fr = k ? child(*k, "frames") : nullptr;
  if (!fr || !fr->is_array()) return out;
  for (size_t e = 0; e < fr->size(); ++e) {
    const json& entry = (*fr)[e];
    const json* f = child(entry, "frame");
    const json* vs = child(entry, "vertices");
    if (!f || !f->is_number_integer() || !vs || !vs->is_array()) continue;
    const SoftVec3 off = vec3(&entry, "offset_m", {0, 0, 0});
    for (const json& v : *vs)
      if (v.is_number_integer()) out.push_back({int(e), f->get<int>(), v.get<int>(), off});
  }
  return out;
}

std::vector<SoftPin> soft_pins_at(const json& scene, int frame) {
  std::vector<SoftPin> out;
  for (const SoftPin& p : soft_pins(scene))
    if (p.frame == frame) out.push_back(p);
  return out;
}

json soft_without_pin(const json& scene, int frame, int vertex) {
  json s = scene;
  for (const SoftPin& p : soft_pins(scene)) {
    if (p.frame != frame || p.vertex != vertex) continue;
    json& vs = s["objectives"]["keyframes"]["frames"][size_t(p.entry)]["vertices"];
    json kept = json::array();
    for (const json& v : vs)
      if (!(v.is_number_integer() && v.get<int>() == vertex)) kept.push_back(v);
    vs = kept;
  }
  // Entries left without vertices go (the engine would reject an empty list).
  if (!soft_pins(scene).empty()) {
    json& fr = s["objectives"]["keyframes"]["frames"];
    json kept = json::array();
    for (const json& e : fr)
      if (!(e.is_object() && e.contains("vertices") && e["vertices"].is_array() && e["vertices"].empty()))
        kept.push_back(e);
    fr = kept;
  }
  return s;
}

json soft_with_pin(const json& scene, int frame, int vertex, const SoftVec3& offset) {
  json s = soft_without_pin(scene, frame, vertex);
  if (!s.contains("objectives") || !s["objectives"].is_object()) s["objectives"] = json::object();
  json& o = s["objectives"];
  if (!o.contains("keyframes") || !o["keyframes"].is_object()) o["keyframes"] = {{"weight", 10}};
  json& k = o["keyframes"];
  if (!k.contains("frames") || !k["frames"].is_array()) k["frames"] = json::array();
  for (json& e : k["frames"]) {
    if (!e.is_object() || !e.contains("frame") || !e["frame"].is_number_integer() || e["frame"].get<int>() != frame)
      continue;
    if (!same(vec3(&e, "offset_m", {0, 0, 0}), offset) || !e.contains("vertices") || !e["vertices"].is_array())
      continue;
    e["vertices"].push_back(vertex);
    return s;
  }
  k["frames"].push_back({{"frame", frame}, {"vertices", {vertex}}, {"offset_m", {offset[0], offset[1], offset[2]}}});
  return s;
}

}  // namespace pliant::editor
