// <compiler coordinate="global"> (MuJoCo 2.2.2; gym's hopper and walker use it):
// every body, geom, joint and inertial gives its frame in world coordinates. Before
// the tree is read, each one is rewritten in its parent body's frame: for a body at
// (P, Q) in the world, a point p becomes Q^-1 (p - P), a rotation q becomes Q^-1 q and
// an axis a becomes Q^-1 a, so everything after this pass reads local coordinates.
// Attributes left out mean the world's origin, identity and z axis, as given.
#include <cstdio>
#include <string>

#include "mjcf_internal.h"

namespace pliant::articulated::mjcf_internal {
namespace {

void set_attr(XmlElement& e, const std::string& key, const std::string& value) {
  for (auto& kv : e.attrs)
    if (kv.first == key) {
      kv.second = value;
      return;
    }
  e.attrs.emplace_back(key, value);
}

void erase_attr(XmlElement& e, const std::string& key) {
  for (size_t k = 0; k < e.attrs.size(); ++k)
    if (e.attrs[k].first == key) {
      e.attrs.erase(e.attrs.begin() + static_cast<std::ptrdiff_t>(k));
      return;
    }
}

std::string format_numbers(const double* v, int n) {
  std::string out;
  char buf[32];
  for (int i = 0; i < n; ++i) {
    std::snprintf(buf, sizeof(buf), "%.17g", v[i]);
    out += (i ? " " : "") + std::string(buf);
  }
  return out;
}

void set_vec(XmlElement& e, const std::string& key, const Vec3& v) { set_attr(e, key, format_numbers(v.data(), 3)); }

// The element's orientation, as a local quat attribute (the other forms removed).
void set_quat(XmlElement& e, const Quat& q) {
  for (const char* k : {"axisangle", "euler", "xyaxes", "zaxis"}) erase_attr(e, k);
  const double w[4] = {q.w(), q.x(), q.y(), q.z()};
  set_attr(e, "quat", format_numbers(w, 4));
}

// A geom, joint or inertial of the body whose world frame is (P, Q).
void localise_child(const Ctx& c, XmlElement& e, const std::string& path, const Vec3& P, const Quat& Q) {
  const Quat Qi = Q.conjugate();
  if (e.name == "geom" && e.attr("fromto")) {
    // MuJoCo 2.2.2 builds a fromto frame in world axes (z from the second point to the
    // first, the shortest turn from +z) and then makes it local, which differs from the
    // frame of the local points by a turn about the geom's axis (a square box shows
    // it): so the geom becomes pos + quat + full size here.
    const auto f = numbers(c, e, path, "fromto", 6, 6);
    const Vec3 a(f[0], f[1], f[2]), b(f[3], f[4], f[5]);
    const double half = 0.5 * (b - a).norm();
    const std::string type = e.attr("type") ? *e.attr("type") : "sphere";
    if (half > 0 && e.attr("size") && (type == "capsule" || type == "box")) {
      auto size = numbers(c, e, path, "size", 1, 3);
      set_vec(e, "pos", Qi * (0.5 * (a + b) - P));
      set_quat(e, Qi * quat_z_to(a - b));
      if (type == "capsule") size = {size[0], half};
      else size = {size[0], size[0], half};
      set_attr(e, "size", format_numbers(size.data(), static_cast<int>(size.size())));
      erase_attr(e, "fromto");
      return;
    }
    // Anything else (no size, zero length, another type) read_geom refuses as in local
    // coordinates; keep the points.
    const Vec3 al = Qi * (a - P), bl = Qi * (b - P);
    const double v[6] = {al.x(), al.y(), al.z(), bl.x(), bl.y(), bl.z()};
    set_attr(e, "fromto", format_numbers(v, 6));
    return;
  }
  if (e.name == "joint") {
    set_vec(e, "pos", Qi * (vec3(c, e, path, "pos", Vec3::Zero()) - P));
    set_vec(e, "axis", Qi * vec3(c, e, path, "axis", Vec3::UnitZ()));
    return;
  }
  // geom or inertial: a frame.
  const Quat q = quat(c, e, path);
  set_vec(e, "pos", Qi * (vec3(c, e, path, "pos", Vec3::Zero()) - P));
  if (e.name == "inertial" && e.attr("fullinertia")) {
    // In the world's axes: I_local = R^T I R (R = the body's rotation).
    const auto f = numbers(c, e, path, "fullinertia", 6, 6);
    Mat3 i;
    i << f[0], f[3], f[4], f[3], f[1], f[5], f[4], f[5], f[2];
    const Mat3 r = Q.toRotationMatrix();
    const Mat3 l = r.transpose() * i * r;
    const double v[6] = {l(0, 0), l(1, 1), l(2, 2), l(0, 1), l(0, 2), l(1, 2)};
    set_attr(e, "fullinertia", format_numbers(v, 6));
    return;
  }
  set_quat(e, Qi * q);
}

void localise_body(const Ctx& c, XmlElement& e, const std::string& path, const Vec3& P, const Quat& Q) {
  const Vec3 p = vec3(c, e, path, "pos", Vec3::Zero());
  const Quat q = quat(c, e, path);
  set_vec(e, "pos", Q.conjugate() * (p - P));
  set_quat(e, Q.conjugate() * q);
  for (size_t k = 0; k < e.children.size(); ++k) {
    XmlElement& ch = e.children[k];
    const std::string cp = child_path(path, e, k);
    if (ch.name == "body") localise_body(c, ch, cp, p, q);
    else if (ch.name == "geom" || ch.name == "joint" || ch.name == "inertial") localise_child(c, ch, cp, p, q);
  }
}

}  // namespace

void global_to_local(const Ctx& c, XmlElement& worldbody, const std::string& path) {
  for (size_t k = 0; k < worldbody.children.size(); ++k)
    if (worldbody.children[k].name == "body")
      localise_body(c, worldbody.children[k], child_path(path, worldbody, k), Vec3::Zero(), Quat::Identity());
}

}  // namespace pliant::articulated::mjcf_internal
