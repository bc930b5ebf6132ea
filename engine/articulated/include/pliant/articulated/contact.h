// Contact: penalty normal force on the penetration depth of body points (sphere
// centres with radius, capsule end spheres, box corners, mesh vertices and edge/face
// samples) against static obstacles
// (planes, spheres, boxes of the world body); every point is tested against every
// obstacle, so the cost is linear in the number of contacts.
// Normal: E = k/2 d^2 (d = penetration), force k d along the obstacle normal.
// Friction (inside PBAD's energy, with the normal force f_n of the previous step):
//   coulomb: dry Coulomb as a dissipation potential mu f_n (sqrt(|s_t|^2+eps^2)-eps),
//            s_t the tangential slip of the point over the step;
//   ck:      the dissertation's tangential model read as a viscous law scaled by the
//            normal force, force -C_k f_n v_t (energy C_k f_n |s_t|^2 / (2 dt));
//   none.
// Explicit integrators use the same laws on velocities (coulomb regularised with
// slip speed eps/dt).
// condim 4 / 6 (coulomb model only): torsional / rolling friction on the relative
// rotation of the two bodies over the step (spin_friction, pbad_energy.cpp).
#pragma once
#include <algorithm>
#include <array>
#include <memory>
#include <utility>
#include <vector>

#include "pliant/articulated/dynamics.h"

namespace pliant::articulated {

enum class FrictionModel { None, Coulomb, Ck };

struct ContactOptions {
  bool enabled = true;
  double stiffness = 1e5;        // N/m
  double damping = 0;            // N s/m (explicit integrators only)
  FrictionModel friction = FrictionModel::Coulomb;
  double mu = 0.5;
  double ck = 10;                // s/m
  double slip_eps = 1e-7;        // m per step
  double spin_eps = 1e-7;        // rad per step (torsional / rolling friction, condim 4 / 6)
  double limit_stiffness = 1e3;  // N m/rad (hinge) or N/m (slide) beyond a joint's range
  // Body-body contact (find_pair_contacts). Off by default: scenes written before it
  // keep their trajectories; MuJoCo would collide every pair its filter allows.
  bool self_collision = false;
};

// A contact's parameters from its two geoms (contact_mix) or an explicit pair.
struct ContactMix {
  double mu = -1;         // Coulomb coefficient; see contact_mu
  bool scene_mu = true;   // the scene's contact.mu takes part (a geom without friction)
  double margin = 0;      // touching below this distance: depth = margin - distance
  bool frictionless = false;  // condim 1: no friction whatever the model
  // condim 4: torsional friction (torque <= torsion f_n about the normal), 6: also
  // rolling (<= roll f_n about the tangents); coefficients in m (spin_friction).
  int condim = 3;
  double torsion = 0, roll = 0;
};
// MuJoCo 2.2.2's rule for automatic (non-pair) contacts (mj_contactParam): the geom
// of higher priority gives friction and condim; equal priorities take the larger of
// each (condim, sliding friction); the margin is always the larger. A geom without
// friction counts with the scene's contact.mu (contact_mu resolves it), so with no
// geom friction anywhere every contact keeps the scene's coefficient exactly. World
// geoms (obstacles, the floor) count as any geom.
// Inline: PBAD's energy calls it for every point x obstacle at every evaluation.
inline ContactMix contact_mix(const Geom& a, const Geom& b) {
  ContactMix c;
  c.margin = std::max(a.margin, b.margin);
  int condim;
  if (a.priority != b.priority) {
    const Geom& w = a.priority > b.priority ? a : b;
    condim = w.condim;
    c.mu = w.friction;
    c.scene_mu = w.friction < 0;
    c.torsion = w.torsion;
    c.roll = w.roll;
  } else {
    condim = std::max(a.condim, b.condim);
    c.mu = std::max(a.friction, b.friction);  // unset (< 0) loses to any set value
    c.scene_mu = a.friction < 0 || b.friction < 0;
    c.torsion = std::max(a.torsion, b.torsion);
    c.roll = std::max(a.roll, b.roll);
  }
  c.frictionless = condim == 1;
  c.condim = condim;
  return c;
}
// The Coulomb coefficient of a contact for the scene's contact.mu. Used by the
// Coulomb model only: C_k (s/m, a viscous coefficient) has no Coulomb coefficient to
// scale, so geom friction leaves it alone; condim 1 (frictionless) applies to both.
inline double contact_mu(const ContactMix& c, double scene_mu) {
  return c.scene_mu ? std::max(c.mu, scene_mu) : c.mu;
}

// Which obstacles a body point meets. Cylinders and ellipsoids (Geom::tessellates with
// Geom::exact_plane_contact) meet planes at their exact surface, through points of
// role Plane (contact_support.cpp), and every other obstacle through their
// tessellation's samples (role NotPlanes).
enum class PointRole : unsigned char { All, NotPlanes, Plane };
// A Plane point's place on its geom: fixed (cp.local), or a support point, the
// deepest point of the shape along the plane's normal, recomputed at every pose: the
// ellipsoid's, or the rim of the cylinder's -z / +z end cap.
enum class PointSupport : unsigned char { Fixed, Ellipsoid, RimLow, RimHigh };

// A contact candidate: one body point, one obstacle.
struct ContactPoint {
  int body;
  Vec3 local;      // in body frame (a support point: unused, see contact_point_local)
  double radius;
  int geom = -1;   // the geom it belongs to (contact_mix with the obstacle)
  double geom_radius = -1;  // that geom's bounding radius (ObstacleCull; < 0: unknown, not culled)
  PointRole role = PointRole::All;
  PointSupport support = PointSupport::Fixed;
  int plane = -1;  // role Plane: the plane obstacle's geom index
};
// Whether point p is tested against obstacle geom `obstacle`.
inline bool point_meets(const Model& m, const ContactPoint& p, int obstacle) {
  switch (p.role) {
    case PointRole::All: return true;
    case PointRole::NotPlanes: return m.geoms[obstacle].type != GeomType::Plane;
    case PointRole::Plane: return obstacle == p.plane;
  }
  return true;
}
// Point p's body-frame position with its body at world rotation `rot`: p.local, or a
// support point's place for this pose (contact_support.cpp). With `curvature`, also the
// world-frame Hessian H of the shape's support function h(u) = max_y u . y at u = -n (n:
// the plane's normal; zero for fixed points): the support point's distance to the plane
// then has the rotational Hessian of a fixed point there plus [n] H [n] (envelope
// theorem; pbad_energy.cpp adds it to the exact Hessian).
Vec3 support_point_local(const Model& m, const ContactPoint& p, const Mat3& rot, Mat3* curvature);
inline Vec3 contact_point_local(const Model& m, const ContactPoint& p, const Mat3& rot, Mat3* curvature = nullptr) {
  if (p.support == PointSupport::Fixed) {
    if (curvature) curvature->setZero();
    return p.local;
  }
  return support_point_local(m, p, rot, curvature);
}
// Cylinders' fixed plane points: kCapRingPoints on a ring of kCapRingRadius x the
// radius inside each cap, so an upright cylinder stands on its face; inside the rim,
// they never touch a plane the cylinder rolls on (its rims' support points carry that).
constexpr int kCapRingPoints = 8;
constexpr double kCapRingRadius = 0.9;

struct Contact {
  int slot;        // point * nobstacles + obstacle
  int body;
  Vec3 point;      // deepest point on the body surface (grown by the margin), world
  Vec3 normal;     // out of the obstacle
  double depth;    // penetration > 0 (margin - distance)
  Vec3 force{0, 0, 0};
  ContactMix mix;  // of the body's geom and the obstacle
};

std::vector<ContactPoint> contact_points(const Model& m);
// Whether any geom sets friction, margin, condim or priority; if none does, every
// contact_mix is ContactMix{} and the point x obstacle loops skip it (it cost 7% of a
// step against cheap sphere obstacles, bench --case mesh_features).
bool geom_contact_params_set(const Model& m);
// contact_mix of point p's geom and obstacle geom `obstacle` (defaults without a geom).
inline ContactMix point_contact_mix(const Model& m, const ContactPoint& p, int obstacle) {
  return p.geom < 0 ? ContactMix{} : contact_mix(m.geoms[p.geom], m.geoms[obstacle]);
}
// A moving mesh's contact points (geom frame): its vertices, plus points along its
// edges and inside its faces at a spacing of 1/kMeshSamplesPerExtent of the mesh's
// largest bounding-box extent (none where the mesh is already that fine), so that
// obstacle edges cannot pass between the vertices of large faces (corners and
// spheres are caught exactly by mesh_feature_contacts).
constexpr double kMeshSamplesPerExtent = 6;
std::vector<Vec3> mesh_contact_samples(const MeshShape& mesh);
std::vector<int> contact_obstacles(const Model& m);
struct MeshBvh;
// Signed distance (positive outside) of a world point from obstacle geom g, and
// its outward normal. A mesh obstacle is queried through `tree` (its MeshBvh from
// obstacle_trees: O(log triangles), sign from the nearest feature's pseudo-normal);
// with tree null, by the brute-force scan with the face-normal sign (the reference the
// tree is tested against).
double obstacle_distance(const Geom& g, const MeshBvh* tree, const Vec3& x, Vec3* normal);
inline double obstacle_distance(const Geom& g, const Vec3& x, Vec3* normal) {
  return obstacle_distance(g, nullptr, x, normal);
}

// Signed distance (positive outside) of point p (mesh frame) to a closed mesh: the
// nearest triangle gives the distance, its face normal the sign (exact on faces, an
// approximation near edges and vertices: the reference for the tree below, used by
// the queries given no tree). O(triangles) per query (mesh_distance.cpp).
double mesh_signed_distance(const MeshShape& mesh, const Vec3& p, Vec3* normal);
// A bounding-volume tree over a mesh's triangles (median splits on the centroids'
// widest axis, leaves of <= 4 triangles), built once per model.
struct MeshBvh {
  struct Node {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // the node's triangles' bounding box
    int first = 0, count = 0;  // leaf: order[first, first + count); inner: count 0
    int right = 0;            // inner: right child (the left child is the next node)
  };
  std::vector<Node> nodes;  // [0]: the root
  std::vector<int> order;   // triangle indices, by leaf
  // Angle-weighted pseudo-normals (unnormalised) of each vertex, and of each
  // triangle's edges (ab, bc, ca): the sign test near edges and vertices.
  std::vector<Vec3> vertex_normal;
  std::vector<std::array<Vec3, 3>> edge_normal;
  // Per vertex, the lowest-index triangle using it (-1: none): visits each vertex
  // once when a query walks the leaves (mesh_feature_contacts).
  std::vector<int> vertex_owner;
};
MeshBvh mesh_bvh(const MeshShape& mesh);
// The same query through the tree: O(log triangles) near the surface, the same
// nearest triangle and distance to the bit (ties to the lower index, same arithmetic),
// and the sign from the nearest feature's pseudo-normal (Baerentzen and Aanaes 2005:
// right at every edge and vertex of a closed, consistently oriented mesh; the face
// normal above fails near convex edges sharper than 90 degrees and at some vertices;
// the same as the face normal's for boxes).
double mesh_signed_distance(const MeshShape& mesh, const MeshBvh& bvh, const Vec3& p, Vec3* normal);

// Each obstacle's tree (obstacles as contact_obstacles lists them): a mesh obstacle's
// MeshBvh, empty for the other types. Built once per model (sim_prepare).
std::vector<MeshBvh> obstacle_trees(const Model& m, const std::vector<int>& obs);

// A geom's contact points lie, with their radii, inside its bounding sphere, and a
// primitive obstacle's distance is 1-Lipschitz: when the sphere's centre is farther
// than its radius + margin from an obstacle, none of the geom's points touches it.
// find_contacts and the PBAD energy skip those point-obstacle tests (the same
// contacts; mesh obstacles are always tested). update() per point, in
// contact_points' order (grouped by geom): work only when the geom changes.
class ObstacleCull {
 public:
  void update(const Model& m, const Kinematics& k, const ContactPoint& cp, const std::vector<int>& obs, bool mixed);
  bool skip(int obstacle) const { return active_ && culled_[obstacle]; }
  bool skip_all() const { return active_ && all_; }  // every obstacle out of reach

 private:
  static constexpr size_t kMax = 64;  // more obstacles: no culling
  int geom_ = -2;
  bool active_ = false, all_ = false;
  bool culled_[kMax] = {};
};


// Active contacts at kinematics k: body points against obstacles (mesh obstacles
// through trees[o], the scan where trees is shorter), then (appended, slot -1)
// obstacle features against moving meshes (mesh_feature_contacts).
// mesh_trees: per geom, a moving mesh's tree (moving_mesh_trees) for the reverse query.
void find_contacts(const Model& m, const Kinematics& k, const std::vector<ContactPoint>& pts,
                   const std::vector<int>& obs, const std::vector<MeshBvh>& trees,
                   const std::vector<MeshBvh>& mesh_trees, std::vector<Contact>* out);
// The reverse query for moving meshes, exact where sampling is not: every corner of a
// static box, every static sphere (centre, radius) and every vertex of a static mesh
// (a spike's tip) against every moving mesh geom. The moving mesh is queried through
// mesh_trees[geom] (moving_mesh_trees: culled by the root box, sign from the nearest
// feature's pseudo-normal); where mesh_trees is shorter or the tree empty, by the
// brute-force scan with the face-normal sign (the reference). The contact acts on the
// mesh's body at the corner (the deepest point of the sphere), normal = the direction
// the body is pushed (minus the mesh's outward normal), so the penalty k/2 depth^2 has
// the same gradient form as a body point's. PBAD: Gauss-Newton Hessian, friction on the
// slip of the mesh's material point under the obstacle point at q_i (sim.cpp). Appends.
// A static mesh's vertices are found by walking its tree (obstacle_trees[o]) with the
// moving mesh's bounding sphere, else all of them are tested.
void mesh_feature_contacts(const Model& m, const Kinematics& k, const std::vector<int>& obs,
                           const std::vector<MeshBvh>& obstacle_trees, const std::vector<MeshBvh>& mesh_trees,
                           std::vector<Contact>* out);
// Per geom: a moving (body != 0) contact mesh geom's MeshBvh, empty for the others.
// Built once per model (sim_prepare, SimWorkspace::mesh_trees).
std::vector<MeshBvh> moving_mesh_trees(const Model& m);

// ---- Body-body contact (ContactOptions::self_collision, Model::contact_pairs) ----
// Candidate geom pairs, found once per model: sphere, capsule, box and mesh geoms of
// two different moving bodies that are not parent and child, not excluded
// (Model::contact_exclude) and pass MuJoCo's contype/conaffinity bitmask rule, then
// the model's explicit pairs (Model::contact_pairs), which skip every filter and
// replace a filtered duplicate. Each call culls a pair by bounding spheres (reach =
// sum of the radii + margin); with a PairBroadphase only the filtered pairs whose
// spheres' intervals overlap on one axis get that test (22 humanoids: 88k pairs).
// A moving mesh geom's collision data, built once per model, shared by its pairs.
struct MeshCollider {
  std::vector<Vec3> samples;  // mesh_contact_samples (geom frame)
  MeshBvh bvh;                // for mesh_signed_distance
};
struct GeomPair {
  int a, b;      // geom indices (a < b for filtered pairs; explicit: as written)
  double reach;  // bounding radius of a + of b (about each geom's centre) + margin
  bool explicit_pair = false;  // from Model::contact_pairs: on without self_collision
  // A moving capsule (a) and a static box obstacle (b, a world geom): the box's edges
  // and the segment's deepest point only (its end spheres meet the box on the obstacle
  // path); on without self_collision.
  bool world_sides = false;
  // Friction, margin, condim: contact_mix of the two geoms, or an explicit pair's own
  // (its mu, else the scene's; its margin; its condim).
  ContactMix mix;
  // Geom a's / b's collision data where it is a mesh.
  std::shared_ptr<const MeshCollider> mesh_a, mesh_b;
};
std::vector<GeomPair> contact_geom_pairs(const Model& m);
double geom_bounding_radius(const Geom& g);
// Whether a moving capsule and a static box obstacle (both in contact) exist: their
// sides meet through the pair path (GeomPair::world_sides).
inline bool capsule_box_obstacles(const Model& m) {
  bool cap = false, box = false;
  for (const Geom& g : m.geoms) {
    cap = cap || (g.body != 0 && g.contact && g.type == GeomType::Capsule);
    box = box || (g.body == 0 && g.contact && g.type == GeomType::Box);
  }
  return cap && box;
}
// Whether body-body contact runs at all: on with self_collision, for explicit pairs, or
// for capsule sides against static boxes.
inline bool pair_contact_on(const Model& m, const ContactOptions& c) {
  return c.enabled && (c.self_collision || !m.contact_pairs.empty() || capsule_box_obstacles(m));
}

// A body-body contact: penalty k/2 depth^2, force k depth normal on body_b at point,
// the opposite on body_a. Pair types: sphere-sphere, sphere-capsule (exact, sphere
// centre against the other's signed distance), capsule-capsule (the segments' closest
// points when interior to both, plus every end sphere against the other capsule but the
// deepest: side by side, the overlap's two ends; energy continuous, contact_pair_primitives.cpp),
// sphere-box (exact), capsule-box (the capsule's end spheres against the
// box, the box's corners against the capsule, and the segment's point deepest in /
// nearest the box in place of the deepest of those where it lies between the ends and
// off the corners: a capsule across an edge or under a face; energy continuous), box-box (each box's corners against
// the other box, plus each box's edges whose deepest point in the other lies between
// their corners: an edge pressed into a face, two edges crossing), mesh-sphere (the sphere's centre against the
// mesh's signed distance), mesh-capsule and mesh-box (the mesh's contact samples
// against the capsule / box, and the capsule's end spheres / the box's corners against
// the mesh; as the obstacle path does), mesh-mesh (each mesh's samples against the
// other's signed distance, both ways). A pair's margin m adds m to every depth
// (penalty on m - distance).
struct PairContact {
  int body_a, body_b;
  Vec3 point;   // world: the deepest point of b's surface (a point of both bodies' lines of action)
  Vec3 normal;  // unit, pushes body_b away from body_a
  double depth; // > 0
  ContactMix mix{};  // the pair's (GeomPair::mix)
  // The depth's gradient is gain x normal (force k depth gain along normal): != 1 where
  // the point sits where two faces' depths meet (a segment's deepest point in a box, a
  // vertex of a box edge's depth profile: the faces' normals mixed,
  // contact_segment_box.cpp); 1 elsewhere.
  double gain = 1;
};
// Active contacts of the pairs at kinematics k (out is cleared; no allocation once
// its capacity suffices). self_collision false: explicit pairs only. Depth = the
// pair's margin minus the distance.
// Sweep and prune for the filtered pairs (pairs[0, filtered), grouped by geom a with
// b ascending, as contact_geom_pairs lists them): per call, each geom's bounding
// interval on the axis along which the geoms' centres spread most, sorted; only pairs
// whose intervals overlap are tested, in list order, so the contacts found and their
// order are exactly the brute-force scan's. Built once per model (pair_broadphase);
// the rest is per-call scratch (no allocation once sized).
struct PairBroadphase {
  int filtered = 0;
  std::vector<int> geoms;      // geoms of the filtered pairs
  std::vector<double> radius;  // per entry of geoms: bounding radius + the largest filtered margin
  std::vector<int> first;      // per model geom + 1: its pairs as a, [first[g], first[g + 1])
  std::vector<Vec3> centre;
  std::vector<std::pair<double, int>> lo;  // interval start, entry
  std::vector<double> hi;
  std::vector<int> candidates;
};
PairBroadphase pair_broadphase(const Model& m, const std::vector<GeomPair>& pairs);

void find_pair_contacts(const Model& m, const Kinematics& k, const std::vector<GeomPair>& pairs,
                        std::vector<PairContact>* out, bool self_collision = true,
                        PairBroadphase* broadphase = nullptr);

}  // namespace pliant::articulated
