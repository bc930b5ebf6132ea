// Articulated rigid bodies in generalized coordinates (MuJoCo conventions, so the
// same MJCF loads in both engines): a tree of bodies, each placed in its parent by
// pos/quat, then moved by its joints in order. Hinge and slide joints have one
// coordinate; ball joints a unit quaternion (nq 4, nv 3, velocity in the body's
// local frame); free joints position + quaternion (nq 7, nv 6: world linear
// velocity, local angular velocity). Body 0 is the world.
#pragma once
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>
#include <vector>

namespace pliant::articulated {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
using VecX = Eigen::VectorXd;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

enum class JointType { Hinge, Slide, Ball, Free };
int joint_nq(JointType t);
int joint_nv(JointType t);

struct Joint {
  std::string name;
  JointType type = JointType::Hinge;
  int body = 1;
  Vec3 axis{0, 0, 1};  // body frame, unit
  Vec3 pos{0, 0, 0};   // anchor, body frame
  int qadr = 0, vadr = 0;
  double damping = 0;   // N m s / rad (viscous, explicit integrators and PBAD alike)
  double armature = 0;  // added rotor inertia (diagonal of M)
  // Dry (Coulomb) joint friction, MuJoCo's frictionloss: a torque (N m) or force (N)
  // of at most this size per dof opposing the joint's motion, holding it at rest below
  // it. PBAD: the dissipation potential F |dq| per step (regularised); explicit
  // integrators: a per-step friction impulse (joint_friction.cpp).
  double frictionloss = 0;
  // Hinge / slide only. ref: the joint value at which the body has its model pose
  // (MuJoCo's qpos0; the joint turns or slides by q - ref). A spring
  // 1/2 stiffness (q - springref)^2 (N m/rad or N/m), in PBAD's energy and as a force
  // in the explicit integrators, as MuJoCo's passive joint spring.
  double ref = 0;
  double stiffness = 0, springref = 0;
  // Joint range (hinge rad, slide m): a one-sided penalty 1/2 k (q - bound)^2 outside
  // it (k = ContactOptions::limit_stiffness), in PBAD's energy and as a force in the
  // explicit integrators. Ball joints: range_min = 0, range_max bounds the total
  // rotation angle (MuJoCo's cone), penalty 1/2 k (angle - range_max)^2. Free joints
  // have no limits.
  bool limited = false;
  double range_min = 0, range_max = 0;
  // Ball joints only, a Pliant extension (scene "joint_limits"): swing cone (angle
  // between `axis` and its image <= swing_max; < 0: none) and twist range about
  // `axis`, each a penalty 1/2 k (excess)^2 with the same k.
  double swing_max = -1;
  bool twist_limited = false;
  double twist_min = 0, twist_max = 0;
};

enum class GeomType { Plane, Sphere, Capsule, Box, Mesh };

// Triangle mesh of a mesh geom, in the geom's frame (pos/quat of the Geom), re-centred
// at its centre of mass when loaded (the geom's pos moved to compensate, as MuJoCo
// does). Drawn as body pose * geom pose * vertex.
struct MeshShape {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

struct Geom {
  std::string name;
  GeomType type = GeomType::Sphere;
  int body = 0;  // 0: static obstacle in the world
  Vec3 pos{0, 0, 0};
  Quat quat = Quat::Identity();
  // sphere: radius; capsule: radius, half-length (along local z); box: half sizes;
  // plane: ignored (infinite, normal = local z).
  Vec3 size{0.05, 0, 0};
  double density = 1000;  // kg/m^3, used when mass < 0
  double mass = -1;       // explicit mass (MJCF "mass")
  bool contact = true;  // against obstacles (MJCF: contype or conaffinity nonzero)
  // Body-body contact (ContactOptions::self_collision) as MuJoCo's bitmask rule: two
  // geoms of different, non parent-child bodies touch when
  // (contype_a & conaffinity_b) || (contype_b & conaffinity_a).
  int contype = 1, conaffinity = 1;
  std::shared_ptr<const MeshShape> mesh;  // GeomType::Mesh only
  // MJCF cylinders and ellipsoids are Mesh geoms whose mesh tessellates the shape
  // (primitive_meshes.cpp) for contact; their mass and inertia are the exact shape's
  // from `size` (cylinder: radius, half-height; ellipsoid: the three radii), as MuJoCo's.
  enum class Tessellated { None, Cylinder, Ellipsoid } tessellates = Tessellated::None;
  // A tessellated geom against planes: the exact shape (support points,
  // contact_support.cpp; default) or the tessellation's samples
  // (MjcfOptions::curved_contact "tessellated").
  bool exact_plane_contact = true;
  // Mass properties of a mesh geom: the enclosed solid's (Exact), or what MuJoCo 2.2.2
  // compiles (mesh_mujoco222_moments; MjcfOptions::mesh_inertia).
  enum class MeshInertia { Exact, MuJoCo222 } mesh_inertia = MeshInertia::Exact;
  // Contact parameters (MJCF friction / margin / condim / priority), mixed per contact
  // by contact_mix (contact.h) as MuJoCo 2.2.2 mixes them for automatic contacts.
  // friction: the sliding (Coulomb) coefficient; < 0: unset, the scene's contact.mu
  // stands in for it (the scene's mu plays MuJoCo's default geom friction 1).
  double friction = -1;
  // Torsional (m: torque mu_t f_n about the normal) and rolling (m: torque mu_r f_n
  // about the tangents) coefficients, used by condim 4 / 6; MuJoCo's defaults.
  double torsion = 0.005, roll = 0.0001;
  double margin = 0;  // touching below this distance (depth = margin - distance)
  int condim = 3;     // 1 frictionless, 3 sliding, 4 + torsional, 6 + rolling friction
  int priority = 0;   // the higher-priority geom's friction and condim win
};

struct Body {
  std::string name;
  int parent = 0;
  Vec3 pos{0, 0, 0};          // in parent frame
  Quat quat = Quat::Identity();
  double mass = 0;
  Vec3 com{0, 0, 0};          // body frame
  Mat3 inertia = Mat3::Zero();  // about com, body frame
  std::vector<int> joints;    // in application order
  int dof_begin = 0, dof_count = 0;
};

// An explicit contact pair (MJCF <contact><pair geom1 geom2 [friction]>, scene
// "contact": {"pairs": [...]}): the two geoms always touch, whatever their
// contype/conaffinity, an exclude or a parent-child relation say, and whether or not
// ContactOptions::self_collision is on (as MuJoCo's <pair>). Geoms of two different
// moving bodies.
struct ContactPair {
  int geom1 = 0, geom2 = 0;
  double mu = -1;  // Coulomb coefficient of this pair; < 0: the scene's contact.mu
  double margin = 0;          // touching below this distance (penalty on margin - distance)
  bool frictionless = false;  // condim 1 (MuJoCo's default condim 3: sliding friction)
  int condim = 3;             // 1, 3, 4 (torsional), 6 (torsional and rolling)
  double torsion = 0.005, roll = 0.0001;  // MJCF pair friction's 3rd / 4th values
};
struct Actuator {
  std::string name;
  int joint = 0;
  double gear = 1;
  double ctrl_min = -1, ctrl_max = 1;
};

// The compiled, read-only model.
struct Model {
  std::string name;
  std::vector<Body> bodies;  // [0] is the world; parents come before children
  std::vector<Joint> joints;
  std::vector<Geom> geoms;
  std::vector<Actuator> actuators;
  int nq = 0, nv = 0;
  Vec3 gravity{0, 0, -9.81};
  double timestep = 0.01;   // MJCF <option timestep>, default for scenes
  VecX qpos0;               // reference configuration
  // MJCF attributes read and deliberately left without effect (MjcfOptions), as
  // "path/@attribute" pointers, for the job's warning.
  std::vector<std::string> ignored_attributes;
  std::vector<int> dof_body;  // body of each velocity dof
  // Body pairs that never touch each other (MJCF <contact><exclude body1 body2>,
  // JSON "exclude"), smaller index first.
  std::vector<std::array<int, 2>> contact_exclude;
  std::vector<ContactPair> contact_pairs;  // explicit pairs, always on
};

// Fills joint addresses, body dof ranges, dof_body and qpos0, and the mass
// properties of bodies without an explicit inertial from their geoms (MuJoCo's
// formulas: sphere, capsule = cylinder + two hemispheres, box). Throws
// std::invalid_argument on an inconsistent tree (callers turn it into InputError).
void model_finalize(Model& m, const std::vector<bool>& has_inertial);

// Why geoms g1 and g2 cannot form a ContactPair ("" if they can).
std::string contact_pair_problem(const Model& m, int g1, int g2);
// Why a condim is refused ("" for 1, 3, 4 and 6, MuJoCo's values; 2, 5 and others are
// refused as MuJoCo refuses them).
std::string contact_pair_condim_problem(double condim);
// Index of the named geom / moving body (the last of that name), or -1 with *why set
// to 'no geom named "x"; did you mean "y"?' (loaders turn it into an InputError).
int geom_named(const Model& m, const std::string& name, std::string* why);
int body_named(const Model& m, const std::string& name, std::string* why);

// Mass and inertia (about its centre, geom frame) of one geom.
void geom_mass_properties(const Geom& g, double* mass, Mat3* inertia);
// Volume, centre and second moment (integral p p^T) of a closed, outward-oriented
// triangle mesh (divergence theorem over tetrahedra from the origin).
void mesh_volume_moments(const MeshShape& mesh, double* volume, Vec3* centre, Mat3* second);
// MuJoCo 2.2.2's compiled mesh mass properties (its pre-3.0 rule; reproduced so MJCF
// models with mesh geoms compile to libmujoco 2.2.2's masses): tetrahedra from the
// area-weighted surface centroid counted with |volume| give the centre; tetrahedra
// from that centre, again unsigned, give *volume and the *second moment about it;
// the mass is density times *mass_volume, the volume of the box with the same
// principal moments per unit mass (8 a b c, a^2 = 3 (J2 + J3 - J1) / (2 volume)).
// Equal to mesh_volume_moments' for a box, larger for most other shapes (an L-shaped
// prism of volume 3: 3.4157 = sqrt(35/3); MuJoCo issue #1472 describes the change).
void mesh_mujoco222_moments(const MeshShape& mesh, double* mass_volume, double* volume, Vec3* centre, Mat3* second);

// A chain of `links` capsules along +x, each body with two hinges (about y then
// z: a 2-DOF ball joint) at its start; used by scenes, tests and the benchmark.
std::string chain_mjcf(int links, double link_length = 0.1, double radius = 0.01);

}  // namespace pliant::articulated
