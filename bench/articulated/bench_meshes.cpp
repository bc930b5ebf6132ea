// Mesh cases: mesh-mesh stack, a static heightfield terrain, static box corners and spheres on moving meshes; tree vs scan queries.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "bench_common.h"

namespace art_bench {
namespace {

// One contact evaluation's nearest-triangle queries (points in the mesh's frame)
// through the tree and by the brute-force scan: seconds per evaluation, fastest of
// 3 x 20; `sink` sums the distances so neither loop is optimised away.
struct MeshQuery {
  const MeshShape* mesh;
  const MeshBvh* bvh;
  Vec3 p;
};
void time_tree_vs_scan(const std::vector<MeshQuery>& queries, double* tree, double* scan, double* sink) {
  *tree = *scan = 1e300;
  for (int rep = 0; rep < 3; ++rep) {
    Vec3 n;
    double t0 = thread_cpu_s();
    for (int r = 0; r < 20; ++r)
      for (const MeshQuery& q : queries) *sink += mesh_signed_distance(*q.mesh, *q.bvh, q.p, &n);
    *tree = std::min(*tree, (thread_cpu_s() - t0) / 20);
    t0 = thread_cpu_s();
    for (int r = 0; r < 20; ++r)
      for (const MeshQuery& q : queries) *sink += mesh_signed_distance(*q.mesh, q.p, &n);
    *scan = std::min(*scan, (thread_cpu_s() - t0) / 20);
  }
}

}  // namespace

// Mesh-mesh contact (assets/scenes/articulated_mesh_stack.json: three 320-triangle
// pebbles dropped on a fixed 192-triangle slab and on each other, pbad3, dt 0.01, 2 s):
// cost per step, LM iterations, contacts; then, at the final state, the nearest-
// triangle queries of one contact evaluation (samples inside the other mesh's box)
// timed through the tree and by the brute-force scan. Thread CPU time, fastest of 3.
void mesh_mesh_case(bool quick) {
  const std::string path = std::string(PLIANT_RESULTS_DIR) + "/../../assets/scenes/articulated_mesh_stack.json";
  const ArticulatedScene a = articulated_compile(pliant::load_scene(path));
  const TimedRollout t = timed_rollout(a.model, a.options, a.initial, a.steps, quick ? 1 : 3);
  const double best = t.cpu_s, iterations = t.iterations, max_iterations = t.max_iterations;
  const double contacts = t.pair_contacts, max_depth = t.max_pair_depth;
  const State& s = t.final;
  // The final state's queries: each mesh's samples inside the other's bounding box.
  Kinematics k;
  kinematics(a.model, s.qpos, &k);
  std::vector<MeshQuery> queries;
  const std::vector<GeomPair> pairs = contact_geom_pairs(a.model);
  for (const GeomPair& pr : pairs) {
    if (!pr.mesh_a || !pr.mesh_b) continue;
    for (int side = 0; side < 2; ++side) {
      const Geom& gs = a.model.geoms[side ? pr.b : pr.a];
      const Geom& gm = a.model.geoms[side ? pr.a : pr.b];
      const MeshCollider& from = side ? *pr.mesh_b : *pr.mesh_a;
      const MeshCollider& to = side ? *pr.mesh_a : *pr.mesh_b;
      const Mat3 rs = k.xmat[gs.body] * gs.quat.toRotationMatrix(), rm = k.xmat[gm.body] * gm.quat.toRotationMatrix();
      const Vec3 cs = k.xpos[gs.body] + k.xmat[gs.body] * gs.pos, cm = k.xpos[gm.body] + k.xmat[gm.body] * gm.pos;
      for (const Vec3& v : from.samples) {
        const Vec3 p = rm.transpose() * (cs + rs * v - cm);
        if (((to.bvh.nodes[0].lo - p).cwiseMax(p - to.bvh.nodes[0].hi).array() < 0).all())
          queries.push_back({gm.mesh.get(), &to.bvh, p});
      }
    }
  }
  double tree, scan, sink = 0;
  time_tree_vs_scan(queries, &tree, &scan, &sink);
  emit({{"case", "mesh_mesh"}, {"method", "pbad3"}, {"dt", a.options.dt}, {"bodies", a.model.bodies.size() - 1},
        {"steps", a.steps}, {"us_per_step", 1e6 * best / a.steps}, {"lm_iterations", iterations / a.steps},
        {"lm_iterations_max", max_iterations}, {"pair_contacts_per_step", contacts / a.steps},
        {"max_pair_depth_m", max_depth}, {"final_queries_per_evaluation", queries.size()},
        {"final_xyz_m", std::vector<double>{s.qpos[0], s.qpos[1], s.qpos[2], s.qpos[7], s.qpos[8], s.qpos[9], s.qpos[14], s.qpos[15], s.qpos[16]}},  // the pebbles' centres
        {"query_us_tree", 1e6 * tree}, {"query_us_scan", 1e6 * scan}, {"checksum", sink},
        {"load_average", load_average()},
        {"timing", "thread CPU time, fastest of 3 runs (1 in --quick); queries: one evaluation's, fastest of 3 x 20"}});
}

namespace {

// Static mesh obstacle (robotics environments load as static meshes): a closed
// heightfield block, n x n cells over 1 m x 1 m (top 2n^2 triangles, flat bottom
// 2n^2, sides 8n: 6720 triangles at n 40), written to a temporary OBJ, with three
// boxes, two balls and a capsule dropped on it; pbad3, dt 0.01, 1 s, Coulomb mu 0.6.
// Cost per step and LM iterations; then, at the final state, every contact point's
// distance to the terrain timed through the tree and by the scan. Thread CPU time,
// fastest of 3 (1 in --quick).
double terrain_height(double x, double y) { return 0.02 * std::sin(6 * x) * std::cos(5 * y); }

std::string write_terrain_obj(int n) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("pliant_bench_terrain_" + std::to_string(::getpid()) + ".obj")).string();
  std::ofstream out(path);
  const auto at = [n](int i) { return -0.5 + double(i) / n; };
  // Vertices: top grid (n+1)^2, then bottom grid (n+1)^2 at z = -0.2 (1-based ids).
  for (int layer = 0; layer < 2; ++layer)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        out << "v " << at(i) << " " << at(j) << " " << (layer ? -0.2 : terrain_height(at(i), at(j))) << "\n";
  const auto id = [n](int layer, int i, int j) { return 1 + layer * (n + 1) * (n + 1) + j * (n + 1) + i; };
  const auto quad = [&](int a, int b, int c, int d) {  // counter-clockwise from outside
    out << "f " << a << " " << b << " " << c << "\nf " << a << " " << c << " " << d << "\n";
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      quad(id(0, i, j), id(0, i + 1, j), id(0, i + 1, j + 1), id(0, i, j + 1));  // top, normal +z
      quad(id(1, i, j), id(1, i, j + 1), id(1, i + 1, j + 1), id(1, i + 1, j));  // bottom, -z
    }
  for (int i = 0; i < n; ++i) {
    quad(id(1, i, 0), id(1, i + 1, 0), id(0, i + 1, 0), id(0, i, 0));          // y = -0.5
    quad(id(1, i + 1, n), id(1, i, n), id(0, i, n), id(0, i + 1, n));          // y = +0.5
    quad(id(1, 0, i + 1), id(1, 0, i), id(0, 0, i), id(0, 0, i + 1));          // x = -0.5
    quad(id(1, n, i), id(1, n, i + 1), id(0, n, i + 1), id(0, n, i));          // x = +0.5
  }
  return path;
}

}  // namespace

void mesh_terrain_case(bool quick) {
  const int n = 40;
  const std::string obj = write_terrain_obj(n);
  std::string bodies;
  const double xy[6][2] = {{-0.25, -0.2}, {0.05, -0.25}, {0.3, 0.1}, {-0.2, 0.25}, {0.1, 0.2}, {-0.05, 0.0}};
  for (int b = 0; b < 6; ++b) {
    const double x = xy[b][0], y = xy[b][1], z = terrain_height(x, y) + 0.07;
    const std::string geom = b < 3 ? "<geom type=\"box\" size=\"0.04 0.03 0.025\" mass=\"0.5\"/>"
                             : b < 5 ? "<geom type=\"sphere\" size=\"0.03\" mass=\"0.3\"/>"
                                     : "<geom type=\"capsule\" size=\"0.02 0.06\" euler=\"0 90 20\" mass=\"0.3\"/>";
    bodies += "<body pos=\"" + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\"><freejoint/>" +
              geom + "</body>";
  }
  const Model m = model_from_mjcf("<mujoco><asset><mesh name=\"terrain\" file=\"" + obj +
                                      "\"/></asset><worldbody><geom type=\"mesh\" mesh=\"terrain\"/>" + bodies +
                                      "</worldbody></mujoco>",
                                  "terrain.xml");
  std::filesystem::remove(obj);
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.mu = 0.6;
  const int steps = 100;
  const TimedRollout t = timed_rollout(m, o, state_init(m), steps, quick ? 1 : 3);
  const double best = t.cpu_s, iterations = t.iterations, contacts = t.contacts;
  const State& s = t.final;
  // One energy evaluation's distance queries at the final state: every contact point
  // against the terrain (mesh frame = world here), tree and scan.
  Kinematics k;
  kinematics(m, s.qpos, &k);
  const MeshShape& mesh = *m.geoms[0].mesh;
  const MeshBvh bvh = mesh_bvh(mesh);
  std::vector<MeshQuery> queries;
  for (const ContactPoint& cp : contact_points(m))
    queries.push_back({&mesh, &bvh, k.xpos[cp.body] + k.xmat[cp.body] * cp.local});
  double tree, scan, sink = 0;
  time_tree_vs_scan(queries, &tree, &scan, &sink);
  std::vector<double> z;
  for (int b = 0; b < 6; ++b) z.push_back(s.qpos[7 * b + 2]);
  emit({{"case", "mesh_terrain"}, {"method", "pbad3"}, {"dt", o.dt}, {"triangles", mesh.triangles.size()},
        {"bodies", m.bodies.size() - 1}, {"steps", steps}, {"us_per_step", 1e6 * best / steps},
        {"lm_iterations", iterations / steps}, {"contacts_per_step", contacts / steps}, {"final_z_m", z},
        {"queries_per_evaluation", queries.size()}, {"query_us_tree", 1e6 * tree}, {"query_us_scan", 1e6 * scan},
        {"checksum", sink}, {"load_average", load_average()},
        {"timing", "thread CPU time, fastest of 3 runs (1 in --quick); queries: one evaluation's, fastest of 3 x 20"}});
}

// Static box corners and spheres against moving meshes (mesh_feature_contacts): two
// 320-triangle pebbles (assets/models/pebble.obj), one dropped on a tripod of three
// 1 cm static spheres, one on a static box standing on its corner, a plane below;
// pbad3, dt 0.01, 1 s, Coulomb mu 0.8. Cost per step, LM iterations, contacts, final
// centres. Thread CPU time, fastest of 3 (1 in --quick).
void mesh_features_case(bool quick) {
  const std::string obj = std::string(PLIANT_RESULTS_DIR) + "/../../assets/models/pebble.obj";
  const std::string xml =
      "<mujoco><asset><mesh name=\"pebble\" file=\"" + obj + "\"/></asset><worldbody>"
      "<geom type=\"plane\" pos=\"0 0 -0.2\" size=\"1 1 0.1\"/>"
      "<geom type=\"sphere\" size=\"0.01\" pos=\"0.02 0 0\"/>"
      "<geom type=\"sphere\" size=\"0.01\" pos=\"-0.01 0.0173 0\"/>"
      "<geom type=\"sphere\" size=\"0.01\" pos=\"-0.01 -0.0173 0\"/>"
      "<geom type=\"box\" size=\"0.04 0.04 0.04\" pos=\"0.5 0 0\" quat=\"0.8880738 0.3250576 -0.3250576 0\"/>"
      "<body pos=\"0.003 0.002 0.04\"><freejoint/><geom type=\"mesh\" mesh=\"pebble\" mass=\"0.1\"/></body>"
      "<body pos=\"0.5 0.004 0.1\"><freejoint/><geom type=\"mesh\" mesh=\"pebble\" mass=\"0.1\"/></body>"
      "</worldbody></mujoco>";
  const Model m = model_from_mjcf(xml, "mesh_features.xml");
  SimOptions o;
  o.integrator = Integrator::Pbad3;
  o.dt = 0.01;
  o.contact.mu = 0.8;
  const int steps = 100;
  const TimedRollout t = timed_rollout(m, o, state_init(m), steps, quick ? 1 : 3);
  const State& s = t.final;
  emit({{"case", "mesh_features"}, {"method", "pbad3"}, {"dt", o.dt}, {"triangles_per_mesh", m.geoms.back().mesh->triangles.size()},
        {"bodies", m.bodies.size() - 1}, {"steps", steps}, {"us_per_step", 1e6 * t.cpu_s / steps},
        {"lm_iterations", t.iterations / steps}, {"contacts_per_step", t.contacts / steps},
        {"final_xyz_m", std::vector<double>{s.qpos[0], s.qpos[1], s.qpos[2], s.qpos[7], s.qpos[8], s.qpos[9]}},
        {"load_average", load_average()}, {"timing", "thread CPU time, fastest of 3 runs (1 in --quick)"}});
}

}  // namespace art_bench
