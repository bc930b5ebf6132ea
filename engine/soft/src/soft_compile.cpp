// Scene -> SoftModel: every field read with JsonReader (unknown keys rejected with a
// suggestion), mesh problems turned into InputError at /character/mesh.
#include <Eigen/Dense>
#include <cmath>
#include <optional>
#include <string>

#include "pliant/core/json_reader.h"
#include "pliant/core/scene.h"
#include "pliant/geom/raster_grid.h"
#include "pliant/soft/soft.h"

namespace pliant::soft {
namespace {

Eigen::Vector3d vec3(JsonReader& r, std::string_view key, Eigen::Vector3d def) {
  const auto v = r.numbers(key, {def[0], def[1], def[2]}, 3, 3);
  return {v[0], v[1], v[2]};
}

Eigen::Vector3d unit3(JsonReader& r, std::string_view key, Eigen::Vector3d def) {
  const Eigen::Vector3d v = vec3(r, key, def);
  if (v.norm() < 1e-12) r.fail(key, "expected a non-zero direction");
  return v.normalized();
}

}  // namespace

SoftModel soft_compile(const Scene& scene) {
  JsonReader root(scene.doc, scene.file);
  accept_scene_envelope(root);
  root.accept("editor");
  SoftModel m;
  Problem& p = m.problem;

  // Character: mesh, lattice, modes.
  auto ch = root.object("character");
  if (!ch) root.fail("character", "missing; expected an object with \"mesh\"");
  const std::string mesh_rel = ch->required_string("mesh");
  const double scale = ch->number("scale", 1.0, 1e-12, 1e12);
  const int resolution = int(ch->integer("resolution", 8, 2, 64));
  const int modes = int(ch->integer("modes", 10, 1, 60));
  const int derivatives = int(ch->integer("modal_derivatives", 0, 0, 8));
  // "pod": nonlinear POD of full simulations under random smooth loads (compile cost:
  // pod_runs x pod_frames full-space steps).
  // "rotation_strain": the linear modes (+ derivatives) in rotation-strain coordinates
  // (Pan et al. 2015), positions by a prefactored CHOLMOD solve.
  const std::string basis_kind = ch->choice("basis", "linear", {"linear", "pod", "rotation_strain"});
  const bool pod = basis_kind == "pod";
  PodTraining pod_training;
  pod_training.runs = int(ch->integer("pod_runs", pod_training.runs, 1, 200));
  pod_training.frames = int(ch->integer("pod_frames", pod_training.frames, 1, 1000));
  pod_training.strain = ch->number("pod_strain", pod_training.strain, 1e-4, 1.0);
  pod_training.linear_modes = int(ch->integer("pod_linear_modes", pod_training.linear_modes, 0, 60));
  const bool cub = ch->boolean("cubature", false);
  const double cub_tol = ch->number("cubature_tolerance", 0.02, 1e-6, 0.5);
  const int cub_poses = int(ch->integer("cubature_poses", 16, 1, 200));
  Material mat;
  if (auto mj = root.object("material")) {
    mat.density_kg_per_m3 = mj->number("density_kg_per_m3", mat.density_kg_per_m3, 1e-3, 1e6);
    mat.young_pa = mj->number("young_pa", mat.young_pa, 1, 1e12);
    mat.poisson = mj->number("poisson", mat.poisson, 0.0, 0.49);
    mj->finish();
  }
  const std::string mesh_ptr = ch->child_pointer("mesh");
  SurfaceMesh surface;
  Lattice lat;
  try {
    geom::TriangleMesh tm = geom::load_mesh(scene.asset_path(mesh_rel), mesh_rel);
    for (auto& v : tm.vertices)
      for (double& c : v) c *= scale;
    surface = repair_mesh(tm, &m.repair);
    lat = build_lattice(surface, resolution, mat.density_kg_per_m3);
  } catch (const geom::GeomError& e) {
    throw InputError(scene.file, mesh_ptr, e.what());
  } catch (const BodyError& e) {
    throw InputError(scene.file, mesh_ptr, mesh_rel + ": " + e.what());
  }
  if (lat.nodes() > 20000)
    throw InputError(scene.file, ch->child_pointer("resolution"),
                     "lattice has " + std::to_string(lat.nodes()) + " nodes (at most 20000); lower the resolution");
  ch->finish();
  if (pod && derivatives > 0)
    ch->fail("modal_derivatives", "modal derivatives and \"basis\": \"pod\" cannot be combined");
  m.character = make_character(std::move(surface), std::move(lat), mat, modes, derivatives, pod ? &pod_training : nullptr);
  // Before the cubature training and soft_bind, which use the character's map.
  if (basis_kind == "rotation_strain") enable_rotation_strain(m.character);

  // Environment.
  Environment& env = p.env;
  bool ground = true;
  double ground_h = 0;
  if (auto e = root.object("environment")) {
    const std::string type = e->choice("type", "ground", {"ground", "water"});
    env.water = type == "water";
    env.gravity_m_per_s2 = vec3(*e, "gravity_m_per_s2", env.water ? Eigen::Vector3d::Zero() : env.gravity_m_per_s2);
    ground = e->boolean("ground", !env.water);
    ground_h = e->number("ground_height_m", 0.0);
    env.friction = e->number("friction", env.friction, 0, 10);
    env.contact_stiffness_per_s2 = e->number("contact_stiffness_per_s2", env.contact_stiffness_per_s2, 1, 1e9);
    env.friction_eps_m_per_s = e->number("friction_eps_m_per_s", env.friction_eps_m_per_s, 1e-9, 10);
    env.fluid_density_kg_per_m3 = e->number("fluid_density_kg_per_m3", env.fluid_density_kg_per_m3, 0, 1e5);
    env.drag_coefficient = e->number("drag_coefficient", env.drag_coefficient, 0, 100);
    env.skin_coefficient = e->number("skin_coefficient", env.skin_coefficient, 0, 100);
    if (ground) env.obstacles.push_back({Obstacle::Plane, Eigen::Vector3d(0, ground_h, 0), Eigen::Vector3d::UnitY(), 0});
    for (auto& o : e->objects("obstacles")) {
      Obstacle ob;
      const std::string t = o.choice("type", "sphere", {"sphere", "plane"});
      if (t == "sphere") {
        ob.type = Obstacle::Sphere;
        ob.point = vec3(o, "center_m", Eigen::Vector3d::Zero());
        ob.radius_m = o.required_number("radius_m", 1e-6, 1e6);
      } else {
        ob.type = Obstacle::Plane;
        ob.point = vec3(o, "point_m", Eigen::Vector3d::Zero());
        ob.normal = unit3(o, "normal", Eigen::Vector3d::UnitY());
      }
      o.finish();
      env.obstacles.push_back(ob);
    }
    e->finish();
  } else {
    env.obstacles.push_back({Obstacle::Plane, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 0});
  }

  // Simulation.
  if (auto s = root.object("simulation")) {
    p.sim.dt_s = s->number("dt_s", 1.0 / 30, 1e-5, 0.2);
    m.frames = int(s->integer("frames", 100, 1, 100000));
    p.sim.modal_damping_s = s->number("modal_damping_s", p.sim.modal_damping_s, 0, 10);
    p.start_offset_m = vec3(*s, "start_offset_m", Eigen::Vector3d::Zero());
    p.sim.max_newton = int(s->integer("newton_iterations", p.sim.max_newton, 1, 1000));
    p.sim.newton_decrement_stop = s->number("newton_decrement_stop", p.sim.newton_decrement_stop, 0, 1e-6);
    s->finish();
  }

  // Controller.
  p.dmp.modes = std::min(m.character.basis.r(), 6);
  if (auto c = root.object("controller")) {
    p.dmp.modes = int(c->integer("modes", p.dmp.modes, 0, m.character.basis.r()));
    p.dmp.kernels = int(c->integer("kernels", p.dmp.kernels, 1, 64));
    p.dmp.period_s = c->number("period_s", p.dmp.period_s, 1e-3, 1e3);
    p.dmp.max_activation_rel = c->number("max_activation_rel", p.dmp.max_activation_rel, 1e-3, 10);
    c->finish();
  }

  // Objectives.
  Objectives& o = p.obj;
  std::optional<JsonReader> steady_reader;  // its horizon check waits for the optimizer block
  if (auto oj = root.object("objectives")) {
    if (auto t = oj->object("velocity")) {
      o.velocity_m_per_s = vec3(*t, "target_m_per_s", Eigen::Vector3d::Zero());
      o.w_velocity = t->number("weight", 1, 0);
      t->finish();
    }
    if (auto t = oj->object("position")) {
      o.position_m = vec3(*t, "target_m", Eigen::Vector3d::Zero());
      o.w_position = t->number("weight", 1, 0);
      t->finish();
    }
    if (auto t = oj->object("heading")) {
      o.heading_axis = unit3(*t, "body_axis", Eigen::Vector3d::UnitX());
      o.heading_direction = unit3(*t, "direction", Eigen::Vector3d::UnitX());
      o.w_heading = t->number("weight", 1, 0);
      t->finish();
    }
    if (auto t = oj->object("course")) {
      o.course_direction = unit3(*t, "direction", Eigen::Vector3d::UnitX());
      // The course is a line on the ground: a vertical direction has no lateral offset.
      if (std::hypot(o.course_direction.x(), o.course_direction.z()) < 1e-6)
        t->fail("direction", "expected a direction with a horizontal (x or z) part: the course is a line on the ground");
      o.w_course = t->number("weight", 1, 0);
      t->finish();
    }
    if (auto t = oj->object("upright")) {
      o.upright_axis = unit3(*t, "body_axis", Eigen::Vector3d::UnitY());
      o.w_upright = t->number("weight", 1, 0);
      t->finish();
    }
    if (auto t = oj->object("turn")) {
      o.turn_axis = unit3(*t, "body_axis", Eigen::Vector3d::UnitX());
      o.turn_rate_rad_per_s = t->number("rate_rad_per_s", 0, -100, 100);
      o.turn_speed_m_per_s = t->number("speed_m_per_s", 0, 0, 100);
      o.w_turn = t->number("weight", 1, 0);
      t->finish();
    }
    if (auto t = oj->object("steady")) {
      o.steady_axis = unit3(*t, "body_axis", Eigen::Vector3d::UnitX());
      o.steady_direction = unit3(*t, "direction", Eigen::Vector3d::UnitX());
      if (std::hypot(o.steady_direction.x(), o.steady_direction.z()) < 1e-6)
        t->fail("direction", "expected a direction with a horizontal (x or z) part: the walk's course on the ground");
      o.steady_periods = int(t->integer("periods", 1, 1, 1000));
      o.w_steady = t->number("weight", 1, 0);
      o.w_steady_periodic = t->number("periodicity_weight", 0, 0);
      t->finish();
      steady_reader = *t;
    }
    if (auto t = oj->object("jump")) {
      o.jump_height_m = t->required_number("height_m", 0, 1e3);
      o.w_jump = t->number("weight", 1, 0);
      t->finish();
    }
    if (auto t = oj->object("distance")) {
      o.distance_m = t->required_number("distance_m", -1e4, 1e4);
      o.distance_direction = unit3(*t, "direction", Eigen::Vector3d::UnitX());
      o.w_distance = t->number("weight", 1, 0);
      t->finish();
    }
    if (auto t = oj->object("shuffle")) {
      o.w_shuffle = t->number("weight", 1, 0);
      t->finish();
    }
    if (auto t = oj->object("effort")) {
      o.w_effort = t->number("weight", o.w_effort, 0);
      t->finish();
    }
    if (auto t = oj->object("keyframes")) {
      o.w_keyframes = t->number("weight", 1, 0);
      for (auto& k : t->objects("frames")) {
        Keyframe kf;
        kf.frame = int(k.required_integer("frame", 1, 1000000));
        const auto ids = k.integers("vertices", {}, 1, 1000000, 0, int(m.character.surface.vertices.size()) - 1);
        for (auto v : ids) kf.vertices.push_back(int(v));
        kf.offset_m = vec3(k, "offset_m", Eigen::Vector3d::Zero());
        k.finish();
        o.keyframes.push_back(kf);
      }
      t->finish();
    }
    oj->finish();
  }

  // Optimizer.
  p.frames = std::min(m.frames, 60);
  if (auto oj = root.object("optimizer")) {
    const std::string method = oj->choice("method", "hybrid", {"hybrid", "lm", "lbfgs", "spacetime", "none"});
    m.optimizer.kind = method == "lm"          ? OptimizerKind::LM
                       : method == "lbfgs"     ? OptimizerKind::LBFGS
                       : method == "spacetime" ? OptimizerKind::Spacetime
                                               : OptimizerKind::Hybrid;
    m.optimizer.max_iterations = int(oj->integer("iterations", 20, 0, 100000));
    if (method == "none") m.optimizer.max_iterations = 0;
    p.frames = int(oj->integer("horizon_frames", p.frames, 1, 100000));
    m.optimizer.fd_step = oj->number("fd_step", m.optimizer.fd_step, 1e-12, 1);
    m.optimizer.tolerance = oj->number("tolerance", m.optimizer.tolerance, 0, 1);
    // LM damping at the start, Broyden reuse iterations, L-BFGS first step (optimizer.h).
    m.optimizer.lambda_initial = oj->number("lm_lambda_initial", m.optimizer.lambda_initial, 1e-12, 1e12);
    m.optimizer.broyden_reuse = int(oj->integer("broyden_reuse", m.optimizer.broyden_reuse, 0, 1000));
    // 0 = the first step is the raw gradient itself (alpha 1 on -g; optimizer.h).
    m.optimizer.lbfgs_initial_step = oj->number("lbfgs_initial_step", m.optimizer.lbfgs_initial_step, 0, 1e12);
    // Fused trials and the LM damping schedule (optimizer.h; tenth session).
    m.optimizer.fused_trials = oj->boolean("fused_trials", m.optimizer.fused_trials);
    const std::string damping = oj->choice(
        "lm_damping", m.optimizer.lm_damping == OptimizerSettings::Damping::TrustRegion ? "trust_region" : "marquardt",
        {"marquardt", "trust_region"});
    m.optimizer.lm_damping = damping == "trust_region" ? OptimizerSettings::Damping::TrustRegion : OptimizerSettings::Damping::Marquardt;
    // The hybrid's L-BFGS phase line search (optimizer.h; eleventh session).
    const std::string hls = oj->choice("hybrid_lbfgs_line_search", line_search_name(m.optimizer.hybrid_lbfgs_line_search),
                                       {"armijo", "wolfe", "strong_wolfe", "bracketing", "nocedal_wright"});
    m.optimizer.hybrid_lbfgs_line_search = parse_line_search(hls);
    // Pure L-BFGS's variant (optimizer.h; bench env only before 2026-12-01): its
    // line search, the curvature pairs kept (the hybrid's L-BFGS phase keeps as many)
    // and the restarts after a failed line search.
    const std::string lls = oj->choice("lbfgs_line_search", line_search_name(m.optimizer.lbfgs_line_search),
                                       {"armijo", "wolfe", "strong_wolfe", "bracketing", "nocedal_wright"});
    m.optimizer.lbfgs_line_search = parse_line_search(lls);
    m.optimizer.lbfgs_memory = int(oj->integer("lbfgs_memory", m.optimizer.lbfgs_memory, 1, 1000));
    m.optimizer.lbfgs_restarts = int(oj->integer("lbfgs_restarts", m.optimizer.lbfgs_restarts, 0, 1000));
    // Rollout Jacobian: exact forward sensitivities or finite differences (optimizer.h).
    const std::string jac = oj->choice("jacobian", m.optimizer.jacobian == JacobianKind::Sensitivity ? "sensitivity" : "finite_difference",
                                       {"sensitivity", "finite_difference"});
    m.optimizer.jacobian = jac == "sensitivity" ? JacobianKind::Sensitivity : JacobianKind::FiniteDifference;
    // Spacetime penalty weights (spacetime.h), per metre^2.
    SpacetimeSettings& sp = m.spacetime;
    sp.w_physics = oj->number("physics_weight", sp.w_physics, 1e-6, 1e16);
    sp.w_dmp_initial = oj->number("dmp_weight_initial", sp.w_dmp_initial, 1e-12, 1e16);
    sp.w_dmp_max = oj->number("dmp_weight_max", sp.w_dmp_max, sp.w_dmp_initial, 1e16);
    oj->finish();
  }
  if (steady_reader) {
    // The windows must lie inside the horizon: one for the rates, two with periodicity.
    const int P = steady_window_frames(o, p.dmp.period_s, p.sim.dt_s);
    const int need = (o.w_steady_periodic > 0 ? 2 : 1) * P;
    if (p.frames < need)
      steady_reader->fail("periods", "the optimizer's horizon_frames (" + std::to_string(p.frames) + ") is shorter than the " +
                                         std::to_string(need) + " frames the steady windows need (" +
                                         std::to_string(o.steady_periods) + " period(s) of " + std::to_string(P) +
                                         " frames each)");
  }
  m.spacetime.max_iterations = m.optimizer.max_iterations;
  m.spacetime.tolerance = m.optimizer.tolerance;
  m.spacetime.jacobian = m.optimizer.jacobian;  // one key picks both optimizers' derivatives
  // Navigation: gaits (forward, left, right) + RRT* to a goal (navigation.h).
  if (auto nj = root.object("navigation")) {
    NavSettings& nav = m.navigation;
    if (!navigation_available())
      root.fail("navigation", "navigation needs OMPL (Debian package libompl-dev); this build has none");
    nav.enabled = true;
    const auto g = nj->numbers("goal_m", {}, 2, 2);
    if (g.size() != 2) nj->fail("goal_m", "missing; expected [x, z] (metres, ground plane)");
    nav.goal_m = {g[0], g[1]};
    nav.goal_tolerance_m = nj->number("goal_tolerance_m", nav.goal_tolerance_m, 1e-3, 1e3);
    nav.body_axis = unit3(*nj, "body_axis", nav.body_axis);
    nav.speed_m_per_s = nj->number("speed_m_per_s", nav.speed_m_per_s, 1e-4, 100);
    nav.turn_rate_rad_per_s = nj->number("turn_rate_rad_per_s", nav.turn_rate_rad_per_s, 1e-3, 100);
    nav.clearance_m = nj->number("clearance_m", nav.clearance_m, 0, 1e3);
    nav.planning_time_s = nj->number("planning_time_s", nav.planning_time_s, 1e-3, 600);
    nav.max_frames = int(nj->integer("max_frames", nav.max_frames, 1, 1000000));
    for (auto& o2 : nj->objects("obstacles")) {
      NavObstacle ob;
      const auto c = o2.numbers("center_m", {}, 2, 2);
      if (c.size() != 2) o2.fail("center_m", "missing; expected [x, z]");
      ob.center_m = {c[0], c[1]};
      ob.radius_m = o2.required_number("radius_m", 1e-6, 1e6);
      o2.finish();
      nav.obstacles.push_back(ob);
      // Also a physical obstacle: a sphere centred on the ground.
      env.obstacles.push_back({Obstacle::Sphere, Eigen::Vector3d(c[0], ground_h, c[1]), Eigen::Vector3d::UnitY(),
                               ob.radius_m});
    }
    if (auto gj = nj->object("gaits")) {
      const char* names[3] = {"forward", "left", "right"};
      std::vector<Eigen::VectorXd> th;
      for (const char* nm : names) {
        const auto v = gj->numbers(nm, {}, 0, 100000);
        if (v.empty()) continue;
        if (int(v.size()) != p.dmp.parameters())
          gj->fail(nm, "expected " + std::to_string(p.dmp.parameters()) + " DMP parameters, got " +
                           std::to_string(v.size()));
        th.push_back(Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size())));
      }
      gj->finish();
      if (th.size() == 3) nav.cached_theta = th;
      else if (!th.empty()) nj->fail("gaits", "give all three of forward, left, right (or none to optimize them)");
    }
    nj->finish();
  }
  for (const auto& k : o.keyframes)
    if (k.frame > p.frames)
      throw InputError(scene.file, "/objectives/keyframes",
                       "keyframe at frame " + std::to_string(k.frame) + " is after the optimization horizon (" +
                           std::to_string(p.frames) + " frames)");
  root.finish();

  if (cub) {
    const auto poses = training_poses(m.character, cub_poses, 0.05, 11);
    m.character.cubature = fit_cubature(m.character, poses, cub_tol, 400, &m.cubature);
  }
  p.character = &m.character;
  return m;
}

}  // namespace pliant::soft
