#include "doc/smoke_keyframes_3d.h"

#include <algorithm>
#include <cmath>

#include "doc/smoke_keyframes.h"
#include "pliant/geom/raster_grid.h"

namespace pliant::editor {

using nlohmann::json;

std::array<int, 3> smoke_resolution_3d(const json& s) {
  if (!is_smoke_scene(s) || !s.contains("grid") || !s["grid"].is_object()) return {0, 0, 0};
  const json& r = s["grid"].value("resolution", json());
  if (!r.is_array() || r.size() != 3) return {0, 0, 0};
  for (const auto& v : r)
    if (!v.is_number_integer() || v.get<int>() < 1) return {0, 0, 0};
  return {r[0].get<int>(), r[1].get<int>(), r[2].get<int>()};
}

geom::PaintedGrid make_painted_volume(int w, int h, int d) {
  geom::PaintedGrid g;
  g.dim = 3;
  g.n = {w, h, d};
  g.value.assign(g.cells(), 0);
  return g;
}

geom::PaintedGrid volume_slice(const geom::PaintedGrid& v, int z) { return volume_slice(v, SliceAxis::XY, z); }

void set_volume_slice(geom::PaintedGrid& v, int z, const geom::PaintedGrid& slice) {
  set_volume_slice(v, SliceAxis::XY, z, slice);
}

geom::PaintedGrid rasterize_slot_volume(const json& scene, const std::filesystem::path& scene_dir, int slot,
                                        std::string* error) {
  const auto n = smoke_resolution_3d(scene);
  if (n[0] <= 0 || !has_control(scene)) {
    if (error) *error = "not a 3D smoke scene with a control section";
    return {};
  }
  const json target = slot_target(scene, slot);
  // Painted at the grid's size: the stored bytes, exactly (no float round trip).
  if (target.is_object() && target.value("type", std::string()) == "painted") {
    try {
      const json& sz = target.at("size");
      if (sz.size() == 3 && sz[0].get<int>() == n[0] && sz[1].get<int>() == n[1] && sz[2].get<int>() == n[2]) {
        geom::PaintedGrid g = geom::decode_painted(target.at("data").get<std::string>(), 3, n);
        if (error) error->clear();
        return g;
      }
    } catch (const std::exception& e) {
      if (error) *error = e.what();
      return {};
    }
  }
  std::array<int, 3> dims{};
  std::vector<float> d = rasterize_slot_density(scene, scene_dir, slot, &dims, error);
  if (d.empty() || dims != n) return {};
  geom::PaintedGrid g = make_painted_volume(n[0], n[1], n[2]);
  for (size_t c = 0; c < g.cells(); ++c) g.value[c] = uint8_t(std::lround(std::clamp(d[c], 0.0f, 1.0f) * 255.0f));
  return g;
}

json with_painted_volume_slot(const json& scene, int slot, const geom::PaintedGrid& v) {
  return with_slot_target(scene, slot,
                          {{"type", "painted"}, {"size", {v.n[0], v.n[1], v.n[2]}}, {"data", geom::encode_painted(v)}});
}

bool is_mesh_slot(const json& scene, int slot) {
  const json t = slot_target(scene, slot);
  return t.is_object() && t.value("type", std::string()) == "mesh";
}

MeshTransform mesh_transform(const json& scene, int slot) {
  MeshTransform t;
  const json target = slot_target(scene, slot);
  if (!target.is_object()) return t;
  const json& c = target.value("center", json());
  const json& cm = target.value("center_m", json());
  if (c.is_array() && c.size() == 3) {
    for (int a = 0; a < 3; ++a) t.center[a] = c[a].is_number() ? c[a].get<double>() : 0.5;
  } else if (cm.is_array() && cm.size() == 3 && scene.contains("grid")) {
    const auto n = smoke_resolution_3d(scene);
    const double h = scene["grid"].value("cell_size_m", 0.0);
    for (int a = 0; a < 3; ++a)
      if (n[a] > 0 && h > 0 && cm[a].is_number()) t.center[a] = cm[a].get<double>() / (n[a] * h);
  }
  if (target.value("scale", json()).is_number()) t.scale = target["scale"].get<double>();
  if (target.value("rotation_deg", json()).is_number()) t.rotation_deg = target["rotation_deg"].get<double>();
  const json& ax = target.value("rotation_axis", json());
  if (ax.is_array() && ax.size() == 3 && ax[0].is_number() && ax[1].is_number() && ax[2].is_number()) {
    const std::array<double, 3> v{ax[0].get<double>(), ax[1].get<double>(), ax[2].get<double>()};
    if (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0) t.rotation_axis = v;
  }
  return t;
}

json with_mesh_transform(const json& scene, int slot, const MeshTransform& t) {
  json target = slot_target(scene, slot);
  if (!target.is_object()) return scene;
  target.erase("center_m");
  target["center"] = {t.center[0], t.center[1], t.center[2]};
  target["scale"] = t.scale;
  target["rotation_deg"] = t.rotation_deg;
  const auto& v = t.rotation_axis;
  if (target.contains("rotation_axis") || v[0] != 0 || v[1] != 0 || !(v[2] > 0))
    target["rotation_axis"] = {v[0], v[1], v[2]};
  return with_slot_target(scene, slot, target);
}

std::array<double, 2> mesh_centre_in_slice(const MeshTransform& t, const std::array<int, 3>& n, SliceAxis a) {
  // Continuous form of doc/volume_slice.h: a flipped index nz-1-z is nz - z here.
  const double x = t.center[0] * n[0], y = t.center[1] * n[1], z = t.center[2] * n[2];
  switch (a) {
    case SliceAxis::XZ: return {x, n[2] - z};
    case SliceAxis::YZ: return {n[2] - z, y};
    default: return {x, y};
  }
}

MeshTransform gizmo_move(const MeshTransform& t, double dx, double dy, const std::array<int, 3>& n, SliceAxis a) {
  double d[3] = {dx, dy, 0};  // XY: u = x, v = y
  if (a == SliceAxis::XZ) d[0] = dx, d[1] = 0, d[2] = -dy;
  if (a == SliceAxis::YZ) d[0] = 0, d[1] = dy, d[2] = -dx;
  MeshTransform out = t;
  for (int i = 0; i < 3; ++i) out.center[i] += d[i] / std::max(1, n[i]);
  return out;
}

MeshTransform gizmo_scale(const MeshTransform& t, double x0, double y0, double x1, double y1,
                          const std::array<int, 3>& n, SliceAxis a) {
  const auto c = mesh_centre_in_slice(t, n, a);
  const double r0 = std::hypot(x0 - c[0], y0 - c[1]), r1 = std::hypot(x1 - c[0], y1 - c[1]);
  MeshTransform out = t;
  if (r0 > 1e-6) out.scale = std::clamp(t.scale * r1 / r0, 0.02, 50.0);
  return out;
}

MeshTransform gizmo_rotate(const MeshTransform& t, double x0, double y0, double x1, double y1,
                           const std::array<int, 3>& n, SliceAxis a) {
  const auto c = mesh_centre_in_slice(t, n, a);
  const double a0 = std::atan2(y0 - c[1], x0 - c[0]), a1 = std::atan2(y1 - c[1], x1 - c[0]);
  // u x v of each view points at the viewer (doc/volume_slice.h): XY +z, XZ +y, YZ +x.
  const std::array<double, 3> normal = a == SliceAxis::XZ ? std::array<double, 3>{0, 1, 0}
                                       : a == SliceAxis::YZ ? std::array<double, 3>{1, 0, 0}
                                                            : std::array<double, 3>{0, 0, 1};
  geom::Placement p;
  p.rotation_deg = t.rotation_deg;
  p.rotation_axis = t.rotation_axis;
  geom::rotate_placement(p, normal, (a1 - a0) * 180.0 / 3.14159265358979323846);
  MeshTransform out = t;
  out.rotation_deg = p.rotation_deg;
  out.rotation_axis = p.rotation_axis;
  return out;
}

double gizmo_footprint_deg(const MeshTransform& t, SliceAxis a) {
  const auto& k = t.rotation_axis;
  if (a == SliceAxis::XY && k[0] == 0 && k[1] == 0 && k[2] > 0) return t.rotation_deg;
  geom::Placement p;
  p.rotation_deg = t.rotation_deg;
  p.rotation_axis = k;
  const geom::Rotation3 R = geom::placement_rotation(p);
  // World directions of screen right (u) and up (v) per view.
  std::array<double, 3> u{1, 0, 0}, v{0, 1, 0};
  if (a == SliceAxis::XZ) v = {0, 0, -1};
  if (a == SliceAxis::YZ) u = {0, 0, -1};
  std::array<double, 3> ru{};
  for (int i = 0; i < 3; ++i) ru[i] = R[i][0] * u[0] + R[i][1] * u[1] + R[i][2] * u[2];
  const double su = ru[0] * u[0] + ru[1] * u[1] + ru[2] * u[2], sv = ru[0] * v[0] + ru[1] * v[1] + ru[2] * v[2];
  if (std::hypot(su, sv) < 1e-9) return 0.0;
  return std::atan2(sv, su) * 180.0 / 3.14159265358979323846;
}

std::array<double, 3> volume_centroid(const geom::PaintedGrid& v) {
  double m = 0, s[3] = {0, 0, 0};
  for (int k = 0; k < v.n[2]; ++k)
    for (int j = 0; j < v.n[1]; ++j)
      for (int i = 0; i < v.n[0]; ++i) {
        const double w = v.value[size_t(i) + size_t(v.n[0]) * (size_t(j) + size_t(v.n[1]) * k)];
        m += w;
        s[0] += w * (i + 0.5), s[1] += w * (j + 0.5), s[2] += w * (k + 0.5);
      }
  if (m <= 0) return {0, 0, 0};
  return {s[0] / m, s[1] / m, s[2] / m};
}

}  // namespace pliant::editor
