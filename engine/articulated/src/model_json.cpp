// Pliant JSON models (see README.md for the format): explicit bodies, or a chain
// generator that goes through the same MJCF text MuJoCo loads.
#include <stdexcept>

#include "pliant/articulated/io.h"
#include "pliant/core/error.h"

namespace pliant::articulated {
namespace {

Vec3 vec3(JsonReader& r, const char* key, Vec3 def) {
  const auto v = r.numbers(key, {def.x(), def.y(), def.z()}, 3, 3);
  return Vec3(v[0], v[1], v[2]);
}

Quat quat(JsonReader& r) {
  const auto v = r.numbers("quat", {1, 0, 0, 0}, 4, 4);
  const Quat q(v[0], v[1], v[2], v[3]);
  if (q.norm() < 1e-12) r.fail("quat", "quaternion is zero");
  return q.normalized();
}

VecX read_range(JsonReader& r) {
  const auto v = r.numbers("range", {}, 2, 2);
  if (!(v[0] < v[1])) r.fail("range", "lower bound must be below the upper bound");
  VecX out(2);
  out << v[0], v[1];
  return out;
}

Geom read_geom(JsonReader& r, int body, const std::filesystem::path& base_dir) {
  Geom g;
  g.body = body;
  g.name = r.string("name", "");
  const std::string type =
      r.choice("type", "sphere", {"plane", "sphere", "capsule", "box", "mesh", "cylinder", "ellipsoid"});
  // Cylinders (radius, half-height) and ellipsoids (three radii) read as capsule / box
  // sizes, then become tessellated mesh geoms as in MJCF (Geom::tessellates).
  g.type = type == "plane" ? GeomType::Plane
           : type == "sphere" ? GeomType::Sphere
           : type == "capsule" || type == "cylinder" ? GeomType::Capsule
           : type == "box" || type == "ellipsoid" ? GeomType::Box
                           : GeomType::Mesh;
  if (type == "cylinder") g.tessellates = Geom::Tessellated::Cylinder;
  if (type == "ellipsoid") g.tessellates = Geom::Tessellated::Ellipsoid;
  g.pos = vec3(r, "pos", Vec3::Zero());
  g.quat = quat(r);
  g.density = r.number("density", 1000, 0);
  g.mass = r.has("mass") ? r.number("mass", 1, 0) : -1;
  g.contact = r.boolean("contact", true);
  // Body-body filter (MuJoCo's bitmask rule); "contact": false also clears both.
  g.contype = static_cast<int>(r.integer("contype", g.contact ? 1 : 0, 0, 0x7fffffff));
  g.conaffinity = static_cast<int>(r.integer("conaffinity", g.contact ? 1 : 0, 0, 0x7fffffff));
  // Contact parameters, MJCF's names (contact_mix): "friction" a number or [slide,
  // torsion, roll] (torsion / roll: condim 4 / 6), "margin" (m), "condim" 1, 3, 4, 6,
  // "priority" (integer).
  if (r.has("friction")) {
    const auto f = r.value()["friction"].is_array() ? r.numbers("friction", {}, 1, 3, 0) : std::vector<double>{r.number("friction", 0, 0)};
    g.friction = f[0];
    if (f.size() > 1) g.torsion = f[1];
    if (f.size() > 2) g.roll = f[2];
  }
  g.margin = r.number("margin", 0, 0);
  if (r.has("condim")) {
    const double cd = r.number("condim", 3, 0);
    const std::string why = contact_pair_condim_problem(cd);
    if (!why.empty()) r.fail("condim", why);
    g.condim = static_cast<int>(cd);
  }
  g.priority = static_cast<int>(r.integer("priority", 0, -0x7fffffff, 0x7fffffff));
  const size_t need = g.type == GeomType::Box ? 3 : (g.type == GeomType::Capsule && !r.has("fromto") ? 2 : 1);
  if (g.type == GeomType::Mesh) {
    // As MJCF's <asset><mesh file scale>: the file relative to the model's folder.
    if (r.has("size")) r.fail("size", "a mesh geom takes its size from \"file\" and \"scale\"");
    const std::string file = r.required_string("file");
    const Vec3 scale = vec3(r, "scale", Vec3::Ones());
    if (!(scale.array() > 0).all()) r.fail("scale", "scale factors must be positive");
    const std::filesystem::path path = std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base_dir / file;
    std::shared_ptr<const MeshShape> shape;
    try {
      shape = mesh_load_file(path, scale);
    } catch (const std::exception& e) {
      r.fail("file", e.what());
    }
    try {
      geom_set_mesh(g, shape);
    } catch (const std::invalid_argument& e) {
      r.fail("file", "mesh \"" + file + "\" " + e.what());
    }
  } else {
    if (r.has("file")) r.fail("file", "\"file\" needs \"type\": \"mesh\"");
    if (r.has("scale")) r.fail("scale", "\"scale\" needs \"type\": \"mesh\"");
  }
  if (g.type != GeomType::Plane && g.type != GeomType::Mesh) {
    if (!r.has("size")) r.fail("size", "geom needs a size");
    const auto s = r.numbers("size", {}, need, 3, 1e-9);
    for (size_t k = 0; k < s.size(); ++k) g.size[k] = s[k];
  }
  if (r.has("fromto")) {
    if (g.type != GeomType::Capsule) r.fail("fromto", "fromto is supported for capsules and cylinders only");
    const auto f = r.numbers("fromto", {}, 6, 6);
    const Vec3 a(f[0], f[1], f[2]), b(f[3], f[4], f[5]);
    if ((b - a).norm() < 1e-12) r.fail("fromto", "zero length");
    g.pos = 0.5 * (a + b);
    g.size[1] = 0.5 * (b - a).norm();
    g.quat = Quat::FromTwoVectors(Vec3::UnitZ(), (b - a).normalized());
  }
  if (g.tessellates == Geom::Tessellated::Cylinder)
    g.mesh = std::make_shared<const MeshShape>(cylinder_mesh(g.size[0], g.size[1]));
  if (g.tessellates == Geom::Tessellated::Ellipsoid) g.mesh = std::make_shared<const MeshShape>(ellipsoid_mesh(g.size));
  if (g.tessellates != Geom::Tessellated::None) g.type = GeomType::Mesh;
  r.finish();
  return g;
}

}  // namespace

Model model_from_json(JsonReader& r, const std::filesystem::path& base_dir) {
  Model m;
  if (auto ch = r.object("chain")) {
    const int links = static_cast<int>(ch->integer("links", 10, 1, 100000));
    const double len = ch->number("link_length", 0.1, 1e-6), rad = ch->number("radius", 0.01, 1e-6);
    ch->finish();
    m = model_from_mjcf(chain_mjcf(links, len, rad), r.file());
    if (r.has("bodies")) r.fail("bodies", "give either \"chain\" or \"bodies\", not both");
  } else {
    Body world;
    world.name = "world";
    m.bodies.push_back(world);
    std::vector<bool> has_inertial{false};
    std::vector<JsonReader> bodies = r.objects("bodies");
    if (bodies.empty()) r.fail("bodies", "a model needs \"bodies\" (or a \"chain\")");
    for (JsonReader& b : bodies) {
      Body body;
      body.name = b.required_string("name");
      for (const Body& o : m.bodies)
        if (o.name == body.name) b.fail("name", "body name \"" + body.name + "\" used twice");
      const std::string parent = b.string("parent", "world");
      body.parent = -1;
      for (size_t i = 0; i < m.bodies.size(); ++i)
        if (m.bodies[i].name == parent) body.parent = static_cast<int>(i);
      if (body.parent < 0) b.fail("parent", "no earlier body named \"" + parent + "\"");
      body.pos = vec3(b, "pos", Vec3::Zero());
      body.quat = quat(b);
      const int id = static_cast<int>(m.bodies.size());
      m.bodies.push_back(body);
      has_inertial.push_back(false);
      for (JsonReader& j : b.objects("joints")) {
        Joint jt;
        jt.body = id;
        jt.name = j.string("name", "");
        const std::string type = j.choice("type", "hinge", {"hinge", "slide", "ball", "free"});
        jt.type = type == "hinge" ? JointType::Hinge
                  : type == "slide" ? JointType::Slide
                  : type == "ball" ? JointType::Ball
                                   : JointType::Free;
        jt.axis = vec3(j, "axis", Vec3::UnitZ());
        if (jt.axis.norm() < 1e-12) j.fail("axis", "axis is zero");
        jt.axis.normalize();
        jt.pos = vec3(j, "pos", Vec3::Zero());
        jt.damping = j.number("damping", 0, 0);
        jt.armature = j.number("armature", 0, 0);
        jt.frictionloss = j.number("frictionloss", 0, 0);  // dry friction, N m or N per dof
        // A spring 1/2 stiffness (q - springref)^2 and the model-pose value ref, as MJCF's
        // (hinges and slides; radians or metres).
        jt.stiffness = j.number("stiffness", 0, 0);
        jt.springref = j.number("springref", 0, -1e300, 1e300);
        jt.ref = j.number("ref", 0, -1e300, 1e300);
        if (jt.type == JointType::Ball || jt.type == JointType::Free)
          for (const auto& [key, value] : {std::pair{"stiffness", jt.stiffness}, {"springref", jt.springref}, {"ref", jt.ref}})
            if (value != 0) j.fail(key, std::string("a nonzero ") + key + " is supported on hinge and slide joints only");
        if (j.has("range")) {
          if (jt.type == JointType::Free) j.fail("range", "free joints take no range");
          const VecX r = read_range(j);
          // Ball: [0, max] bounds the total rotation angle (MuJoCo's cone).
          if (jt.type == JointType::Ball && r[0] != 0)
            j.fail("range", "a ball joint's range is [0, max_angle] (the lower bound must be 0)");
          jt.limited = true;
          jt.range_min = r[0];
          jt.range_max = r[1];
        }
        j.finish();
        m.joints.push_back(jt);
      }
      for (JsonReader& g : b.objects("geoms")) m.geoms.push_back(read_geom(g, id, base_dir));
      if (auto in = b.object("inertial")) {
        m.bodies[id].mass = in->required_number("mass", 1e-12);
        m.bodies[id].com = vec3(*in, "pos", Vec3::Zero());
        m.bodies[id].inertia = vec3(*in, "diaginertia", Vec3::Zero()).asDiagonal();
        in->finish();
        has_inertial[id] = true;
      }
      b.finish();
    }
    for (JsonReader& a : r.objects("actuators")) {
      Actuator act;
      const std::string jn = a.required_string("joint");
      act.joint = -1;
      for (size_t j = 0; j < m.joints.size(); ++j)
        if (m.joints[j].name == jn) act.joint = static_cast<int>(j);
      if (act.joint < 0) a.fail("joint", "no joint named \"" + jn + "\"");
      act.name = a.string("name", jn);
      act.gear = a.number("gear", 1);
      const auto cr = a.numbers("ctrlrange", {-1, 1}, 2, 2);
      if (cr[0] > cr[1]) a.fail("ctrlrange", "lower bound above upper bound");
      act.ctrl_min = cr[0];
      act.ctrl_max = cr[1];
      a.finish();
      m.actuators.push_back(act);
    }
    // Body pairs that never touch (as MJCF's <contact><exclude body1 body2>).
    for (JsonReader& x : r.objects("exclude")) {
      int ids[2];
      const char* keys[2] = {"body1", "body2"};
      for (int i = 0; i < 2; ++i) {
        std::string why;
        ids[i] = body_named(m, x.required_string(keys[i]), &why);
        if (ids[i] < 0) x.fail(keys[i], why);
      }
      if (ids[0] == ids[1]) x.fail("body2", "a body cannot be excluded from itself");
      x.finish();
      m.contact_exclude.push_back({std::min(ids[0], ids[1]), std::max(ids[0], ids[1])});
    }
    try {
      model_finalize(m, has_inertial);
    } catch (const std::invalid_argument& e) {
      throw InputError(r.file(), r.child_pointer("bodies"), e.what());
    }
  }
  m.name = r.string("name", m.name);
  m.gravity = vec3(r, "gravity", m.gravity);
  m.timestep = r.number("timestep", m.timestep, 1e-9);
  for (JsonReader& g : r.objects("obstacles")) m.geoms.push_back(read_geom(g, 0, base_dir));
  return m;
}

}  // namespace pliant::articulated
