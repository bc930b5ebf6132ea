#include "doc/liquid_scene_edit.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

namespace pliant::editor {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kMinKeyGap_s = 1e-3;

json pose_of(const json& src, int dim) {
  json p = src.value("position_m", json::array());
  if (!p.is_array()) p = json::array();
  while (int(p.size()) < dim) p.push_back(0.0);
  return json{{"position_m", p}, {"tilt_deg", src.value("tilt_deg", 0.0)}};
}

double mix(const json& a, const json& b, double t) {
  const double x = a.get<double>(), y = b.get<double>();
  return x + t * (y - x);
}

}  // namespace

int liquid_dim(const json& scene) { return scene.value("dim", 2) == 3 ? 3 : 2; }

double liquid_duration_s(const json& scene) {
  const json t = scene.value("time", json::object());
  return t.value("frames", 100) * t.value("dt_s", 0.02);
}

std::vector<double> liquid_key_times(const json& scene) {
  std::vector<double> out;
  const json* keys = scene.contains("source") ? &scene["source"] : nullptr;
  if (!keys || !keys->contains("trajectory") || !(*keys)["trajectory"].is_array()) return out;
  for (const json& k : (*keys)["trajectory"]) out.push_back(k.value("time_s", 0.0));
  return out;
}

json liquid_add_key(const json& scene, double time_s, int* index) {
  *index = -1;
  if (!scene.contains("source") || !scene["source"].is_object()) return scene;
  const int dim = liquid_dim(scene);
  json out = scene;
  json& src = out["source"];
  if (!src.contains("trajectory") || !src["trajectory"].is_array()) src["trajectory"] = json::array();
  json& keys = src["trajectory"];
  const std::vector<double> times = liquid_key_times(out);
  for (double t : times)
    if (std::abs(t - time_s) < kMinKeyGap_s) return scene;
  const int at = int(std::lower_bound(times.begin(), times.end(), time_s) - times.begin());
  json key;
  if (keys.empty()) {
    key = pose_of(src, dim);
  } else if (at == 0) {
    key = pose_of(keys[0], dim);
  } else if (at == int(keys.size())) {
    key = pose_of(keys[at - 1], dim);
  } else {
    const json a = pose_of(keys[at - 1], dim), b = pose_of(keys[at], dim);
    const double t = (time_s - times[at - 1]) / (times[at] - times[at - 1]);
    key = a;
    for (int i = 0; i < dim; ++i) key["position_m"][i] = mix(a["position_m"][i], b["position_m"][i], t);
    key["tilt_deg"] = mix(a["tilt_deg"], b["tilt_deg"], t);
  }
  key["time_s"] = time_s;
  keys.insert(keys.begin() + at, key);
  *index = at;
  return out;
}

json liquid_delete_key(const json& scene, int index) {
  const std::vector<double> times = liquid_key_times(scene);
  if (index < 0 || index >= int(times.size())) return scene;
  json out = scene;
  json& keys = out["source"]["trajectory"];
  keys.erase(keys.begin() + index);
  if (keys.empty()) out["source"].erase("trajectory");
  return out;
}

json liquid_move_key(const json& scene, int index, double time_s) {
  const std::vector<double> times = liquid_key_times(scene);
  if (index < 0 || index >= int(times.size())) return scene;
  double lo = index > 0 ? times[index - 1] + kMinKeyGap_s : 0.0;
  double hi = index + 1 < int(times.size()) ? times[index + 1] - kMinKeyGap_s : 1e6;
  json out = scene;
  out["source"]["trajectory"][index]["time_s"] = std::clamp(time_s, lo, std::max(lo, hi));
  return out;
}

json liquid_move_key_position(const json& scene, int index, double dx, double dy) {
  const std::vector<double> times = liquid_key_times(scene);
  if (index < 0 || index >= int(times.size())) return scene;
  json out = scene;
  json& k = out["source"]["trajectory"][index];
  json p = pose_of(k, liquid_dim(scene))["position_m"];
  p[0] = p[0].get<double>() + dx;
  p[1] = p[1].get<double>() + dy;
  k["position_m"] = p;
  return out;
}

json liquid_set_key_tilt(const json& scene, int index, double tilt_deg) {
  const std::vector<double> times = liquid_key_times(scene);
  if (index < 0 || index >= int(times.size())) return scene;
  json out = scene;
  out["source"]["trajectory"][index]["tilt_deg"] = tilt_deg;
  return out;
}

json liquid_adopt_trajectory(const json& scene, const json& keys) {
  if (!keys.is_array() || keys.empty() || !scene.contains("source") || !scene["source"].is_object()) return scene;
  const int dim = liquid_dim(scene);
  json out = scene;
  json traj = json::array();
  for (const json& k : keys) {
    if (!k.is_object()) return scene;
    json key = pose_of(k, dim);
    // The planner reports 3 coordinates in 2D too; the scene takes dim of them.
    while (int(key["position_m"].size()) > dim) key["position_m"].erase(key["position_m"].size() - 1);
    key["time_s"] = k.value("time_s", 0.0);
    traj.push_back(key);
  }
  out["source"]["trajectory"] = traj;
  out["planner"]["mode"] = "none";
  return out;
}

json liquid_move_container(const json& scene, ContainerRole role, double dx, double dy) {
  if (!scene.contains(role) || !scene[role].is_object()) return scene;
  const int dim = liquid_dim(scene);
  json out = scene;
  json& c = out[role];
  auto shift = [&](json& obj) {
    json p = pose_of(obj, dim)["position_m"];
    p[0] = p[0].get<double>() + dx;
    p[1] = p[1].get<double>() + dy;
    obj["position_m"] = p;
  };
  shift(c);
  if (c.contains("trajectory") && c["trajectory"].is_array())
    for (json& k : c["trajectory"]) shift(k);
  return out;
}

bool liquid_container_is_inline(const json& scene, ContainerRole role) {
  return scene.contains(role) && scene[role].is_object() && scene[role].contains("container") &&
         scene[role]["container"].is_object();
}

json liquid_resize_container(const json& scene, ContainerRole role, double radius_m, double height_m) {
  if (!liquid_container_is_inline(scene, role)) return scene;
  json out = scene;
  json& c = out[role]["container"];
  c["radius_m"] = radius_m;
  c["height_m"] = height_m;
  return out;
}

bool liquid_inline_container(json* scene, ContainerRole role, const fs::path& scene_dir, std::string* err) {
  if (!scene->contains(role) || !(*scene)[role].is_object()) {
    *err = std::string("no /") + role;
    return false;
  }
  json& c = (*scene)[role];
  if (liquid_container_is_inline(*scene, role)) return true;
  if (!c.contains("container") || !c["container"].is_string()) {
    *err = std::string("/") + role + "/container is neither an object nor a path";
    return false;
  }
  fs::path p = c["container"].get<std::string>();
  if (p.is_relative()) p = scene_dir / p;
  std::ifstream in(p);
  const json obj0 = in ? json::parse(in, nullptr, /*allow_exceptions=*/false, /*ignore_comments=*/true)
                       : json(json::value_t::discarded);
  json obj = obj0;
  if (obj.is_discarded() || !obj.is_object()) {
    *err = "cannot read container file " + p.string();
    return false;
  }
  obj.erase("comment");
  c["container"] = obj;
  return true;
}

json liquid_set_mesh_container(const json& scene, ContainerRole role, const std::string& file) {
  json out = scene;
  if (!out.contains(role) || !out[role].is_object()) {
    json zero = json::array();
    for (int i = 0; i < liquid_dim(scene); ++i) zero.push_back(0.0);
    out[role] = {{"position_m", zero}};
  }
  out[role]["container"] = {{"shape", "mesh"}, {"file", file}};
  return out;
}

bool liquid_is_mesh_file(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".obj" || ext == ".stl" || ext == ".ply";
}

std::vector<fs::path> liquid_container_library(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".json") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace pliant::editor
