// MJCF <body> tree: bodies, joints, geoms (with their contact parameters), inertials.
#include <cmath>
#include <stdexcept>

#include "mjcf_internal.h"
#include "pliant/articulated/io.h"
#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"

namespace pliant::articulated::mjcf_internal {
namespace {

// A geom's contact parameters (contact_mix mixes them per contact): friction "slide
// [torsion [roll]]" (the sliding value is the Coulomb coefficient; torsion and roll,
// lengths, serve condim 4 / 6; values not given keep MuJoCo's defaults), margin,
// condim 1, 3, 4 or 6, priority (an integer, as MuJoCo's).
void read_geom_contact_params(const Ctx& c, const XmlElement& e, const std::string& path, Geom* g) {
  if (e.attr("friction")) {
    const auto f = numbers(c, e, path, "friction", 1, 3);
    for (double v : f)
      if (v < 0) throw InputError(c.file, path + "/@friction", "friction coefficients must be >= 0");
    g->friction = f[0];
    if (f.size() > 1) g->torsion = f[1];
    if (f.size() > 2) g->roll = f[2];
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

}  // namespace

void read_geom(Ctx& c, const XmlElement& e, const std::string& path, int body) {
  check_attrs(c, e, path,
              {"name", "type", "size", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "fromto", "density", "mass", "rgba", "contype", "mesh",
               "conaffinity", "friction", "condim", "material", "group", "margin", "priority"});
  Geom g;
  g.body = body;
  if (const auto* n = e.attr("name")) g.name = *n;
  const std::string type = e.attr("type") ? *e.attr("type") : "sphere";
  // Cylinders and ellipsoids: read as their exact shape, then tessellated (below).
  static const std::map<std::string, GeomType> types = {{"plane", GeomType::Plane},
                                                        {"sphere", GeomType::Sphere},
                                                        {"capsule", GeomType::Capsule},
                                                        {"cylinder", GeomType::Capsule},
                                                        {"box", GeomType::Box},
                                                        {"ellipsoid", GeomType::Box},
                                                        {"mesh", GeomType::Mesh}};
  if (!types.count(type))
    throw InputError(c.file, path + "/@type", "unsupported geom type \"" + type +
                                                  "\" (supported: plane, sphere, capsule, cylinder, box, ellipsoid, mesh)");
  g.type = types.at(type);
  if (type == "cylinder") g.tessellates = Geom::Tessellated::Cylinder;
  if (type == "ellipsoid") g.tessellates = Geom::Tessellated::Ellipsoid;
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
      g.mesh_inertia = c.mesh_inertia;
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
    if ((g.type != GeomType::Capsule && g.type != GeomType::Box) || g.tessellates == Geom::Tessellated::Ellipsoid)
      throw InputError(c.file, path + "/@fromto", "fromto is supported for capsules, cylinders and boxes only");
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
  if (g.tessellates == Geom::Tessellated::Cylinder)
    g.mesh = std::make_shared<const MeshShape>(cylinder_mesh(g.size[0], g.size[1]));
  if (g.tessellates == Geom::Tessellated::Ellipsoid) g.mesh = std::make_shared<const MeshShape>(ellipsoid_mesh(g.size));
  if (g.tessellates != Geom::Tessellated::None) g.type = GeomType::Mesh;
  g.exact_plane_contact = c.exact_plane_contact;
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
        check_attrs(c, ch, p, {"name", "type", "axis", "pos", "damping", "armature", "frictionloss", "range",
                               "limited", "ref", "stiffness", "springref"});
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
        j.frictionloss = number(c, ch, p, "frictionloss", 0, 0);
        // ref / springref are joint values: angles for hinges (<compiler angle>), metres for slides.
        const double value_scale = j.type == JointType::Hinge ? c.angle_scale : 1.0;
        j.ref = number(c, ch, p, "ref", 0, -1e300) * value_scale;
        j.stiffness = number(c, ch, p, "stiffness", 0, 0);
        j.springref = number(c, ch, p, "springref", 0, -1e300) * value_scale;
        if (j.type == JointType::Ball || j.type == JointType::Free)
          for (const auto& [key, value] : {std::pair{"ref", j.ref}, {"stiffness", j.stiffness}, {"springref", j.springref}})
            if (value != 0)
              throw InputError(c.file, p + "/@" + key,
                               std::string("a nonzero ") + key + " is supported on hinge and slide joints only");
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

}  // namespace pliant::articulated::mjcf_internal
