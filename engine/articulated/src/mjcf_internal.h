// Internals shared by the MJCF reader's files: the reading context, the <default>
// class table and the readers each file defines (mjcf_attrs.cpp: attribute values;
// mjcf_defaults.cpp: <default> classes; mjcf_bodies.cpp: <body>/<geom>/<joint>;
// mjcf_meshes.cpp: <asset> meshes; mjcf_contact.cpp: <contact>; mjcf_global.cpp:
// global coordinates; mjcf.cpp: the document).
#pragma once
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "pliant/articulated/model.h"
#include "xml.h"

namespace pliant::articulated::mjcf_internal {

struct Ctx {
  explicit Ctx(const std::string& f) : file(f) {}
  const std::string& file;
  Model m;
  std::vector<bool> has_inertial{false};
  double angle_scale = M_PI / 180;  // compiler angle="degree"
  std::string eulerseq = "xyz";
  bool autolimits = false;  // MuJoCo 2.2.2's default
  bool inertia_from_geom = false;  // compiler inertiafromgeom="true": <inertial> ignored
  bool global = false;             // compiler coordinate="global" (mjcf_global.cpp)
  bool ignore_solver_params = false;  // MjcfOptions (io.h): record, not reject, geom/pair solref/solimp/solmix
  Geom::MeshInertia mesh_inertia = Geom::MeshInertia::Exact;  // MjcfOptions (io.h)
  bool exact_plane_contact = true;                            // MjcfOptions (io.h)
  std::filesystem::path mesh_dir;
  std::map<std::string, std::shared_ptr<const MeshShape>> meshes;  // <asset><mesh name=...>
};

// Replaces every <include file> below root by the included file's elements
// (mjcf_include.cpp); files relative to base_dir.
void expand_includes(Ctx& c, XmlElement& root, const std::filesystem::path& base_dir);

// <default> classes: class name -> element name -> attributes (inherited ones merged).
using Defaults = std::map<std::string, std::map<std::string, std::vector<std::pair<std::string, std::string>>>>;

// Attribute values (mjcf_attrs.cpp). Paths name the element: /mujoco/worldbody/body[0].
std::string child_path(const std::string& parent, const XmlElement& parent_el, size_t index);
// Throws on an attribute outside `allowed`; a geom's or pair's solver parameter is
// recorded in c.m.ignored_attributes instead when c.ignore_solver_params.
void check_attrs(Ctx& c, const XmlElement& e, const std::string& path, const std::set<std::string>& allowed);
std::vector<double> numbers(const Ctx& c, const XmlElement& e, const std::string& path,
                            const std::string& key, size_t min_n, size_t max_n);
Vec3 vec3(const Ctx& c, const XmlElement& e, const std::string& path, const std::string& key, Vec3 def);
double number(const Ctx& c, const XmlElement& e, const std::string& path, const std::string& key,
              double def, double min);
Quat quat_z_to(const Vec3& v);
Quat quat(const Ctx& c, const XmlElement& e, const std::string& path);

// <default> classes (mjcf_defaults.cpp).
void read_default(const Ctx& c, const XmlElement& e, const std::string& path, const std::string& parent,
                  bool top, Defaults* d);
void apply_defaults(const Ctx& c, XmlElement& e, const std::string& path, const Defaults& d,
                    const std::string& cls);

// coordinate="global": rewrites the worldbody's frames in local coordinates (mjcf_global.cpp).
void global_to_local(const Ctx& c, XmlElement& worldbody, const std::string& path);

// Elements (mjcf_bodies.cpp, mjcf_meshes.cpp, mjcf_contact.cpp).
void read_geom(Ctx& c, const XmlElement& e, const std::string& path, int body);
void read_body(Ctx& c, const XmlElement& e, const std::string& path, int parent);
void read_assets(Ctx& c, const XmlElement& e, const std::string& path, const std::filesystem::path& base_dir);
void read_contact(Ctx& c, const XmlElement& e, const std::string& path);

}  // namespace pliant::articulated::mjcf_internal
