// MJCF subset -> Model. Element paths in errors: /mujoco/worldbody/body[0]/geom[1],
// attributes as .../@size. Angles (euler, axisangle, hinge range) follow <compiler
// angle> (MuJoCo's default: degree) and eulerseq (default xyz; lower case = axes that
// move with the frame, upper case = fixed axes). <default> classes (nested, with
// class= and childclass=) are applied to joint/geom/motor elements before reading,
// as MuJoCo does: the element's own attributes override its class's.
#include <cmath>
#include <fstream>
#include <sstream>

#include "mjcf_internal.h"
#include "pliant/articulated/io.h"
#include "pliant/core/error.h"
#include "xml.h"

namespace pliant::articulated {

using namespace mjcf_internal;

Model model_from_mjcf(const std::string& text, const std::string& file, const std::filesystem::path& base_dir,
                      const MjcfOptions& options) {
  XmlElement root = parse_xml(text, file);
  if (root.name != "mujoco") throw InputError(file, "/" + root.name, "root element must be <mujoco>");
  Ctx c(file);
  c.ignore_solver_params = options.ignore_solver_params;
  c.mesh_inertia = options.mesh_inertia;
  c.exact_plane_contact = options.exact_plane_contact;
  expand_includes(c, root, base_dir);
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
      if (const auto* a = e.attr("coordinate")) {
        if (*a != "local" && *a != "global") throw InputError(file, p + "/@coordinate", "expected local or global");
        c.global = *a == "global";
      }
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
    if (e.name == "worldbody" && c.global) global_to_local(c, e, child_path("/mujoco", root, k));
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
      // Solver numerics (iterations, tolerances, the Jacobian's storage) do not change
      // the model: accepted without effect, as MuJoCo's own results barely depend on them.
      check_attrs(c, e, p, {"timestep", "gravity", "integrator", "iterations", "solver", "tolerance", "jacobian",
                            "mpr_iterations", "mpr_tolerance", "apirate"});
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
    } else if (e.name == "tendon" || e.name == "equality" ||
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

Model model_load_file(const std::filesystem::path& path, const std::string& label, const MjcfOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(label, "", "cannot read model file " + path.string());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  if (path.extension() == ".xml") return model_from_mjcf(text, label, path.parent_path(), options);
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
