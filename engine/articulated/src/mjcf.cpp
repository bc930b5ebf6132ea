// MJCF subset -> Model. Element paths in errors: /mujoco/worldbody/body[0]/geom[1],
// attributes as .../@size. Angles (euler, axisangle, hinge range) follow <compiler
// angle> (MuJoCo's default: degree) and eulerseq (default xyz; lower case = axes that
// move with the frame, upper case = fixed axes). <default> classes (nested, with
// class= and childclass=) are applied to joint/geom/motor elements before reading,
// as MuJoCo does: the element's own attributes override its class's.
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "pliant/articulated/io.h"
#include "pliant/core/error.h"
#include "pliant/geom/triangle_mesh.h"
#include "xml.h"

namespace pliant::articulated {
namespace {

struct Ctx {
  explicit Ctx(const std::string& f) : file(f) {}
  const std::string& file;
  Model m;
  std::vector<bool> has_inertial{false};
  double angle_scale = M_PI / 180;  // compiler angle="degree"
  std::string eulerseq = "xyz";
  bool autolimits = false;  // MuJoCo 2.2.2's default
  bool inertia_from_geom = false;  // compiler inertiafromgeom="true": <inertial> ignored
  std::filesystem::path mesh_dir;
  std::map<std::string, std::shared_ptr<const MeshShape>> meshes;  // <asset><mesh name=...>
};

std::string child_path(const std::string& parent, const XmlElement& parent_el, size_t index) {
  const XmlElement& c = parent_el.children[index];
  int n = 0;
  for (size_t k = 0; k < index; ++k)
    if (parent_el.children[k].name == c.name) ++n;
  return parent + "/" + c.name + "[" + std::to_string(n) + "]";
}

void check_attrs(const Ctx& c, const XmlElement& e, const std::string& path,
                 const std::set<std::string>& allowed) {
  for (const auto& [k, v] : e.attrs)
    if (!allowed.count(k)) {
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

// <default> classes: class name -> element name -> attributes (inherited ones merged).
using Defaults = std::map<std::string, std::map<std::string, std::vector<std::pair<std::string, std::string>>>>;

void merge_attrs(std::vector<std::pair<std::string, std::string>>& into,
                 const std::vector<std::pair<std::string, std::string>>& from) {
  for (const auto& [k, v] : from) {
    bool found = false;
    for (auto& kv : into)
      if (kv.first == k) kv.second = v, found = true;
    if (!found) into.emplace_back(k, v);
  }
}

void read_default(const Ctx& c, const XmlElement& e, const std::string& path, const std::string& parent,
                  bool top, Defaults* d) {
  for (const auto& [k, v] : e.attrs)
    if (k != "class") throw InputError(c.file, path + "/@" + k, "unsupported attribute of <default>");
  std::string cls = "main";
  if (const auto* n = e.attr("class")) cls = *n;
  else if (!top) throw InputError(c.file, path + "/@class", "a nested <default> needs a class");
  if (d->count(cls) && !(top && cls == "main")) throw InputError(c.file, path + "/@class", "class \"" + cls + "\" defined twice");
  (*d)[cls] = parent.empty() ? std::map<std::string, std::vector<std::pair<std::string, std::string>>>{} : (*d)[parent];
  for (size_t k = 0; k < e.children.size(); ++k) {
    const XmlElement& ch = e.children[k];
    const std::string p = child_path(path, e, k);
    if (ch.name == "default") {
      read_default(c, ch, p, cls, false, d);
    } else if (ch.name == "joint" || ch.name == "geom" || ch.name == "motor" || ch.name == "mesh") {
      for (const auto& [key, v] : ch.attrs)
        if (key == "class" || key == "name") throw InputError(c.file, p + "/@" + key, "not allowed in a default");
      merge_attrs((*d)[cls][ch.name], ch.attrs);
    } else if (ch.name == "site" || ch.name == "camera" || ch.name == "light" || ch.name == "material") {
      continue;  // visual only
    } else {
      throw InputError(c.file, p, "unsupported element <" + ch.name + "> in <default> (supported: joint, geom, motor, mesh)");
    }
  }
}

void check_class(const Ctx& c, const std::string& name, const std::string& attr_path, const Defaults& d) {
  if (d.count(name)) return;
  std::vector<std::string> names;
  for (const auto& kv : d) names.push_back(kv.first);
  const std::string near = nearest_name(name, names);
  throw InputError(c.file, attr_path,
                   "no default class \"" + name + "\"" + (near.empty() ? "" : "; did you mean \"" + near + "\"?"));
}

// Rewrites joint/geom/motor/mesh elements with their class's attributes under their own.
void apply_defaults(const Ctx& c, XmlElement& e, const std::string& path, const Defaults& d,
                    const std::string& cls) {
  std::string child_cls = cls;
  if (e.name == "body") {
    if (const auto* n = e.attr("childclass")) {
      check_class(c, *n, path + "/@childclass", d);
      child_cls = *n;
    }
  }
  if (e.name == "joint" || e.name == "geom" || e.name == "motor" || e.name == "mesh") {
    std::string own = cls;
    if (const auto* n = e.attr("class")) {
      check_class(c, *n, path + "/@class", d);
      own = *n;
    }
    auto merged = std::vector<std::pair<std::string, std::string>>{};
    const auto it = d.find(own);
    if (it != d.end()) {
      const auto el = it->second.find(e.name);
      if (el != it->second.end()) merged = el->second;
    }
    std::vector<std::pair<std::string, std::string>> own_attrs;
    for (const auto& kv : e.attrs)
      if (kv.first != "class") own_attrs.push_back(kv);
    merge_attrs(merged, own_attrs);
    e.attrs = merged;
  }
  std::vector<std::pair<std::string, std::string>> kept;
  for (const auto& kv : e.attrs)
    if (!(e.name == "body" && kv.first == "childclass")) kept.push_back(kv);
  e.attrs = kept;
  for (size_t k = 0; k < e.children.size(); ++k)
    apply_defaults(c, e.children[k], child_path(path, e, k), d, child_cls);
}

double number(const Ctx& c, const XmlElement& e, const std::string& path, const std::string& key,
              double def, double min) {
  if (!e.attr(key)) return def;
  const double v = numbers(c, e, path, key, 1, 1)[0];
  if (v < min) throw InputError(c.file, path + "/@" + key, "must be >= " + std::to_string(min));
  return v;
}

// A geom's contact parameters (contact_mix mixes them per contact): friction "slide
// [torsion [roll]]" (the sliding value is the Coulomb coefficient; torsion and roll are
// read, checked and unused: only condim 4 / 6 would use them, and those are refused),
// margin, condim 1 or 3, priority (an integer, as MuJoCo's).
void read_geom_contact_params(const Ctx& c, const XmlElement& e, const std::string& path, Geom* g) {
  if (e.attr("friction")) {
    const auto f = numbers(c, e, path, "friction", 1, 3);
    for (double v : f)
      if (v < 0) throw InputError(c.file, path + "/@friction", "friction coefficients must be >= 0");
    g->friction = f[0];
  }
  g->margin = number(c, e, path, "margin", 0, 0);
  if (e.attr("condim")) {
    const double cd = numbers(c, e, path, "condim", 1, 1)[0];
    const std::string problem = contact_pair_condim_problem(cd);
    if (!problem.empty()) throw InputError(c.file, path + "/@condim", problem);
    g->condim = static_cast<int>(cd);
  }
  if (e.attr("priority")) {
    const double pr = numbers(c, e, path, "priority", 1, 1)[0];
    if (pr != std::floor(pr) || std::abs(pr) > 0x7fffffff) throw InputError(c.file, path + "/@priority", "must be an integer");
    g->priority = static_cast<int>(pr);
  }
}

void read_geom(Ctx& c, const XmlElement& e, const std::string& path, int body) {
  check_attrs(c, e, path,
              {"name", "type", "size", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "fromto", "density", "mass", "rgba", "contype", "mesh",
               "conaffinity", "friction", "condim", "material", "group", "margin", "priority"});
  Geom g;
  g.body = body;
  if (const auto* n = e.attr("name")) g.name = *n;
  const std::string type = e.attr("type") ? *e.attr("type") : "sphere";
  static const std::map<std::string, GeomType> types = {{"plane", GeomType::Plane},
                                                        {"sphere", GeomType::Sphere},
                                                        {"capsule", GeomType::Capsule},
                                                        {"box", GeomType::Box},
                                                        {"mesh", GeomType::Mesh}};
  if (!types.count(type))
    throw InputError(c.file, path + "/@type", "unsupported geom type \"" + type +
                                                  "\" (supported: plane, sphere, capsule, box, mesh)");
  g.type = types.at(type);
  g.pos = vec3(c, e, path, "pos", Vec3::Zero());
  g.quat = quat(c, e, path);
  g.density = number(c, e, path, "density", 1000, 0);
  g.mass = number(c, e, path, "mass", -1, 0);
  // fromto gives a capsule's half-length, a box's z half size (x = y = size[0]).
  const size_t need = e.attr("fromto") ? 1 : g.type == GeomType::Box ? 3 : g.type == GeomType::Capsule ? 2 : 1;
  if (g.type == GeomType::Mesh) {
    const auto* name = e.attr("mesh");
    if (!name) throw InputError(c.file, path + "/@mesh", "a mesh geom needs mesh=\"<asset mesh name>\"");
    const auto it = c.meshes.find(*name);
    if (it == c.meshes.end()) {
      std::vector<std::string> names;
      for (const auto& kv : c.meshes) names.push_back(kv.first);
      const std::string near = nearest_name(*name, names);
      throw InputError(c.file, path + "/@mesh",
                       "no mesh named \"" + *name + "\"" + (near.empty() ? "" : "; did you mean \"" + near + "\"?"));
    }
    try {
      geom_set_mesh(g, it->second);
    } catch (const std::invalid_argument& err) {
      throw InputError(c.file, path + "/@mesh", "mesh \"" + *name + "\" " + err.what());
    }
  } else if (e.attr("mesh")) {
    throw InputError(c.file, path + "/@mesh", "mesh= needs type=\"mesh\"");
  }
  if (g.type != GeomType::Plane && g.type != GeomType::Mesh) {
    if (!e.attr("size")) throw InputError(c.file, path + "/@size", "geom needs a size");
    const auto s = numbers(c, e, path, "size", need, 3);
    for (size_t k = 0; k < s.size(); ++k) {
      if (s[k] <= 0) throw InputError(c.file, path + "/@size", "sizes must be positive");
      g.size[k] = s[k];
    }
  }
  if (e.attr("fromto")) {
    if (g.type != GeomType::Capsule && g.type != GeomType::Box)
      throw InputError(c.file, path + "/@fromto", "fromto is supported for capsules and boxes only");
    const auto f = numbers(c, e, path, "fromto", 6, 6);
    const Vec3 a(f[0], f[1], f[2]), b(f[3], f[4], f[5]);
    if ((b - a).norm() < 1e-12) throw InputError(c.file, path + "/@fromto", "zero length");
    // As MuJoCo 2.2.2: fromto overrides pos and any orientation; local z points from
    // the second point to the first (the shapes are symmetric, the frame is MuJoCo's).
    g.pos = 0.5 * (a + b);
    g.quat = quat_z_to(a - b);
    if (g.type == GeomType::Box) {
      g.size[1] = g.size[0];
      g.size[2] = 0.5 * (b - a).norm();
    } else {
      g.size[1] = 0.5 * (b - a).norm();
    }
  }
  // Integers as in MuJoCo: obstacles touch a geom whose contype or conaffinity is
  // nonzero; body-body pairs use the bitmask rule (contact_geom_pairs).
  const double contype = number(c, e, path, "contype", 1, 0), conaff = number(c, e, path, "conaffinity", 1, 0);
  for (const auto& [key, v] : {std::make_pair("contype", contype), std::make_pair("conaffinity", conaff)})
    if (v != std::floor(v) || v > 0x7fffffff) throw InputError(c.file, path + "/@" + key, "must be a non-negative integer");
  g.contype = static_cast<int>(contype);
  g.conaffinity = static_cast<int>(conaff);
  g.contact = contype != 0 || conaff != 0;
  read_geom_contact_params(c, e, path, &g);
  c.m.geoms.push_back(g);
}

void read_body(Ctx& c, const XmlElement& e, const std::string& path, int parent) {
  check_attrs(c, e, path, {"name", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis"});
  Body b;
  b.name = e.attr("name") ? *e.attr("name") : "body" + std::to_string(c.m.bodies.size());
  b.parent = parent;
  b.pos = vec3(c, e, path, "pos", Vec3::Zero());
  b.quat = quat(c, e, path);
  const int id = static_cast<int>(c.m.bodies.size());
  c.m.bodies.push_back(b);
  c.has_inertial.push_back(false);
  for (size_t k = 0; k < e.children.size(); ++k) {
    const XmlElement& ch = e.children[k];
    const std::string p = child_path(path, e, k);
    if (ch.name == "joint" || ch.name == "freejoint") {
      Joint j;
      j.body = id;
      if (ch.name == "freejoint") {
        check_attrs(c, ch, p, {"name"});
        j.type = JointType::Free;
      } else {
        check_attrs(c, ch, p, {"name", "type", "axis", "pos", "damping", "armature", "range", "limited"});
        const std::string type = ch.attr("type") ? *ch.attr("type") : "hinge";
        static const std::map<std::string, JointType> types = {{"hinge", JointType::Hinge},
                                                               {"slide", JointType::Slide},
                                                               {"ball", JointType::Ball},
                                                               {"free", JointType::Free}};
        if (!types.count(type))
          throw InputError(c.file, p + "/@type", "unknown joint type \"" + type + "\"");
        j.type = types.at(type);
        j.axis = vec3(c, ch, p, "axis", Vec3::UnitZ());
        if (j.axis.norm() < 1e-12) throw InputError(c.file, p + "/@axis", "axis is zero");
        j.axis.normalize();
        j.pos = vec3(c, ch, p, "pos", Vec3::Zero());
        j.damping = number(c, ch, p, "damping", 0, 0);
        j.armature = number(c, ch, p, "armature", 0, 0);
        const std::string limited = ch.attr("limited") ? *ch.attr("limited") : "auto";
        if (limited != "true" && limited != "false" && limited != "auto")
          throw InputError(c.file, p + "/@limited", "expected true, false or auto, got \"" + limited + "\"");
        if (limited == "auto" && ch.attr("range") && !c.autolimits)
          throw InputError(c.file, p + "/@limited",
                           "joint has a range but no limited=\"true\"/\"false\" (or <compiler autolimits=\"true\"/>), as MuJoCo requires");
        j.limited = limited == "true" || (limited == "auto" && c.autolimits && ch.attr("range"));
        if (j.limited) {
          if (!ch.attr("range")) throw InputError(c.file, p + "/@range", "a limited joint needs a range");
          if (j.type == JointType::Free)
            throw InputError(c.file, p + "/@range", "free joints take no range");
          const auto r = numbers(c, ch, p, "range", 2, 2);
          if (!(r[0] < r[1])) throw InputError(c.file, p + "/@range", "lower bound must be below the upper bound");
          // Ball: MuJoCo's cone, range="0 max" bounds the joint's total rotation angle.
          if (j.type == JointType::Ball && r[0] != 0)
            throw InputError(c.file, p + "/@range", "a ball joint's range is \"0 max_angle\" (the lower bound must be 0)");
          const double scale = j.type == JointType::Slide ? 1.0 : c.angle_scale;
          j.range_min = r[0] * scale;
          j.range_max = r[1] * scale;
        }
      }
      if (const auto* n = ch.attr("name")) j.name = *n;
      c.m.joints.push_back(j);
    } else if (ch.name == "geom") {
      read_geom(c, ch, p, id);
    } else if (ch.name == "inertial") {
      check_attrs(c, ch, p, {"pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "mass", "diaginertia", "fullinertia"});
      if (!ch.attr("mass")) throw InputError(c.file, p + "/@mass", "inertial needs a mass");
      Body& bd = c.m.bodies[id];
      bd.mass = number(c, ch, p, "mass", 0, 0);
      bd.com = vec3(c, ch, p, "pos", Vec3::Zero());
      if (ch.attr("diaginertia")) {
        const Mat3 r = quat(c, ch, p).toRotationMatrix();
        bd.inertia = r * vec3(c, ch, p, "diaginertia", Vec3::Zero()).asDiagonal() * r.transpose();
      } else if (ch.attr("fullinertia")) {
        for (const char* k : {"quat", "axisangle", "euler", "xyaxes", "zaxis"})
          if (ch.attr(k))
            throw InputError(c.file, p + "/@" + k, "fullinertia is in the body frame; it takes no orientation");
        const auto f = numbers(c, ch, p, "fullinertia", 6, 6);
        bd.inertia << f[0], f[3], f[4], f[3], f[1], f[5], f[4], f[5], f[2];
      } else {
        throw InputError(c.file, p + "/@diaginertia", "inertial needs diaginertia or fullinertia");
      }
      c.has_inertial[id] = !c.inertia_from_geom;
    } else if (ch.name == "body") {
      read_body(c, ch, p, id);
    } else if (ch.name == "site" || ch.name == "camera" || ch.name == "light") {
      // visual only
    } else {
      throw InputError(c.file, p, "unsupported element <" + ch.name + "> in <body>");
    }
  }
}

}  // namespace

// <asset><mesh name file scale/>: triangle meshes through pliant_geom (assimp: OBJ,
// STL, PLY, ...); textures and materials are ignored.
void read_assets(Ctx& c, const XmlElement& e, const std::string& path, const std::filesystem::path& base_dir) {
  for (size_t k = 0; k < e.children.size(); ++k) {
    const XmlElement& ch = e.children[k];
    const std::string p = child_path(path, e, k);
    if (ch.name == "texture" || ch.name == "material") continue;
    if (ch.name != "mesh") throw InputError(c.file, p, "unsupported element <" + ch.name + "> in <asset>");
    check_attrs(c, ch, p, {"name", "file", "scale"});
    if (!ch.attr("file")) throw InputError(c.file, p + "/@file", "mesh needs a file");
    const std::filesystem::path file = base_dir / c.mesh_dir / *ch.attr("file");
    std::string name = ch.attr("name") ? *ch.attr("name") : file.stem().string();
    const Vec3 scale = vec3(c, ch, p, "scale", Vec3::Ones());
    std::shared_ptr<const MeshShape> shape;
    try {
      shape = mesh_load_file(file, scale);
    } catch (const std::exception& err) {
      throw InputError(c.file, p + "/@file", err.what());
    }
    if (c.meshes.count(name)) throw InputError(c.file, p + "/@name", "mesh \"" + name + "\" defined twice");
    c.meshes[name] = shape;
  }
}

std::shared_ptr<const MeshShape> mesh_load_file(const std::filesystem::path& file, const Vec3& scale) {
  const geom::TriangleMesh tm = geom::load_mesh(file, file.string());
  auto shape = std::make_shared<MeshShape>();
  for (const auto& v : tm.vertices) shape->vertices.emplace_back(v[0] * scale.x(), v[1] * scale.y(), v[2] * scale.z());
  for (const auto& t : tm.triangles)
    shape->triangles.push_back({static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
  return shape;
}

void geom_set_mesh(Geom& g, const std::shared_ptr<const MeshShape>& shape) {
  // Re-centre at the mesh's centre of mass (vertices stay in the geom frame).
  double volume;
  Vec3 centre;
  mesh_volume_moments(*shape, &volume, &centre, nullptr);
  if (!(volume > 0)) throw std::invalid_argument("has no positive volume (not closed or inward-facing)");
  auto shifted = std::make_shared<MeshShape>(*shape);
  for (Vec3& v : shifted->vertices) v -= centre;
  g.type = GeomType::Mesh;
  g.mesh = shifted;
  g.pos += g.quat * centre;
}

// <contact><pair geom1 geom2 [friction] [margin] [condim]>: an explicit pair
// (Model::contact_pairs), friction's first (sliding) value its Coulomb coefficient,
// margin its activation distance, condim 1 (frictionless) or 3 (the default);
// condim 4 / 6 (torsional / rolling friction) rejected, as solref/solimp/gap.
void read_contact_pair(Ctx& c, const XmlElement& e, const std::string& path) {
  check_attrs(c, e, path, {"name", "geom1", "geom2", "friction", "condim", "margin"});
  ContactPair pair;
  int* ids[2] = {&pair.geom1, &pair.geom2};
  const char* keys[2] = {"geom1", "geom2"};
  for (int i = 0; i < 2; ++i) {
    const auto* name = e.attr(keys[i]);
    if (!name) throw InputError(c.file, path + "/@" + keys[i], "<pair> needs geom1 and geom2");
    std::string why;
    *ids[i] = geom_named(c.m, *name, &why);
    if (*ids[i] < 0) throw InputError(c.file, path + "/@" + keys[i], why);
  }
  const std::string problem = contact_pair_problem(c.m, pair.geom1, pair.geom2);
  if (!problem.empty()) throw InputError(c.file, path + "/@geom2", problem);
  if (e.attr("friction")) pair.mu = numbers(c, e, path, "friction", 1, 5)[0];
  if (e.attr("friction") && pair.mu < 0) throw InputError(c.file, path + "/@friction", "must be >= 0");
  pair.margin = number(c, e, path, "margin", 0, 0);
  if (e.attr("condim")) {
    const double cd = numbers(c, e, path, "condim", 1, 1)[0];
    const std::string problem = contact_pair_condim_problem(cd);
    if (!problem.empty()) throw InputError(c.file, path + "/@condim", problem);
    pair.frictionless = cd == 1;
  }
  c.m.contact_pairs.push_back(pair);
}

// <contact>: <exclude body1 body2> (body pairs that never touch) and <pair>; anything
// else rejected.
void read_contact(Ctx& c, const XmlElement& e, const std::string& path) {
  check_attrs(c, e, path, {});
  for (size_t k = 0; k < e.children.size(); ++k) {
    const XmlElement& ch = e.children[k];
    const std::string cp = child_path(path, e, k);
    if (ch.name == "pair") {
      read_contact_pair(c, ch, cp);
      continue;
    }
    if (ch.name != "exclude")
      throw InputError(c.file, cp, "unsupported element <" + ch.name + "> in <contact> (only <exclude> and <pair> are supported)");
    check_attrs(c, ch, cp, {"name", "body1", "body2"});
    int ids[2];
    const char* keys[2] = {"body1", "body2"};
    for (int i = 0; i < 2; ++i) {
      const auto* name = ch.attr(keys[i]);
      if (!name) throw InputError(c.file, cp + "/@" + keys[i], "<exclude> needs body1 and body2");
      std::string why;
      ids[i] = body_named(c.m, *name, &why);
      if (ids[i] < 0)
        throw InputError(c.file, cp + "/@" + keys[i],
                         why + (*name == "world" ? " (excluding the world's obstacles is not supported)" : ""));
    }
    if (ids[0] == ids[1]) throw InputError(c.file, cp + "/@body2", "a body cannot be excluded from itself");
    c.m.contact_exclude.push_back({std::min(ids[0], ids[1]), std::max(ids[0], ids[1])});
  }
}

Model model_from_mjcf(const std::string& text, const std::string& file, const std::filesystem::path& base_dir) {
  XmlElement root = parse_xml(text, file);
  if (root.name != "mujoco") throw InputError(file, "/" + root.name, "root element must be <mujoco>");
  Ctx c(file);
  // Compiler settings and default classes first: they apply wherever they appear.
  Defaults defaults;
  defaults["main"];
  for (size_t k = 0; k < root.children.size(); ++k) {
    const XmlElement& e = root.children[k];
    const std::string p = child_path("/mujoco", root, k);
    if (e.name == "compiler") {
      check_attrs(c, e, p, {"angle", "inertiafromgeom", "coordinate", "autolimits", "eulerseq", "meshdir", "assetdir",
                            "texturedir"});
      if (const auto* d = e.attr("assetdir"); d && !e.attr("meshdir")) c.mesh_dir = *d;
      if (const auto* d = e.attr("meshdir")) c.mesh_dir = *d;
      if (const auto* a = e.attr("inertiafromgeom")) {
        if (*a == "false")
          throw InputError(file, p + "/@inertiafromgeom",
                           "\"false\" (bodies without <inertial> get no mass) is not supported; use auto or true");
        if (*a != "auto" && *a != "true") throw InputError(file, p + "/@inertiafromgeom", "expected auto or true");
        c.inertia_from_geom = *a == "true";
      }
      if (e.attr("coordinate") && *e.attr("coordinate") != "local")
        throw InputError(file, p + "/@coordinate",
                         "only local coordinates are supported (coordinate=\"global\" changes every frame)");
      if (const auto* a = e.attr("angle")) {
        if (*a != "degree" && *a != "radian") throw InputError(file, p + "/@angle", "expected degree or radian");
        c.angle_scale = *a == "radian" ? 1.0 : M_PI / 180;
      }
      if (const auto* q = e.attr("eulerseq")) {
        bool ok = q->size() == 3;
        for (char ch : *q) ok = ok && std::string("xyzXYZ").find(ch) != std::string::npos;
        if (!ok) throw InputError(file, p + "/@eulerseq", "expected three of x y z X Y Z, got \"" + *q + "\"");
        c.eulerseq = *q;
      }
      if (const auto* a = e.attr("autolimits")) c.autolimits = *a == "true";
    } else if (e.name == "default") {
      read_default(c, e, p, "", true, &defaults);
    }
  }
  for (size_t k = 0; k < root.children.size(); ++k) {
    XmlElement& e = root.children[k];
    if (e.name == "worldbody" || e.name == "actuator" || e.name == "asset")
      apply_defaults(c, e, child_path("/mujoco", root, k), defaults, "main");
  }
  for (size_t k = 0; k < root.children.size(); ++k) {
    const XmlElement& e = root.children[k];
    if (e.name == "asset") read_assets(c, e, child_path("/mujoco", root, k), base_dir);
  }
  Body world;
  world.name = "world";
  c.m.bodies.push_back(world);
  if (const auto* n = root.attr("model")) c.m.name = *n;
  const std::string rp = "/mujoco";
  std::vector<size_t> contact_elements;
  for (size_t k = 0; k < root.children.size(); ++k) {
    const XmlElement& e = root.children[k];
    const std::string p = child_path(rp, root, k);
    if (e.name == "compiler" || e.name == "default") {
      continue;  // read above
    } else if (e.name == "option") {
      check_attrs(c, e, p, {"timestep", "gravity", "integrator", "iterations", "solver"});
      if (!e.children.empty())  // <flag> can switch contact, gravity, limits... off
        throw InputError(file, child_path(p, e, 0),
                         "unsupported element <" + e.children[0].name + "> in <option> (it changes the dynamics)");
      c.m.timestep = number(c, e, p, "timestep", 0.002, 1e-9);
      c.m.gravity = vec3(c, e, p, "gravity", Vec3(0, 0, -9.81));
    } else if (e.name == "worldbody") {
      for (size_t w = 0; w < e.children.size(); ++w) {
        const XmlElement& ch = e.children[w];
        const std::string cp = child_path(p, e, w);
        if (ch.name == "body") read_body(c, ch, cp, 0);
        else if (ch.name == "geom") read_geom(c, ch, cp, 0);
        else if (ch.name == "light" || ch.name == "camera" || ch.name == "site") continue;
        else throw InputError(file, cp, "unsupported element <" + ch.name + "> in <worldbody>");
      }
    } else if (e.name == "actuator") {
      for (size_t a = 0; a < e.children.size(); ++a) {
        const XmlElement& ch = e.children[a];
        const std::string cp = child_path(p, e, a);
        if (ch.name != "motor") throw InputError(file, cp, "only <motor> actuators are supported");
        check_attrs(c, ch, cp, {"name", "joint", "gear", "ctrlrange", "ctrllimited"});
        if (!ch.attr("joint")) throw InputError(file, cp + "/@joint", "motor needs a joint");
        Actuator act;
        if (const auto* n = ch.attr("name")) act.name = *n;
        act.joint = -1;
        for (size_t j = 0; j < c.m.joints.size(); ++j)
          if (c.m.joints[j].name == *ch.attr("joint")) act.joint = static_cast<int>(j);
        if (act.joint < 0) throw InputError(file, cp + "/@joint", "no joint named \"" + *ch.attr("joint") + "\"");
        if (ch.attr("gear")) act.gear = numbers(c, ch, cp, "gear", 1, 6)[0];
        if (ch.attr("ctrlrange")) {
          const auto r = numbers(c, ch, cp, "ctrlrange", 2, 2);
          if (r[0] > r[1]) throw InputError(file, cp + "/@ctrlrange", "lower bound above upper bound");
          act.ctrl_min = r[0];
          act.ctrl_max = r[1];
        }
        if (ch.attr("ctrllimited") && *ch.attr("ctrllimited") == "false") {
          act.ctrl_min = -1e300;
          act.ctrl_max = 1e300;
        }
        c.m.actuators.push_back(act);
      }
    } else if (e.name == "visual" || e.name == "asset" || e.name == "statistic" || e.name == "size" ||
               e.name == "sensor" || e.name == "keyframe") {  // asset: above; the rest do not change the dynamics
      continue;
    } else if (e.name == "contact") {
      contact_elements.push_back(k);  // after the bodies: exclude names them
    } else if (e.name == "tendon" || e.name == "equality" || e.name == "include" ||
               e.name == "custom" || e.name == "extension") {
      throw InputError(file, p, "unsupported element <" + e.name + "> in <mujoco>: it changes the model or its dynamics, and "
                                "Pliant does not support it (remove it, or model it with joints and motors)");
    } else {
      throw InputError(file, p, "unsupported element <" + e.name + "> in <mujoco>");
    }
  }
  for (size_t k : contact_elements) read_contact(c, root.children[k], child_path(rp, root, k));
  try {
    model_finalize(c.m, c.has_inertial);
  } catch (const std::invalid_argument& err) {
    throw InputError(file, "/mujoco/worldbody", err.what());
  }
  return c.m;
}

Model model_load_file(const std::filesystem::path& path, const std::string& label) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(label, "", "cannot read model file " + path.string());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  if (path.extension() == ".xml") return model_from_mjcf(text, label, path.parent_path());
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text, nullptr, true, true);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(label, "", std::string("JSON syntax error: ") + e.what());
  }
  JsonReader r(doc, label);
  Model m = model_from_json(r, path.parent_path());
  r.finish();
  return m;
}

}  // namespace pliant::articulated
