#include "doc/smoke_keyframes.h"

#include <algorithm>

#include "doc/paint_ops.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/control.h"

namespace pliant::editor {

using nlohmann::json;

bool is_smoke_scene(const json& s) {
  return s.is_object() && s.value("kind", std::string()) == "smoke";
}

bool is_smoke_2d(const json& s) {
  if (!is_smoke_scene(s) || !s.contains("grid") || !s["grid"].is_object()) return false;
  const json& r = s["grid"].value("resolution", json());
  return r.is_array() && r.size() == 2 && r[0].is_number_integer() && r[1].is_number_integer();
}

bool has_control(const json& s) { return is_smoke_scene(s) && s.contains("control") && s["control"].is_object(); }

std::array<int, 2> smoke_resolution(const json& s) {
  if (!is_smoke_2d(s)) return {0, 0};
  const json& r = s["grid"]["resolution"];
  return {r[0].get<int>(), r[1].get<int>()};
}

int smoke_frames(const json& s) {
  if (!s.is_object() || !s.contains("time") || !s["time"].is_object()) return 0;
  const json& f = s["time"].value("frames", json());
  return f.is_number_integer() ? f.get<int>() : 0;
}

std::vector<KeyframeInfo> list_keyframes(const json& s) {
  std::vector<KeyframeInfo> out;
  if (!has_control(s)) return out;
  const json& ks = s["control"].value("keyframes", json::array());
  if (!ks.is_array()) return out;
  for (size_t i = 0; i < ks.size(); ++i) {
    if (!ks[i].is_object()) continue;
    KeyframeInfo k;
    k.index = int(i);
    k.frame = ks[i].value("frame", 0);
    if (ks[i].contains("target") && ks[i]["target"].is_object())
      k.type = ks[i]["target"].value("type", std::string());
    out.push_back(k);
  }
  return out;
}

int keyframe_at_frame(const json& s, int frame) {
  for (const auto& k : list_keyframes(s))
    if (k.frame == frame) return k.index;
  return -2;
}

json default_control_section() {
  return {{"method", "admm"},
          {"r", 1e-5},
          {"max_iterations", 40},
          {"tolerance", 1e-4},
          {"progressive_preview", true},
          {"initial_density", json::array({{{"type", "circle"}, {"center", {0.5, 0.3}}, {"radius", 0.15}}})},
          {"keyframes", json::array()}};
}

namespace {

json& control_of(json& s) {
  if (!s.contains("control") || !s["control"].is_object()) s["control"] = default_control_section();
  if (!s["control"].contains("keyframes") || !s["control"]["keyframes"].is_array())
    s["control"]["keyframes"] = json::array();
  return s["control"];
}

int clamp_frame(const json& s, int frame) { return std::clamp(frame, 1, std::max(1, smoke_frames(s))); }

// Stable sort by frame; returns where `tracked` went.
int sort_keyframes(json& ks, int tracked) {
  std::vector<std::pair<int, int>> order;  // (frame, old index)
  for (size_t i = 0; i < ks.size(); ++i) order.push_back({ks[i].value("frame", 0), int(i)});
  std::stable_sort(order.begin(), order.end(), [](auto a, auto b) { return a.first < b.first; });
  json sorted = json::array();
  int where = -1;
  for (size_t i = 0; i < order.size(); ++i) {
    if (order[i].second == tracked) where = int(i);
    sorted.push_back(ks[order[i].second]);
  }
  ks = std::move(sorted);
  return where;
}

}  // namespace

json with_keyframe_added(const json& scene, int frame, int* index) {
  json s = scene;
  frame = clamp_frame(s, frame);
  int existing = keyframe_at_frame(s, frame);
  if (existing >= 0) {
    if (index) *index = existing;
    return scene;
  }
  json& ks = control_of(s)["keyframes"];
  const auto res = smoke_resolution(s);
  if (res[0] > 0) {
    geom::PaintedGrid g = make_painted_grid(res[0], res[1]);
    ks.push_back({{"frame", frame},
                  {"target", {{"type", "painted"}, {"size", {g.n[0], g.n[1]}}, {"data", geom::encode_painted(g)}}}});
  } else {
    // 3D: no painting; a sphere to replace by a mesh or edit in the scene.
    ks.push_back({{"frame", frame},
                  {"target", {{"type", "sphere"}, {"center", {0.5, 0.5, 0.5}}, {"radius", 0.2}}}});
  }
  int where = sort_keyframes(ks, int(ks.size()) - 1);
  if (index) *index = where;
  return s;
}

json with_keyframe_removed(const json& scene, int index) {
  if (!has_control(scene)) return scene;
  json s = scene;
  json& ks = s["control"]["keyframes"];
  if (!ks.is_array() || index < 0 || index >= int(ks.size())) return scene;
  ks.erase(ks.begin() + index);
  return s;
}

json with_keyframe_moved(const json& scene, int index, int frame, int* new_index) {
  if (new_index) *new_index = index;
  if (!has_control(scene)) return scene;
  json s = scene;
  json& ks = s["control"]["keyframes"];
  if (!ks.is_array() || index < 0 || index >= int(ks.size())) return scene;
  frame = clamp_frame(s, frame);
  int other = keyframe_at_frame(s, frame);
  if (other >= 0 && other != index) return scene;
  ks[index]["frame"] = frame;
  int where = sort_keyframes(ks, index);
  if (new_index) *new_index = where;
  return s;
}

json with_slot_target(const json& scene, int slot, const json& target) {
  json s = scene;
  json& c = control_of(s);
  if (slot == kInitialDensitySlot) {
    c["initial_density"] = json::array({target});
  } else if (slot >= 0 && slot < int(c["keyframes"].size())) {
    c["keyframes"][slot]["target"] = target;
  }
  return s;
}

json with_painted_slot(const json& scene, int slot, const geom::PaintedGrid& g) {
  return with_slot_target(scene, slot,
                          {{"type", "painted"}, {"size", {g.n[0], g.n[1]}}, {"data", geom::encode_painted(g)}});
}

json slot_target(const json& s, int slot) {
  if (!has_control(s)) return nullptr;
  const json& c = s["control"];
  if (slot == kInitialDensitySlot) {
    const json& init = c.value("initial_density", json::array());
    if (init.is_array() && init.size() == 1) return init[0];
    return init.is_array() && !init.empty() ? json{{"type", "union"}} : json();
  }
  const json& ks = c.value("keyframes", json::array());
  if (!ks.is_array() || slot < 0 || slot >= int(ks.size()) || !ks[slot].is_object()) return nullptr;
  return ks[slot].value("target", json());
}

geom::PaintedGrid rasterize_slot(const json& scene, const std::filesystem::path& scene_dir, int slot,
                                 std::string* error) {
  const auto res = smoke_resolution(scene);
  if (res[0] <= 0 || res[1] <= 0 || !has_control(scene)) {
    if (error) *error = "not a 2D smoke scene with a control section";
    return {};
  }
  const json target = slot_target(scene, slot);
  // Painted at the grid's size: the stored bytes, exactly (no float round trip).
  if (target.is_object() && target.value("type", std::string()) == "painted") {
    try {
      const json& sz = target.at("size");
      if (sz.size() == 2 && sz[0].get<int>() == res[0] && sz[1].get<int>() == res[1])
        return geom::decode_painted(target.at("data").get<std::string>(), 2, {res[0], res[1], 1});
    } catch (const std::exception& e) {
      if (error) *error = e.what();
      return make_painted_grid(res[0], res[1]);
    }
  }
  std::array<int, 3> dims{};
  std::vector<float> d = rasterize_slot_density(scene, scene_dir, slot, &dims, error);
  if (d.empty()) return make_painted_grid(res[0], res[1]);
  return painted_from_density(d, res[0], res[1]);
}

std::vector<float> rasterize_slot_density(const json& scene, const std::filesystem::path& scene_dir, int slot,
                                          std::array<int, 3>* dims, std::string* error) {
  // Compile a copy whose only keyframe (frame 1) and initial density are this
  // slot's, so other broken keyframes do not matter.
  try {
    if (!has_control(scene)) throw std::runtime_error("the scene has no control section");
    json s = scene;
    json& c = s["control"];
    json init = c.value("initial_density", json::array());
    const json target = slot_target(scene, slot);
    json kt = slot == kInitialDensitySlot ? (init.is_array() && !init.empty() ? init[0] : json()) : target;
    if (kt.is_null()) throw std::runtime_error("the slot has no target");
    c["keyframes"] = json::array({{{"frame", 1}, {"target", kt}}});
    c.erase("sequence");
    if (slot != kInitialDensitySlot || init.size() <= 1) c["initial_density"] = json::array({kt});
    Scene sc = parse_scene(s.dump(), "scene", scene_dir.empty() ? std::filesystem::path(".") : scene_dir);
    smoke::ControlModel m = smoke::control_compile(sc);
    if (error) error->clear();
    if (dims) *dims = {m.sim.n[0], m.sim.n[1], m.sim.dim == 3 ? m.sim.n[2] : 1};
    return slot == kInitialDensitySlot ? m.initial_density : m.keyframes.at(0).density;
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return {};
  }
}

}  // namespace pliant::editor
