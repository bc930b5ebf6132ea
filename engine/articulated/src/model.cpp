// Model bookkeeping and mass properties (MuJoCo's geom formulas so MJCF models
// compile to the same masses and inertias in both engines).
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "pliant/articulated/model.h"
#include "pliant/core/json_reader.h"  // nearest_name

namespace pliant::articulated {

int joint_nq(JointType t) {
  switch (t) {
    case JointType::Hinge:
    case JointType::Slide: return 1;
    case JointType::Ball: return 4;
    case JointType::Free: return 7;
  }
  return 0;
}

int joint_nv(JointType t) {
  switch (t) {
    case JointType::Hinge:
    case JointType::Slide: return 1;
    case JointType::Ball: return 3;
    case JointType::Free: return 6;
  }
  return 0;
}

void geom_mass_properties(const Geom& g, double* mass, Mat3* inertia) {
  double volume = 0;
  Vec3 diag = Vec3::Zero();
  const double r = g.size[0];
  switch (g.type) {
    case GeomType::Plane: *mass = 0; *inertia = Mat3::Zero(); return;
    case GeomType::Sphere: volume = 4.0 / 3.0 * M_PI * r * r * r; break;
    case GeomType::Capsule: {
      const double h = 2 * g.size[1];
      volume = M_PI * r * r * h + 4.0 / 3.0 * M_PI * r * r * r;
      break;
    }
    case GeomType::Box: volume = 8 * g.size[0] * g.size[1] * g.size[2]; break;
    case GeomType::Mesh: {
      if (g.tessellates != Geom::Tessellated::None) {  // the exact shape, not its tessellation
        const Vec3& s = g.size;
        const bool cyl = g.tessellates == Geom::Tessellated::Cylinder;
        volume = cyl ? M_PI * s[0] * s[0] * 2 * s[1] : 4.0 / 3.0 * M_PI * s[0] * s[1] * s[2];
        const double m = g.mass >= 0 ? g.mass : g.density * volume;
        const double h = 2 * s[1];
        diag = cyl ? Vec3(m * (3 * s[0] * s[0] + h * h) / 12, m * (3 * s[0] * s[0] + h * h) / 12, m * s[0] * s[0] / 2)
                   : Vec3(s[1] * s[1] + s[2] * s[2], s[0] * s[0] + s[2] * s[2], s[0] * s[0] + s[1] * s[1]) * (m / 5);
        *mass = m;
        *inertia = diag.asDiagonal();
        return;
      }
      // Re-centred at load: the tetrahedra from the origin give volume and second
      // moment; inertia = tr(C) I - C per unit density. MuJoCo 2.2.2's rule (opt-in)
      // takes the mass from its equivalent inertia box instead (mesh_inertia.cpp).
      Mat3 c;
      double mass_volume;
      if (g.mesh_inertia == Geom::MeshInertia::MuJoCo222) {
        mesh_mujoco222_moments(*g.mesh, &mass_volume, &volume, nullptr, &c);
      } else {
        mesh_volume_moments(*g.mesh, &volume, nullptr, &c);
        mass_volume = volume;
      }
      const double m = g.mass >= 0 ? g.mass : g.density * mass_volume;
      *mass = m;
      *inertia = volume > 0 ? Mat3((m / volume) * (c.trace() * Mat3::Identity() - c)) : Mat3::Zero();
      return;
    }
  }
  const double m = g.mass >= 0 ? g.mass : g.density * volume;
  switch (g.type) {
    case GeomType::Sphere: diag.setConstant(0.4 * m * r * r); break;
    case GeomType::Capsule: {
      // Cylinder plus two hemispheres at +-(h/2 + 3r/8) (parallel axis theorem).
      const double h = 2 * g.size[1];
      const double vs = 4.0 / 3.0 * M_PI * r * r * r, vc = M_PI * r * r * h;
      const double ms = m * vs / (vs + vc), mc = m - ms;
      const double ixx = mc * (3 * r * r + h * h) / 12 + ms * (0.4 * r * r + h * h / 4 + 3 * h * r / 8);
      const double izz = mc * r * r / 2 + ms * 0.4 * r * r;
      diag = Vec3(ixx, ixx, izz);
      break;
    }
    case GeomType::Box: {
      const Vec3 s = 2 * g.size;
      diag = Vec3(s[1] * s[1] + s[2] * s[2], s[0] * s[0] + s[2] * s[2], s[0] * s[0] + s[1] * s[1]) *
             (m / 12);
      break;
    }
    case GeomType::Plane:
    case GeomType::Mesh: break;
  }
  *mass = m;
  *inertia = diag.asDiagonal();
}

void model_finalize(Model& m, const std::vector<bool>& has_inertial) {
  if (m.bodies.empty()) throw std::invalid_argument("model has no world body");
  for (Body& b : m.bodies) b.joints.clear();
  for (size_t j = 0; j < m.joints.size(); ++j) {
    const int b = m.joints[j].body;
    if (b <= 0 || b >= static_cast<int>(m.bodies.size()))
      throw std::invalid_argument("joint " + std::to_string(j) + " has no body");
    m.bodies[b].joints.push_back(static_cast<int>(j));
  }
  for (size_t b = 1; b < m.bodies.size(); ++b) {
    const int p = m.bodies[b].parent;
    if (p < 0 || p >= static_cast<int>(b))
      throw std::invalid_argument("body \"" + m.bodies[b].name + "\" must come after its parent");
  }
  // Addresses follow body order, then joint order within a body.
  m.nq = m.nv = 0;
  m.dof_body.clear();
  std::vector<Joint> ordered;
  std::vector<int> new_index(m.joints.size(), -1);
  for (size_t b = 1; b < m.bodies.size(); ++b) {
    Body& body = m.bodies[b];
    body.dof_begin = m.nv;
    std::vector<int> ids;
    for (int j : body.joints) {
      Joint jt = m.joints[j];
      if (jt.type == JointType::Free && (body.parent != 0 || body.joints.size() != 1))
        throw std::invalid_argument("free joint of body \"" + body.name +
                                    "\" must be the only joint of a child of the world");
      jt.qadr = m.nq;
      jt.vadr = m.nv;
      m.nq += joint_nq(jt.type);
      m.nv += joint_nv(jt.type);
      for (int d = 0; d < joint_nv(jt.type); ++d) m.dof_body.push_back(static_cast<int>(b));
      new_index[j] = static_cast<int>(ordered.size());
      ids.push_back(static_cast<int>(ordered.size()));
      ordered.push_back(jt);
    }
    body.joints = ids;
    body.dof_count = m.nv - body.dof_begin;
    // A rigid body has 6 degrees of freedom; more joint dofs would make the tree
    // solve's joint block singular (and it is specialised for at most 6).
    if (body.dof_count > 6)
      throw std::invalid_argument("body \"" + body.name + "\" has " + std::to_string(body.dof_count) +
                                  " joint degrees of freedom (at most 6)");
  }
  m.joints = ordered;
  for (Actuator& a : m.actuators) {
    if (a.joint < 0 || a.joint >= static_cast<int>(new_index.size()))
      throw std::invalid_argument("actuator \"" + a.name + "\" has no joint");
    a.joint = new_index[a.joint];
  }
  m.qpos0 = VecX::Zero(m.nq);
  for (const Joint& j : m.joints) {
    if (j.type == JointType::Ball) m.qpos0[j.qadr] = 1;
    if (j.type == JointType::Hinge || j.type == JointType::Slide) m.qpos0[j.qadr] = j.ref;
    if (j.type == JointType::Free) {
      m.qpos0.segment<3>(j.qadr) = m.bodies[j.body].pos;
      const Quat& q = m.bodies[j.body].quat;
      m.qpos0.segment<4>(j.qadr + 3) << q.w(), q.x(), q.y(), q.z();
    }
  }
  // Mass properties from geoms (in the body frame) where no inertial was given.
  for (size_t b = 1; b < m.bodies.size(); ++b) {
    if (b < has_inertial.size() && has_inertial[b]) continue;
    double mass = 0;
    Vec3 mc = Vec3::Zero();
    for (const Geom& g : m.geoms)
      if (g.body == static_cast<int>(b) && g.type != GeomType::Plane) {
        double gm;
        Mat3 gi;
        geom_mass_properties(g, &gm, &gi);
        mass += gm;
        mc += gm * g.pos;
      }
    Body& body = m.bodies[b];
    body.mass = mass;
    body.com = mass > 0 ? Vec3(mc / mass) : Vec3::Zero();
    body.inertia.setZero();
    for (const Geom& g : m.geoms)
      if (g.body == static_cast<int>(b) && g.type != GeomType::Plane) {
        double gm;
        Mat3 gi;
        geom_mass_properties(g, &gm, &gi);
        const Mat3 r = g.quat.toRotationMatrix();
        const Vec3 d = g.pos - body.com;
        body.inertia += r * gi * r.transpose() + gm * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
      }
  }
  for (size_t b = 1; b < m.bodies.size(); ++b)
    if (!(m.bodies[b].mass > 0) && m.bodies[b].dof_count > 0)
      throw std::invalid_argument("body \"" + m.bodies[b].name + "\" has joints but no mass");
}

namespace {
std::string no_such_name(const char* kind, const std::string& name, const std::vector<std::string>& names) {
  const std::string near = nearest_name(name, names);
  return std::string("no ") + kind + " named \"" + name + "\"" + (near.empty() ? "" : "; did you mean \"" + near + "\"?");
}
}  // namespace

int geom_named(const Model& m, const std::string& name, std::string* why) {
  int id = -1;
  std::vector<std::string> names;
  for (size_t g = 0; g < m.geoms.size(); ++g) {
    if (m.geoms[g].name.empty()) continue;
    names.push_back(m.geoms[g].name);
    if (m.geoms[g].name == name) id = static_cast<int>(g);
  }
  if (id < 0) *why = no_such_name("geom", name, names);
  return id;
}

int body_named(const Model& m, const std::string& name, std::string* why) {
  int id = -1;
  std::vector<std::string> names;
  for (size_t b = 1; b < m.bodies.size(); ++b) {
    names.push_back(m.bodies[b].name);
    if (m.bodies[b].name == name) id = static_cast<int>(b);
  }
  if (id < 0) *why = no_such_name("body", name, names);
  return id;
}

std::string contact_pair_problem(const Model& m, int g1, int g2) {
  const Geom &a = m.geoms[g1], &b = m.geoms[g2];
  if (g1 == g2) return "a geom cannot pair with itself";
  if (a.body == 0 || b.body == 0)
    return "pairs with world geoms are not supported (world geoms are obstacles: they touch every geom whose "
           "contype or conaffinity is nonzero)";
  if (a.body == b.body) return "both geoms belong to one body";
  if (a.type == GeomType::Plane || b.type == GeomType::Plane) return "planes on moving bodies take no part in contact";
  return "";
}

std::string contact_pair_condim_problem(double condim) {
  if (condim == 1 || condim == 3 || condim == 4 || condim == 6) return "";
  return "must be 1 (frictionless), 3 (sliding), 4 (+ torsional) or 6 (+ rolling friction)";
}

std::string chain_mjcf(int links, double link_length, double radius) {
  std::ostringstream s;
  s.precision(17);
  s << "<mujoco model=\"chain" << links << "\">\n"
    << "  <option timestep=\"0.01\" gravity=\"0 0 -9.81\"/>\n  <worldbody>\n";
  std::string indent = "    ";
  for (int i = 0; i < links; ++i) {
    s << indent << "<body name=\"link" << i << "\" pos=\"" << (i == 0 ? 0.0 : link_length)
      << " 0 0\">\n";
    s << indent << "  <joint name=\"j" << i << "y\" type=\"hinge\" axis=\"0 1 0\"/>\n";
    s << indent << "  <joint name=\"j" << i << "z\" type=\"hinge\" axis=\"0 0 1\"/>\n";
    s << indent << "  <geom type=\"capsule\" size=\"" << radius << "\" fromto=\"0 0 0 "
      << link_length << " 0 0\" density=\"1000\" contype=\"0\" conaffinity=\"0\"/>\n";
    indent += "  ";
  }
  for (int i = links - 1; i >= 0; --i) {
    indent.resize(indent.size() - 2);
    s << indent << "</body>\n";
  }
  s << "  </worldbody>\n</mujoco>\n";
  return s.str();
}

}  // namespace pliant::articulated
