// MJCF attribute values: element paths, allowed names, numbers, vectors, orientations.
#include <cctype>
#include <cmath>
#include <sstream>

#include "mjcf_internal.h"
#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"

namespace pliant::articulated::mjcf_internal {

std::string child_path(const std::string& parent, const XmlElement& parent_el, size_t index) {
  const XmlElement& c = parent_el.children[index];
  int n = 0;
  for (size_t k = 0; k < index; ++k)
    if (parent_el.children[k].name == c.name) ++n;
  return parent + "/" + c.name + "[" + std::to_string(n) + "]";
}

namespace {

// MuJoCo constraint-solver settings with no counterpart in Pliant's penalties: what
// Pliant uses instead, or nullptr when (element, attribute) is not one of them.
const char* solver_param_counterpart(const std::string& element, const std::string& attr) {
  if ((element == "geom" || element == "pair") && (attr == "solref" || attr == "solimp" || attr == "solmix"))
    return "Pliant's penalty contact (the scene's contact.stiffness)";
  if (element == "joint" && (attr == "solreflimit" || attr == "solimplimit"))
    return "Pliant's joint-limit penalty (its own stiffness)";
  if (element == "joint" && (attr == "solreffriction" || attr == "solimpfriction"))
    return "Pliant's dry joint friction (frictionloss, regularised by contact.spin_eps / slip_eps)";
  if (element == "option" && (attr == "impratio" || attr == "cone" || attr == "noslip_iterations" ||
                              attr == "noslip_tolerance"))
    return "Pliant's friction (the scene's contact.friction and mu)";
  return nullptr;
}

}  // namespace

void check_attrs(Ctx& c, const XmlElement& e, const std::string& path, const std::set<std::string>& allowed) {
  for (const auto& [k, v] : e.attrs)
    if (!allowed.count(k)) {
      if (const char* instead = solver_param_counterpart(e.name, k)) {
        if (c.ignore_solver_params) {
          c.m.ignored_attributes.push_back(path + "/@" + k);
          continue;
        }
        throw InputError(c.file, path + "/@" + k,
                         std::string("MuJoCo's constraint-solver parameter has no counterpart in ") + instead +
                             "; to load the model with it, set \"mjcf\": {\"ignore_solver_params\": true} in the scene");
      }
      std::vector<std::string> names(allowed.begin(), allowed.end());
      const std::string near = nearest_name(k, names);
      throw InputError(c.file, path + "/@" + k,
                       "unsupported attribute of <" + e.name + ">" +
                           (near.empty() ? "" : "; did you mean \"" + near + "\"?"));
    }
}

std::vector<double> numbers(const Ctx& c, const XmlElement& e, const std::string& path,
                            const std::string& key, size_t min_n, size_t max_n) {
  const std::string* v = e.attr(key);
  std::istringstream in(*v);
  std::vector<double> out;
  std::string tok;
  while (in >> tok) {
    char* end = nullptr;
    const double d = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0' || !std::isfinite(d))
      throw InputError(c.file, path + "/@" + key, "expected numbers, got \"" + *v + "\"");
    out.push_back(d);
  }
  if (out.size() < min_n || out.size() > max_n)
    throw InputError(c.file, path + "/@" + key,
                     "expected " + std::to_string(min_n) +
                         (max_n != min_n ? " to " + std::to_string(max_n) : "") + " numbers, got " +
                         std::to_string(out.size()));
  return out;
}

Vec3 vec3(const Ctx& c, const XmlElement& e, const std::string& path, const std::string& key, Vec3 def) {
  if (!e.attr(key)) return def;
  const auto v = numbers(c, e, path, key, 3, 3);
  return Vec3(v[0], v[1], v[2]);
}

// MuJoCo's rotation taking local z to v (mjuu_z2quat): about z x v by the angle
// between them; a half turn about x when v points along -z.
Quat quat_z_to(const Vec3& v) {
  Vec3 axis = Vec3::UnitZ().cross(v);
  const double s = axis.norm();
  if (s < 1e-10) axis = Vec3::UnitX();
  else axis /= s;
  return Quat(Eigen::AngleAxisd(std::atan2(s, v.z()), axis));
}

// Orientation from quat, axisangle (x y z angle), euler (three angles, eulerseq),
// xyaxes (x axis, then y made orthogonal to it; z = x cross y) or zaxis (the
// smallest rotation taking z to it), as MuJoCo's compiler reads them.
Quat quat(const Ctx& c, const XmlElement& e, const std::string& path) {
  static const char* const kinds[] = {"quat", "axisangle", "euler", "xyaxes", "zaxis"};
  int given = 0;
  std::string last;
  for (const char* k : kinds)
    if (e.attr(k)) ++given, last = k;
  if (given > 1)
    throw InputError(c.file, path + "/@" + last,
                     "give one orientation (quat, axisangle, euler, xyaxes or zaxis), not several");
  if (e.attr("xyaxes")) {
    const auto v = numbers(c, e, path, "xyaxes", 6, 6);
    Vec3 x(v[0], v[1], v[2]), y(v[3], v[4], v[5]);
    if (x.norm() < 1e-12) throw InputError(c.file, path + "/@xyaxes", "x axis is zero");
    x.normalize();
    y -= x * x.dot(y);
    if (y.norm() < 1e-12) throw InputError(c.file, path + "/@xyaxes", "y axis is zero or parallel to the x axis");
    y.normalize();
    Mat3 r;
    r << x, y, x.cross(y).normalized();
    return Quat(r).normalized();
  }
  if (e.attr("zaxis")) {
    const Vec3 z = vec3(c, e, path, "zaxis", Vec3::UnitZ());
    if (z.norm() < 1e-12) throw InputError(c.file, path + "/@zaxis", "axis is zero");
    return quat_z_to(z);
  }
  if (e.attr("axisangle")) {
    const auto v = numbers(c, e, path, "axisangle", 4, 4);
    const Vec3 axis(v[0], v[1], v[2]);
    if (axis.norm() < 1e-12) throw InputError(c.file, path + "/@axisangle", "axis is zero");
    return Quat(Eigen::AngleAxisd(v[3] * c.angle_scale, axis.normalized()));
  }
  if (e.attr("euler")) {
    const auto v = numbers(c, e, path, "euler", 3, 3);
    Quat q = Quat::Identity();
    for (int i = 0; i < 3; ++i) {
      const char a = c.eulerseq[i];
      const Vec3 axis = Vec3::Unit(std::tolower(a) - 'x');
      const Quat r(Eigen::AngleAxisd(v[i] * c.angle_scale, axis));
      q = std::islower(a) ? Quat(q * r) : Quat(r * q);  // moving (intrinsic) or fixed axes
    }
    return q.normalized();
  }
  if (!e.attr("quat")) return Quat::Identity();
  const auto v = numbers(c, e, path, "quat", 4, 4);
  const Quat q(v[0], v[1], v[2], v[3]);
  if (q.norm() < 1e-12) throw InputError(c.file, path + "/@quat", "quaternion is zero");
  return q.normalized();
}

double number(const Ctx& c, const XmlElement& e, const std::string& path, const std::string& key,
              double def, double min) {
  if (!e.attr(key)) return def;
  const double v = numbers(c, e, path, key, 1, 1)[0];
  if (v < min) throw InputError(c.file, path + "/@" + key, "must be >= " + std::to_string(min));
  return v;
}

}  // namespace pliant::articulated::mjcf_internal
