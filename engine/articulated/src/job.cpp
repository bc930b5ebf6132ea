// Job kind "articulated": scene compile, frame records, the simulation and MPC jobs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "pliant/articulated/articulated.h"
#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"
#include "pliant/core/scene.h"

namespace pliant::articulated {
namespace {

void read_vector(JsonReader& r, const char* key, int n, VecX* v) {
  if (!r.has(key)) return;
  const auto vals = r.numbers(key, {}, n, n);
  for (int i = 0; i < n; ++i) (*v)[i] = vals[i];
}

}  // namespace

ArticulatedScene articulated_compile(const Scene& scene) {
  JsonReader r(scene.doc, scene.file);
  accept_scene_envelope(r);
  r.accept("description");
  ArticulatedScene a;
  if (!r.has("model")) r.fail("model", "an articulated scene needs a \"model\" (object or file path)");
  const nlohmann::json& mv = scene.doc.at("model");
  MjcfOptions mjcf;
  if (auto x = r.object("mjcf")) {
    mjcf.ignore_solver_params = x->boolean("ignore_solver_params", false);
    // "mujoco-2.2.2": mesh geoms get the masses libmujoco 2.2.2 compiles (io.h).
    if (x->choice("mesh_inertia", "exact", {"exact", "mujoco-2.2.2"}) == "mujoco-2.2.2")
      mjcf.mesh_inertia = Geom::MeshInertia::MuJoCo222;
    // "tessellated": cylinders and ellipsoids meet planes through their tessellation.
    mjcf.exact_plane_contact = x->choice("curved_contact", "exact", {"exact", "tessellated"}) == "exact";
    x->finish();
  }
  if (mv.is_string()) {
    r.accept("model");
    const std::string rel = mv.get<std::string>();
    const auto path = scene.asset_path(rel);
    try {
      a.model = model_load_file(path, rel, mjcf);
    } catch (const InputError& e) {
      // Name the scene's field and the model file's own location.
      throw InputError(scene.file, "/model",
                       e.file() + (e.pointer().empty() ? "" : ": " + e.pointer()) + ": " + e.problem());
    }
  } else {
    auto mr = r.object("model");
    a.model = model_from_json(*mr, scene.asset_path("."));
    mr->finish();
    // The same choice for a JSON model's cylinders and ellipsoids.
    for (Geom& g : a.model.geoms) g.exact_plane_contact = mjcf.exact_plane_contact;
  }
  const Model& m = a.model;
  SimOptions& o = a.options;
  o.integrator = integrator_from_name(r.choice("integrator", "pbad3", {"pbad2", "pbad3", "pbad4", "euler", "rk4"}));
  o.dt = r.number("dt", m.timestep, 1e-6, 1.0);
  a.duration_s = r.number("duration_s", 5, 0, 1e6);
  a.steps = static_cast<int>(std::llround(a.duration_s / o.dt));
  a.write_every = static_cast<int>(r.integer("write_every", 1, 1, 1000000));
  if (auto c = r.object("contact")) {
    o.contact.enabled = c->boolean("enabled", true);
    o.contact.stiffness = c->number("stiffness", o.contact.stiffness, 1e-6);
    o.contact.damping = c->number("damping", 0, 0);
    const std::string f = c->choice("friction", "coulomb", {"none", "coulomb", "ck"});
    o.contact.friction = f == "none" ? FrictionModel::None : f == "ck" ? FrictionModel::Ck : FrictionModel::Coulomb;
    o.contact.mu = c->number("mu", o.contact.mu, 0);
    o.contact.ck = c->number("ck", o.contact.ck, 0);
    o.contact.slip_eps = c->number("slip_eps", o.contact.slip_eps, 1e-12);
    o.contact.spin_eps = c->number("spin_eps", o.contact.spin_eps, 1e-12);
    o.contact.limit_stiffness = c->number("limit_stiffness", o.contact.limit_stiffness, 0);
    // Body-body contact (off by default: older scenes keep their trajectories).
    o.contact.self_collision = c->boolean("self_collision", false);
    // Explicit pairs, geoms by name (as MJCF's <contact><pair>): always touch, whatever
    // self_collision, contype/conaffinity or exclude say; "mu" overrides contact.mu,
    // "margin" (m) makes the pair touch below that distance, "condim" 1 frictionless,
    // 4 / 6 with "torsion" / "roll" (m).
    for (JsonReader& pr : c->objects("pairs")) {
      ContactPair cp;
      int* ids[2] = {&cp.geom1, &cp.geom2};
      const char* keys[2] = {"geom1", "geom2"};
      for (int i = 0; i < 2; ++i) {
        std::string why;
        *ids[i] = geom_named(m, pr.required_string(keys[i]), &why);
        if (*ids[i] < 0) pr.fail(keys[i], why);
      }
      const std::string problem = contact_pair_problem(m, cp.geom1, cp.geom2);
      if (!problem.empty()) pr.fail("geom2", problem);
      if (pr.has("mu")) cp.mu = pr.number("mu", 0, 0);
      cp.margin = pr.number("margin", 0, 0);
      if (pr.has("condim")) {
        const double cd = pr.number("condim", 3, 0);
        const std::string why = contact_pair_condim_problem(cd);
        if (!why.empty()) pr.fail("condim", why);
        cp.frictionless = cd == 1;
        cp.condim = static_cast<int>(cd);
      }
      // Torsional / rolling coefficients (m) for condim 4 / 6.
      cp.torsion = pr.number("torsion", cp.torsion, 0);
      cp.roll = pr.number("roll", cp.roll, 0);
      pr.finish();
      a.model.contact_pairs.push_back(cp);
    }
    c->finish();
  }
  if (auto jl = r.object("joint_limits")) {
    // Pliant extension, by joint name: a ball joint's swing cone and twist range about
    // its axis (radians), penalties with contact.limit_stiffness (joint_limits.cpp).
    std::vector<std::string> keys, balls;
    for (const auto& item : jl->value().items()) keys.push_back(item.key());
    for (const Joint& j : m.joints)
      if (j.type == JointType::Ball && !j.name.empty()) balls.push_back(j.name);
    for (const std::string& key : keys) {
      Joint* joint = nullptr;
      for (Joint& j : a.model.joints)
        if (j.name == key && j.type == JointType::Ball) joint = &j;
      if (!joint) {
        const std::string near = nearest_name(key, balls);
        jl->fail(key, "no ball joint named \"" + key + "\"" + (near.empty() ? "" : "; did you mean \"" + near + "\"?"));
      }
      auto jr = jl->object(key);
      if (jr->has("swing")) joint->swing_max = jr->required_number("swing", 0, M_PI);
      if (jr->has("twist")) {
        const auto t = jr->numbers("twist", {}, 2, 2, -M_PI, M_PI);
        if (!(t[0] < t[1])) jr->fail("twist", "lower bound must be below the upper bound");
        joint->twist_limited = true;
        joint->twist_min = t[0];
        joint->twist_max = t[1];
      }
      jr->finish();
    }
    jl->finish();
  }
  if (auto s = r.object("solver")) {
    o.solver = s->choice("method", "lm", {"lm", "lbfgs"}) == "lbfgs" ? Solver::Lbfgs : Solver::Lm;
    o.lm_max_iterations = static_cast<int>(s->integer("max_iterations", o.lm_max_iterations, 1, 10000));
    o.lm_tolerance = s->number("tolerance", o.lm_tolerance, 1e-16, 1);
    o.lm_relative_tolerance = s->number("relative_tolerance", o.lm_relative_tolerance, 0, 1);
    o.exact_hessian = s->choice("hessian", "exact", {"exact", "gauss_newton"}) == "exact";
    s->finish();
  }
  a.initial = state_init(m);
  if (auto in = r.object("initial")) {
    read_vector(*in, "qpos", m.nq, &a.initial.qpos);
    read_vector(*in, "qvel", m.nv, &a.initial.qvel);
    in->finish();
  }
  if (auto mp = r.object("mpc")) {
    if (m.actuators.empty()) mp->fail("horizon", "MPC needs a model with actuators");
    MpcOptions c;
    c.duration_s = a.duration_s;
    c.horizon = static_cast<int>(mp->integer("horizon", c.horizon, 1, 1000));
    c.substeps = static_cast<int>(mp->integer("substeps", c.substeps, 1, 1000));
    c.samples = static_cast<int>(mp->integer("samples", c.samples, 2, 100000));
    c.elites = static_cast<int>(mp->integer("elites", c.elites, 1, c.samples));
    c.iterations = static_cast<int>(mp->integer("iterations", c.iterations, 1, 100));
    c.noise = mp->number("noise", c.noise, 0, 10);
    c.seed = static_cast<unsigned>(mp->integer("seed", 1, 0, 1LL << 31));
    c.ctrl_cost = mp->number("ctrl_cost", c.ctrl_cost, 0);
    c.upright_weight = mp->number("upright_weight", c.upright_weight, 0);
    c.height_weight = mp->number("height_weight", c.height_weight, 0);
    mp->finish();
    a.mpc = c;
  }
  r.finish();
  a.frames = a.steps / a.write_every + 1;
  return a;
}

Record articulated_frame_record(const Model& m, const SimOptions& o, const State& s, int index,
                                SimWorkspace& ws) {
  sim_prepare(m, ws);
  Record rec;
  rec.kind = RecordKind::Frame;
  rec.index = index;
  rec.time_s = s.time;
  const Energy e = state_energy(m, o, s, ws);  // leaves kinematics + contacts in ws
  const uint32_t nb = static_cast<uint32_t>(m.bodies.size() - 1);
  Field pose{"body_pose", {nb, 7}, {}};
  pose.data.reserve(nb * 7);
  for (uint32_t b = 1; b <= nb; ++b) {
    const Vec3& x = ws.kin.xpos[b];
    const Quat& q = ws.kin.xquat[b];
    for (double v : {x.x(), x.y(), x.z(), q.w(), q.x(), q.y(), q.z()}) pose.data.push_back(static_cast<float>(v));
  }
  // Obstacle contacts, then body-body ones (force on the body the normal pushes).
  const size_t npair = pair_contact_on(m, o.contact) ? ws.pair_contacts.size() : 0;
  Field contacts{"contacts", {static_cast<uint32_t>(ws.contacts.size() + npair), 6}, {}};
  for (const Contact& c : ws.contacts) {
    const Vec3 f = o.contact.stiffness * c.depth * c.normal;
    for (double v : {c.point.x(), c.point.y(), c.point.z(), f.x(), f.y(), f.z()})
      contacts.data.push_back(static_cast<float>(v));
  }
  for (size_t i = 0; i < npair; ++i) {
    const PairContact& c = ws.pair_contacts[i];
    const Vec3 f = o.contact.stiffness * c.depth * c.gain * c.normal;
    for (double v : {c.point.x(), c.point.y(), c.point.z(), f.x(), f.y(), f.z()})
      contacts.data.push_back(static_cast<float>(v));
  }
  Field energy{"energy", {3}, {static_cast<float>(e.kinetic), static_cast<float>(e.potential), static_cast<float>(e.total)}};
  rec.fields = {std::move(pose), std::move(contacts), std::move(energy)};
  return rec;
}

int articulated_job_frames(const Scene& scene) {
  const ArticulatedScene a = articulated_compile(scene);
  return a.mpc ? a.steps + 1 : a.frames;
}

nlohmann::json articulated_summary(const Scene& scene) {
  const ArticulatedScene a = articulated_compile(scene);
  nlohmann::json s = {{"frames", a.mpc ? a.steps + 1 : a.frames},
                      {"bodies", static_cast<int>(a.model.bodies.size()) - 1},
                      {"nq", a.model.nq},
                      {"nv", a.model.nv},
                      {"integrator", integrator_name(a.options.integrator)},
                      {"dt", a.options.dt}};
  if (!a.model.ignored_attributes.empty()) s["ignored_mjcf_attributes"] = a.model.ignored_attributes;
  return s;
}

nlohmann::json articulated_run_job(JobContext& ctx) {
  const ArticulatedScene a = articulated_compile(ctx.scene);
  if (!a.model.ignored_attributes.empty()) {
    // Asked for by the scene, but the user should still see what had no effect (once
    // per run; the list is also in the metrics and in `pliant validate`'s summary).
    std::string list;
    for (const std::string& at : a.model.ignored_attributes) list += (list.empty() ? "" : ", ") + at;
    std::fprintf(stderr, "%s: /mjcf/ignore_solver_params: %zu MJCF solver parameters without effect: %s\n",
                 ctx.scene.file.c_str(), a.model.ignored_attributes.size(), list.c_str());
  }
  const Model& m = a.model;
  const SimOptions& o = a.options;
  SimWorkspace ws;
  const auto t0 = std::chrono::steady_clock::now();
  double e0 = 0, e_min = 1e300, e_max = -1e300, e_last = 0;
  int frames_written = 0;
  Vec3 root0 = Vec3::Zero();
  double root_displacement = 0;
  auto write = [&](const State& s) {
    Record rec = articulated_frame_record(m, o, s, frames_written, ws);
    if (m.bodies.size() > 1) {
      if (frames_written == 0) root0 = ws.kin.xpos[1];
      root_displacement = (ws.kin.xpos[1] - root0).norm();
    }
    const double e = rec.find("energy")->data[2];
    if (frames_written == 0) e0 = e;
    e_last = e;
    e_min = std::min(e_min, e);
    e_max = std::max(e_max, e);
    ctx.take.append(rec);
    ctx.events.frame(frames_written);
    ++frames_written;
  };
  nlohmann::json metrics;
  if (a.mpc) {
    ctx.progress.stage("mpc", a.steps);
    write(a.initial);
    int airborne = 0, executed = 0;  // frames with no contact: flight phases of a hop
    double torso_min_z = 1e300, torso_max_tilt = 0;
    const MpcResult res = run_cem_mpc(m, o, a.initial, *a.mpc, [&](int i, const State& s) {
      ctx.progress.check_cancelled();
      if (!s.qpos.allFinite()) throw std::runtime_error("MPC trajectory became non-finite at step " + std::to_string(i));
      write(s);  // leaves the frame's contacts in ws
      airborne += ws.contacts.empty() ? 1 : 0;
      ++executed;
      if (m.bodies.size() > 1) {  // body 1's posture: tells a hop from a crawl or a tumble
        torso_min_z = std::min(torso_min_z, ws.kin.xcom[1].z());
        torso_max_tilt = std::max(torso_max_tilt, std::acos(std::clamp(ws.kin.xmat[1](2, 2), -1.0, 1.0)));
      }
      ctx.progress.report(i);
    });
    metrics["distance_m"] = res.distance;
    metrics["airborne_fraction"] = executed > 0 ? double(airborne) / executed : 0.0;
    if (m.bodies.size() > 1) {
      metrics["body1_min_height_m"] = torso_min_z;
      metrics["body1_max_tilt_rad"] = torso_max_tilt;
    }
    metrics["steps"] = static_cast<int>(res.trajectory.size()) - 1;
  } else {
    ctx.progress.stage("simulate", a.steps);
    State s = a.initial;
    write(s);
    long long iterations = 0;
    for (int i = 1; i <= a.steps; ++i) {
      ctx.progress.check_cancelled();
      StepInfo info;
      if (!sim_step(m, o, s, ws, &info))
        throw std::runtime_error("simulation became non-finite (NaN in qpos/qvel) at step " +
                                 std::to_string(i) + ", t = " + std::to_string(s.time) + " s");
      iterations += info.iterations;
      if (i % a.write_every == 0) write(s);
      ctx.progress.report(i);
    }
    metrics["steps"] = a.steps;
    metrics["lm_iterations_per_step"] = a.steps > 0 ? double(iterations) / a.steps : 0.0;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  metrics["wall_s"] = wall;
  metrics["integrator"] = integrator_name(o.integrator);
  metrics["dt"] = o.dt;
  metrics["energy_initial"] = e0;
  // Under MPC the motors do work, so |E - E0| is no integrator's drift: report the net
  // change (the motors' work less what contact and damping took) instead.
  if (a.mpc)
    metrics["energy_change"] = e_last - e0;
  else
    metrics["energy_drift"] = std::max(std::abs(e_max - e0), std::abs(e_min - e0));
  metrics["frames"] = frames_written;
  metrics["root_displacement_m"] = root_displacement;
  if (!m.ignored_attributes.empty()) metrics["ignored_mjcf_attributes"] = m.ignored_attributes;
  return metrics;
}

}  // namespace pliant::articulated
