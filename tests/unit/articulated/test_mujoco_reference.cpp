// Reference checks against MuJoCo 2.2.2's own compiler (mj_loadXML).
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pliant/articulated/dynamics.h"
#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"
#include "test_util.h"

namespace pliant::articulated {
namespace {

mjModel* load_mujoco(const std::string& xml) {
  const auto path = std::filesystem::temp_directory_path() / ("pliant_mj_" + std::to_string(::getpid()) + ".xml");
  std::ofstream(path) << xml;
  char err[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  std::filesystem::remove(path);
  EXPECT_NE(m, nullptr) << err;
  return m;
}

// tol: relative for masses and moments, absolute for centres (1e-7 where MuJoCo
// re-centres a mesh in float and compiles its mass from the float vertices).
void compare_mass_properties(const Model& ours, const mjModel* mj, double tol = 1e-9) {
  ASSERT_EQ(mj->nbody, static_cast<int>(ours.bodies.size()));
  ASSERT_EQ(mj->nv, ours.nv);
  for (int b = 1; b < mj->nbody; ++b) {
    const Body& body = ours.bodies[b];
    EXPECT_NEAR(body.mass, mj->body_mass[b], tol * body.mass) << "body " << b;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(body.com[a], mj->body_ipos[3 * b + a], tol);
    // MuJoCo stores principal moments (body_inertia) in the frame body_iquat.
    Eigen::SelfAdjointEigenSolver<Mat3> eig(body.inertia);
    std::vector<double> ours_p(eig.eigenvalues().data(), eig.eigenvalues().data() + 3);
    std::vector<double> mj_p(mj->body_inertia + 3 * b, mj->body_inertia + 3 * b + 3);
    std::sort(ours_p.begin(), ours_p.end());
    std::sort(mj_p.begin(), mj_p.end());
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(ours_p[a], mj_p[a], tol * mj_p[2]) << "body " << b;
  }
}

void expect_same_mass_properties(const std::string& xml, const MjcfOptions& options = {}) {
  const Model ours = model_from_mjcf(xml, "model.xml", {}, options);
  mjModel* mj = load_mujoco(xml);
  ASSERT_NE(mj, nullptr);
  compare_mass_properties(ours, mj);
  mj_deleteModel(mj);
}

TEST(MujocoReference, ChainMassesAndInertiasMatch) { expect_same_mass_properties(chain_mjcf(10)); }

TEST(MujocoReference, MixedGeomsMatch) {
  expect_same_mass_properties(R"(<mujoco><worldbody>
    <body name="a" pos="0 0 1"><freejoint/>
      <geom type="box" size="0.1 0.2 0.05" pos="0.05 0 0"/>
      <geom type="sphere" size="0.07" pos="-0.1 0.1 0" density="500"/>
      <body name="b" pos="0.2 0 0"><joint type="ball"/>
        <geom type="capsule" fromto="0 0 0 0.1 0.2 -0.1" size="0.03"/>
      </body>
    </body></worldbody></mujoco>)");
}

std::string asset(const std::string& rel) {
  std::ifstream in(std::string(PLIANT_ASSETS_DIR) + "/" + rel);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(MujocoReference, HopperAndWalkerModelsMatch) {
  expect_same_mass_properties(asset("models/hopper2d.xml"));
  expect_same_mass_properties(asset("models/walker3d.xml"));
}

TEST(MujocoReference, MassMatrixMatches) {
  // Same model, same configuration: joint-space inertia M(q) agrees with mj_fullM.
  const std::string xml = chain_mjcf(5);
  const Model ours = model_from_mjcf(xml, "chain.xml");
  mjModel* mj = load_mujoco(xml);
  ASSERT_NE(mj, nullptr);
  mjData* d = mj_makeData(mj);
  VecX q(ours.nq);
  for (int i = 0; i < ours.nq; ++i) q[i] = 0.3 * std::sin(1.7 * i + 0.4);
  for (int i = 0; i < ours.nq; ++i) d->qpos[i] = q[i];
  mj_forward(mj, d);
  std::vector<mjtNum> full(mj->nv * mj->nv);
  mj_fullM(mj, full.data(), d->qM);
  Kinematics k;
  kinematics(ours, q, &k);
  const Eigen::MatrixXd mm = mass_matrix(ours, k);
  for (int i = 0; i < ours.nv; ++i)
    for (int j = 0; j < ours.nv; ++j) EXPECT_NEAR(mm(i, j), full[i * mj->nv + j], 1e-9);
  mj_deleteData(d);
  mj_deleteModel(mj);
}

// <default> classes (nested, class=, childclass=), euler (both eulerseq cases) and
// axisangle in degrees, and joint ranges compile as MuJoCo compiles them: same masses,
// same body poses at a configuration, same ranges.
void compare_poses_and_ranges(const Model& ours, mjModel* mj, double tol = 1e-9) {
  compare_mass_properties(ours, mj, tol);
  mjData* d = mj_makeData(mj);
  VecX q(ours.nq);
  for (int i = 0; i < ours.nq; ++i) q[i] = 0.4 * std::sin(1.3 * i + 0.2);
  for (int i = 0; i < ours.nq; ++i) d->qpos[i] = q[i];
  mj_forward(mj, d);
  Kinematics k;
  kinematics(ours, q, &k);
  for (int b = 1; b < mj->nbody; ++b)
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(k.xpos[b][a], d->xpos[3 * b + a], 1e-9) << "body " << b;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(k.xmat[b](a, c), d->xmat[9 * b + 3 * a + c], 1e-9) << "body " << b;
    }
  // Compiled frames: body pose in its parent, inertia (full matrix about the centre,
  // body frame), joint axes and anchors, primitive geoms' pose and size in the body.
  const auto expect_same_quat = [](const Quat& q, const mjtNum* mq, const std::string& what) {
    const double sign = q.w() * mq[0] + q.x() * mq[1] + q.y() * mq[2] + q.z() * mq[3] < 0 ? -1 : 1;
    const double diff = (Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()) - sign * Eigen::Vector4d(mq[0], mq[1], mq[2], mq[3])).norm();
    EXPECT_NEAR(diff, 0, 1e-9) << what;
  };
  for (int b = 1; b < mj->nbody; ++b) {
    const Body& body = ours.bodies[b];
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(body.pos[a], mj->body_pos[3 * b + a], 1e-9) << "body " << b;
    expect_same_quat(body.quat, mj->body_quat + 4 * b, "body " + std::to_string(b));
    mjtNum rm[9];
    mju_quat2Mat(rm, mj->body_iquat + 4 * b);
    const Mat3 r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(rm);
    const Mat3 mj_inertia = r * Vec3(mj->body_inertia[3 * b], mj->body_inertia[3 * b + 1], mj->body_inertia[3 * b + 2]).asDiagonal() * r.transpose();
    // (MuJoCo stores principal axes from its iterative eigen-solver: ~1e-7 relative)
    EXPECT_NEAR((body.inertia - mj_inertia).norm(), 0, std::max(1e-9, tol * mj_inertia.norm())) << "body " << b;
  }
  for (int j = 0; j < mj->njnt; ++j)
    if (mj->jnt_type[j] == mjJNT_HINGE || mj->jnt_type[j] == mjJNT_SLIDE)
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(ours.joints[j].axis[a], mj->jnt_axis[3 * j + a], 1e-9) << "joint " << j;
        EXPECT_NEAR(ours.joints[j].pos[a], mj->jnt_pos[3 * j + a], 1e-9) << "joint " << j;
      }
  ASSERT_EQ(static_cast<int>(ours.actuators.size()), mj->nu);
  for (int a = 0; a < mj->nu; ++a) {
    EXPECT_EQ(ours.actuators[a].joint, mj->actuator_trnid[2 * a]) << "actuator " << a;
    EXPECT_EQ(ours.actuators[a].gear, mj->actuator_gear[6 * a]) << "actuator " << a;
  }
  for (int j = 0; j < mj->njnt; ++j)
    EXPECT_EQ(ours.joints[j].armature, mj->dof_armature[mj->jnt_dofadr[j]]) << "joint " << j;
  std::vector<Geom> geoms = ours.geoms;  // MuJoCo lists geoms body by body
  std::stable_sort(geoms.begin(), geoms.end(), [](const Geom& x, const Geom& y) { return x.body < y.body; });
  ASSERT_EQ(static_cast<int>(geoms.size()), mj->ngeom);
  for (int g = 0; g < mj->ngeom; ++g) {
    if (geoms[g].type == GeomType::Mesh) continue;
    EXPECT_EQ(geoms[g].body, mj->geom_bodyid[g]);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(geoms[g].pos[a], mj->geom_pos[3 * g + a], 1e-9) << "geom " << g;
    expect_same_quat(geoms[g].quat, mj->geom_quat + 4 * g, "geom " + std::to_string(g));
    const int nsize = geoms[g].type == GeomType::Box ? 3 : geoms[g].type == GeomType::Capsule ? 2 : 1;
    if (geoms[g].type != GeomType::Plane) {
      for (int a = 0; a < nsize; ++a) EXPECT_NEAR(geoms[g].size[a], mj->geom_size[3 * g + a], 1e-12) << "geom " << g;
    }
  }
  for (int j = 0; j < mj->njnt; ++j) {
    EXPECT_EQ(ours.joints[j].limited, mj->jnt_limited[j] != 0) << "joint " << j;
    EXPECT_NEAR(ours.joints[j].damping, mj->dof_damping[mj->jnt_dofadr[j]], 1e-12) << "joint " << j;
    EXPECT_NEAR(ours.joints[j].stiffness, mj->jnt_stiffness[j], 1e-12) << "joint " << j;
    if (ours.joints[j].limited) {
      EXPECT_NEAR(ours.joints[j].range_min, mj->jnt_range[2 * j], 1e-12);
      EXPECT_NEAR(ours.joints[j].range_max, mj->jnt_range[2 * j + 1], 1e-12);
    }
  }
  mj_deleteData(d);
}

void expect_same_poses_and_ranges(const std::string& xml, const MjcfOptions& options = {}) {
  const Model ours = model_from_mjcf(xml, "model.xml", {}, options);
  mjModel* mj = load_mujoco(xml);
  ASSERT_NE(mj, nullptr);
  compare_poses_and_ranges(ours, mj);
  mj_deleteModel(mj);
}

// The same for a model file (its includes and meshes beside it).
void expect_same_model_file(const std::filesystem::path& path, const MjcfOptions& options = {}, double tol = 1e-9) {
  const Model ours = model_load_file(path, path.filename().string(), options);
  char err[1000] = "";
  mjModel* mj = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  ASSERT_NE(mj, nullptr) << err;
  compare_poses_and_ranges(ours, mj, tol);
  mj_deleteModel(mj);
}

TEST(MujocoReference, DefaultsEulerAxisangleAndRangesMatch) {
  const std::string body = R"(<default>
      <joint damping="0.3"/>
      <geom type="capsule" size="0.03" density="800"/>
      <default class="leg"><joint range="-40 60" limited="true"/><geom size="0.02"/>
        <default class="foot"><geom type="sphere" size="0.05" density="2000"/></default>
      </default>
    </default>
    <worldbody>
      <body pos="0 0 1" euler="10 20 30"><joint type="slide" axis="0 0 1"/>
        <geom type="box" size="0.1 0.05 0.03" axisangle="1 1 0 35"/>
        <body pos="0.1 0 0" childclass="leg" axisangle="0 1 1 -50"><joint axis="0 1 0"/>
          <geom fromto="0 0 0 0 0 -0.3"/>
          <body pos="0 0 -0.3" euler="0 -15 5"><joint axis="1 0 0" range="-10 10"/>
            <geom class="foot" pos="0 0 -0.1"/>
            <geom class="main" fromto="0 0 0 0.1 0 0" euler="0 0 0"/>
            <body pos="0.1 0 0"><joint type="ball" range="0 45"/><geom class="foot"/></body>
          </body>
        </body>
      </body>
    </worldbody></mujoco>)";
  expect_same_poses_and_ranges("<mujoco>" + body);
  expect_same_poses_and_ranges("<mujoco><compiler eulerseq=\"ZYX\"/>" + body);
  expect_same_poses_and_ranges("<mujoco><compiler eulerseq=\"xZy\"/>" + body);
}

// xyaxes and zaxis (bodies, geoms, inertials; unnormalised, non-orthogonal and
// antiparallel inputs), fromto on boxes and capsules, joint axes, radians and an
// extrinsic eulerseq, nested defaults with childclass for joints, geoms and motors,
// and compiler inertiafromgeom: same compiled frames, inertias and axes as MuJoCo's.
TEST(MujocoReference, AllOrientationFormsAndFromtoMatch) {
  const std::string body = R"(
    <default>
      <joint axis="0 1 1" damping="0.2" armature="0.01"/>
      <geom type="box" size="0.05 0.04 0.03" density="900"/>
      <motor gear="7"/>
      <default class="arm"><joint axis="1 0 0.5"/><geom type="capsule" size="0.02"/>
        <default class="tip"><geom type="sphere" size="0.03" density="3000"/><motor gear="2"/></default>
      </default>
    </default>
    <worldbody>
      <geom type="plane" size="1 1 0.1" zaxis="0.1 0.2 1"/>
      <body pos="0.1 -0.2 1" xyaxes="1 1 0 -2 1 0.3"><freejoint/>
        <geom xyaxes="0 1 0 -1 0 0" pos="0.01 0 0"/>
        <geom zaxis="0 0 -1" pos="0 0.1 0"/>
        <geom fromto="-0.1 0 0 0.1 0.05 0.02" size="0.03"/>
        <body pos="0 0.2 0" zaxis="1 -1 0.2" childclass="arm"><joint name="j1"/>
          <geom fromto="0 0 0 0 0 -0.25"/>
          <geom fromto="0 0 0 0.1 0.1 0.1" type="box" size="0.01"/>
          <body pos="0 0 -0.25" euler="0.3 -0.4 1.2"><joint name="j2" axis="0 -2 0" pos="0 0 0.01"/>
            <joint name="j3" type="slide" axis="1 1 1"/>
            <geom class="tip" zaxis="0 1 0"/>
            <inertial pos="0.01 0.02 -0.03" mass="0.7" diaginertia="0.01 0.02 0.03" xyaxes="0 0 1 1 1 0"/>
          </body>
          <body pos="0.1 0 0" axisangle="1 2 3 0.7"><joint name="j4" type="ball"/>
            <geom class="tip"/>
            <inertial pos="0 0 0.01" mass="0.4" diaginertia="0.004 0.005 0.006" zaxis="0 0 -1"/>
          </body>
        </body>
      </body>
    </worldbody>
    <actuator><motor joint="j1"/><motor joint="j2" class="tip"/></actuator></mujoco>)";
  expect_same_poses_and_ranges("<mujoco><compiler angle=\"radian\" eulerseq=\"XZY\"/>" + body);
  expect_same_poses_and_ranges("<mujoco><compiler angle=\"radian\" eulerseq=\"zyx\" inertiafromgeom=\"true\"/>" + body);
  const Model m = model_from_mjcf("<mujoco><compiler angle=\"radian\"/>" + body, "m.xml");
  ASSERT_EQ(m.actuators.size(), 2u);
  EXPECT_EQ(m.actuators[0].gear, 7);
  EXPECT_EQ(m.actuators[1].gear, 2);
}

// <compiler coordinate="global"> (gym's hopper and walker style): every frame in world
// coordinates, bodies turned by euler / axisangle / xyaxes, geoms by fromto and quat,
// joints with world anchors and axes, an inertial with diaginertia and one with
// fullinertia in world axes. Compiles to MuJoCo 2.2.2's own local frames.
// MuJoCo's own example models as Debian's libmujoco-samples ships them: the humanoid
// (a free joint and 21 hinges, up to three per body, nested default classes with
// childclass, fromto capsules, cameras and lights, motors) and 22 of them in one file
// (352 bodies). Their geom solref/solimp and joint solimplimit have no meaning in
// Pliant's penalty contact, so they load with ignore_solver_params, and must be named
// without it; everything else compiles as MuJoCo compiles it.
TEST(MujocoReference, MuJoCosShippedHumanoidsCompileAsMuJoCoCompilesThem) {
  for (const std::string rel : {"humanoid/humanoid.xml", "humanoid/22_humanoids.xml"}) {
    const std::filesystem::path path = std::filesystem::path(PLIANT_MUJOCO_MODEL_DIR) / rel;
    ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing: scripts/setup.sh installs libmujoco-samples";
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    MjcfOptions options;
    options.ignore_solver_params = true;
    expect_same_model_file(path, options);
    const Model ours = model_from_mjcf(ss.str(), rel, {}, options);
    EXPECT_GE(ours.ignored_attributes.size(), 3u) << rel;
    try {
      model_from_mjcf(ss.str(), rel);
      ADD_FAILURE() << rel << " loaded with its solref without ignore_solver_params";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("ignore_solver_params"), std::string::npos) << e.what();
    }
  }
}

// The humanoid with 100 free objects (humanoid100.xml: an <include>d body, capsules,
// ellipsoids, boxes, cylinders, spheres) and the mug (a mesh and cylinders): cylinders
// and ellipsoids get MuJoCo's exact masses and inertias (their tessellation is for
// contact only).
TEST(MujocoReference, CylindersEllipsoidsAndIncludesOfMuJoCosModelsMatch) {
  MjcfOptions options;
  options.ignore_solver_params = true;
  expect_same_model_file(std::filesystem::path(PLIANT_MUJOCO_MODEL_DIR) / "humanoid100/humanoid100.xml", options);
  expect_same_poses_and_ranges(R"(<mujoco><worldbody>
    <body name="can" pos="0 0 1"><freejoint/><geom type="cylinder" size="0.04 0.06" density="700"/>
      <geom type="cylinder" fromto="0.05 0 0 0.05 0.1 0.02" size="0.01"/>
      <body name="egg" pos="0.1 0 0" euler="10 20 30"><joint axis="0 1 0"/>
        <geom type="ellipsoid" size="0.03 0.05 0.02" pos="0.01 0 0" euler="0 30 0" density="1200"/></body>
    </body></worldbody></mujoco>)");
}

// Mesh geoms: with mjcf.mesh_inertia "mujoco-2.2.2" a model compiles to libmujoco
// 2.2.2's own masses (mesh_inertia.cpp: unsigned tetrahedra, the mass from the
// equivalent inertia box). An L-shaped prism (integer vertices: exact in MuJoCo's float
// meshes, scaled by 1/8) posed in a body beside a capsule, to 1e-7 (MuJoCo re-centres
// the mesh in float); the mug of libmujoco-samples (24544 faces) to 1e-6. By default the solid's mass stands: 3 of MuJoCo's
// sqrt(35/3) for the L, and the mug's mesh below MuJoCo's by more than half.
TEST(MujocoReference, MeshGeomsCompileToMuJoCosMassesUnderItsRule) {
  const auto dir = std::filesystem::temp_directory_path() / ("pliant_mj_mesh_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    std::ofstream obj(dir / "L.obj");
    const double p[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    for (double z : {0.0, 1.0})
      for (const auto& v : p) obj << "v " << v[0] << " " << v[1] << " " << z << "\n";
    const int cap[4][3] = {{3, 4, 5}, {3, 5, 0}, {3, 0, 1}, {3, 1, 2}};
    for (const auto& t : cap) {
      obj << "f " << t[0] + 1 << " " << t[2] + 1 << " " << t[1] + 1 << "\n";
      obj << "f " << t[0] + 7 << " " << t[1] + 7 << " " << t[2] + 7 << "\n";
    }
    for (int i = 0; i < 6; ++i) {
      const int j = (i + 1) % 6;
      obj << "f " << i + 1 << " " << j + 1 << " " << j + 7 << "\n";
      obj << "f " << i + 1 << " " << j + 7 << " " << i + 7 << "\n";
    }
  }
  std::ofstream(dir / "l.xml") << R"(<mujoco><asset><mesh file="L.obj" scale="0.125 0.125 0.125"/></asset><worldbody>
    <body name="l" pos="0 0 1"><freejoint/><geom type="mesh" mesh="L" pos="0.02 -0.01 0.03" euler="20 -30 40"/>
      <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.02"/></body></worldbody></mujoco>)";
  MjcfOptions mj222;
  mj222.mesh_inertia = Geom::MeshInertia::MuJoCo222;
  expect_same_model_file(dir / "l.xml", mj222, 1e-7);
  const Model exact = model_load_file(dir / "l.xml", "l.xml");
  const Model legacy = model_load_file(dir / "l.xml", "l.xml", mj222);
  const double capsule = 1000 * (M_PI * 0.02 * 0.02 * 0.1 + 4.0 / 3 * M_PI * 0.02 * 0.02 * 0.02);
  EXPECT_NEAR(exact.bodies[1].mass - capsule, 1000 * 3.0 / 512, 1e-9);
  EXPECT_NEAR(legacy.bodies[1].mass - capsule, 1000.0 / 512 * std::sqrt(35.0 / 3), 1e-9);
  std::filesystem::remove_all(dir);

  const auto mug = std::filesystem::path(PLIANT_MUJOCO_MODEL_DIR) / "mug/mug.xml";
  char err[1000] = "";
  mjModel* mj = mj_loadXML(mug.c_str(), nullptr, err, sizeof(err));
  ASSERT_NE(mj, nullptr) << err;
  const Model ours = model_load_file(mug, "mug.xml", mj222);
  const Model solid = model_load_file(mug, "mug.xml");
  ASSERT_EQ(static_cast<int>(ours.bodies.size()), mj->nbody);
  for (int b = 1; b < mj->nbody; ++b) {
    EXPECT_NEAR(ours.bodies[b].mass, mj->body_mass[b], 1e-6 * mj->body_mass[b]) << b;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(ours.bodies[b].com[a], mj->body_ipos[3 * b + a], 1e-7) << b;
    Eigen::SelfAdjointEigenSolver<Mat3> eig(ours.bodies[b].inertia);
    std::vector<double> mj_p(mj->body_inertia + 3 * b, mj->body_inertia + 3 * b + 3);
    std::sort(mj_p.begin(), mj_p.end());
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(eig.eigenvalues()[a], mj_p[a], 1e-6 * mj_p[2]) << b;
  }
  // The mesh is the cup body's only mesh: its solid mass is 0.133 kg of MuJoCo's 0.379.
  EXPECT_LT(solid.bodies[1].mass, mj->body_mass[1] - 0.2);
  mj_deleteModel(mj);
}

// <include> (nested, named from the main file's folder): the expanded model compiles
// as MuJoCo compiles the same files.
TEST(MujocoReference, IncludedFilesCompileAsMuJoCoCompilesThem) {
  const auto dir = std::filesystem::temp_directory_path() / ("pliant_mj_include_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "parts");
  std::ofstream(dir / "parts/leg.xml") << R"(<mujoco><body name="shin" pos="0 0 -0.3"><joint axis="1 0 0"/>
    <geom type="capsule" fromto="0 0 0 0 0.05 -0.3" size="0.03"/><include file="parts/foot.xml"/></body></mujoco>)";
  std::ofstream(dir / "parts/foot.xml") << R"(<mujoco><body name="foot" pos="0 0.05 -0.3"><joint axis="0 1 0"/>
    <geom type="box" size="0.08 0.03 0.02" pos="0.04 0 0"/></body></mujoco>)";
  std::ofstream(dir / "parts/defaults.xml") << R"(<mujoco><default><geom density="900"/></default></mujoco>)";
  std::ofstream(dir / "main.xml") << R"(<mujoco><include file="parts/defaults.xml"/><worldbody>
    <body name="thigh" pos="0 0 1"><freejoint/><geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.05"/>
    <include file="parts/leg.xml"/></body></worldbody></mujoco>)";
  const Model ours = model_load_file(dir / "main.xml", "main.xml");
  char err[1000] = "";
  mjModel* mj = mj_loadXML((dir / "main.xml").c_str(), nullptr, err, sizeof(err));
  ASSERT_NE(mj, nullptr) << err;
  ASSERT_EQ(mj->nbody, static_cast<int>(ours.bodies.size()));
  ASSERT_EQ(mj->nv, ours.nv);
  for (int b = 1; b < mj->nbody; ++b) {
    EXPECT_NEAR(ours.bodies[b].mass, mj->body_mass[b], 1e-9 * mj->body_mass[b]) << b;
    EXPECT_EQ(ours.bodies[b].parent, mj->body_parentid[b]) << b;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(ours.bodies[b].pos[a], mj->body_pos[3 * b + a], 1e-12) << b;
  }
  mj_deleteModel(mj);
  std::filesystem::remove_all(dir);
}

TEST(MujocoReference, GlobalCoordinatesCompileAsMuJoCoCompilesThem) {
  expect_same_poses_and_ranges(R"(<mujoco><compiler angle="degree" coordinate="global" inertiafromgeom="true"/>
    <default><joint armature="1" damping="1" limited="true"/><geom condim="1" margin="0.001"/></default>
    <worldbody><geom name="floor" type="plane" size="20 20 0.125" condim="3"/>
      <body name="torso" pos="0 0 1.25">
        <joint name="rootx" type="slide" axis="1 0 0" pos="0 0 0" limited="false" armature="0" damping="0"/>
        <joint name="rootz" type="slide" axis="0 0 1" pos="0 0 0" limited="false" armature="0" damping="0"/>
        <joint name="rooty" type="hinge" axis="0 1 0" pos="0 0 1.25" limited="false" armature="0" damping="0"/>
        <geom name="torso_geom" type="capsule" fromto="0 0 1.45 0 0 1.05" size="0.05"/>
        <body name="thigh" pos="0 0 1.05">
          <joint name="thigh_joint" axis="0 -1 0" pos="0 0 1.05" range="-150 0"/>
          <geom type="capsule" fromto="0 0 1.05 0 0 0.6" size="0.05"/>
          <body name="leg" pos="0 0 0.35">
            <joint name="leg_joint" axis="0 -1 0" pos="0 0 0.6" range="-150 0"/>
            <geom type="capsule" fromto="0 0 0.6 0 0 0.1" size="0.04"/>
            <body name="foot" pos="0.13 0 0.1">
              <joint name="foot_joint" axis="0 -1 0" pos="0 0 0.1" range="-45 45"/>
              <geom type="capsule" fromto="-0.13 0 0.1 0.26 0 0.1" size="0.06"/>
            </body></body></body></body></worldbody>
    <actuator><motor joint="thigh_joint" gear="200"/><motor joint="foot_joint" gear="100"/></actuator></mujoco>)");
  expect_same_poses_and_ranges(R"(<mujoco><compiler angle="radian" coordinate="global"/>
    <worldbody>
      <body name="a" pos="0.1 -0.2 1" euler="0.3 -0.2 0.9"><freejoint/>
        <geom type="box" size="0.05 0.04 0.03" pos="0.12 -0.2 1.01" quat="0.9 0.1 -0.3 0.2"/>
        <geom type="sphere" size="0.03" pos="0.1 -0.1 1"/>
        <body name="b" pos="0.3 0 1.1" axisangle="1 2 3 0.7">
          <joint name="j1" axis="0.2 1 0.3" pos="0.3 0.01 1.1"/>
          <joint name="j2" type="slide" axis="1 0 0.4" pos="0.3 0 1.1"/>
          <geom type="capsule" fromto="0.3 0 1.1 0.5 0.1 0.9" size="0.02"/>
          <geom type="box" fromto="0.3 0 1.1 0.4 0.05 1.0" size="0.01"/>
          <geom type="sphere" size="0.01"/>
          <inertial pos="0.35 0.02 1.05" mass="0.7" diaginertia="0.01 0.02 0.03" xyaxes="0 0 1 1 1 0"/>
          <body name="c" pos="0.5 0.1 0.9" xyaxes="0 1 0 -1 0 0"><joint name="j3" type="ball" pos="0.5 0.1 0.9"/>
            <geom type="sphere" size="0.04" pos="0.52 0.1 0.88"/>
            <inertial pos="0.51 0.1 0.9" mass="0.4" fullinertia="0.004 0.005 0.006 0.0001 -0.0002 0.0003"/>
          </body></body></body></worldbody></mujoco>)");
}

// Joint ref (qpos0: the value at the model pose), stiffness and springref (MuJoCo's
// passive spring) on hinges and slides, in degrees: compiled qpos0, stiffness and
// spring reference equal MuJoCo's, and the same 0.5 s under both engines' RK4 at
// dt 1 ms ends at the same joint values (the spring's sign, units and reference);
// PBAD3 ends near them too (armature included).
TEST(MujocoReference, JointRefAndSpringMatchMuJoCo) {
  const std::string xml = R"(<mujoco><option timestep="0.001" integrator="RK4"/><worldbody>
    <body pos="0 0 1"><joint name="s" type="slide" axis="0 0 1" ref="0.3" stiffness="50" springref="0.25" damping="0.5"/>
      <geom type="box" size="0.1 0.1 0.1" mass="2"/>
      <body pos="0.2 0 0"><joint name="h" type="hinge" axis="0 1 0" ref="20" stiffness="3" springref="-10" armature="0.02"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.5"/>
      </body></body></worldbody></mujoco>)";
  expect_same_poses_and_ranges(xml);
  const Model ours = model_from_mjcf(xml, "spring.xml");
  mjModel* mj = load_mujoco(xml);
  ASSERT_NE(mj, nullptr);
  ASSERT_EQ(ours.nq, mj->nq);
  for (int j = 0; j < mj->njnt; ++j) {
    EXPECT_NEAR(ours.qpos0[ours.joints[j].qadr], mj->qpos0[mj->jnt_qposadr[j]], 1e-12) << "joint " << j;
    EXPECT_NEAR(ours.joints[j].stiffness, mj->jnt_stiffness[j], 1e-12) << "joint " << j;
    EXPECT_NEAR(ours.joints[j].springref, mj->qpos_spring[mj->jnt_qposadr[j]], 1e-12) << "joint " << j;
  }
  mjData* d = mj_makeData(mj);
  mj_resetData(mj, d);
  SimOptions o;
  o.integrator = Integrator::Rk4;
  o.dt = 0.001;
  o.contact.enabled = false;
  State s = state_init(ours);
  SimWorkspace ws;
  for (int i = 0; i < 500; ++i) {
    mj_step(mj, d);
    sim_step(ours, o, s, ws);
  }
  // The spring moved both joints away from their start (q0 = ref).
  EXPECT_GT(std::abs(d->qpos[0] - 0.3), 0.01);
  EXPECT_GT(std::abs(d->qpos[1] - 20 * M_PI / 180), 0.01);
  for (int i = 0; i < mj->nq; ++i) EXPECT_NEAR(s.qpos[i], d->qpos[i], 1e-8) << "qpos " << i;
  // PBAD (its own armature, spring and damping terms) at the same dt follows within
  // its discretisation error (second order: ~1e-4 here; without the armature in its
  // energy: 0.0094 m on the slide and 0.42 rad on the hinge).
  SimOptions po = o;
  po.integrator = Integrator::Pbad3;
  State ps = state_init(ours);
  for (int i = 0; i < 500; ++i) ASSERT_TRUE(sim_step(ours, po, ps, ws));
  for (int i = 0; i < mj->nq; ++i) EXPECT_NEAR(ps.qpos[i], d->qpos[i], 1e-3) << "pbad3 qpos " << i;
  mj_deleteData(d);
  mj_deleteModel(mj);
}

// Geom contact parameters (friction's sliding value, margin, condim, priority), set
// directly, through nested default classes, class= and childclass=, compile to
// MuJoCo's geom_friction / geom_margin / geom_condim / geom_priority (by geom name).
// A geom without friction is unset in Pliant (the scene's contact.mu stands in for
// it) where MuJoCo holds its default 1.
TEST(MujocoReference, GeomContactParametersMatch) {
  const std::string xml = R"(<mujoco>
    <default><geom margin="0.001"/>
      <default class="rubber"><geom friction="1.3 0.01 0.0002" condim="3"/>
        <default class="slick"><geom friction="0.05" condim="1" priority="2"/></default></default></default>
    <worldbody><geom name="floor" type="plane" size="1 1 0.1" friction="0.9" margin="0.004"/>
      <geom name="wall" type="box" size="0.1 1 1" pos="2 0 0"/>
      <body name="a" childclass="rubber"><freejoint/><geom name="a0" type="box" size="0.1 0.1 0.1"/>
        <geom name="a1" class="slick" size="0.05" pos="0 0 0.2"/>
        <geom name="a2" size="0.05" pos="0 0 -0.2" margin="0.02" priority="-1"/>
        <body name="b"><joint type="hinge"/><geom name="b0" class="main" type="capsule" size="0.02 0.1"/></body>
      </body>
    </worldbody></mujoco>)";
  const Model ours = model_from_mjcf(xml, "model.xml");
  mjModel* mj = load_mujoco(xml);
  ASSERT_NE(mj, nullptr);
  ASSERT_EQ(mj->ngeom, static_cast<int>(ours.geoms.size()));
  for (const Geom& g : ours.geoms) {
    const int id = mj_name2id(mj, mjOBJ_GEOM, g.name.c_str());
    ASSERT_GE(id, 0) << g.name;
    if (g.friction >= 0) EXPECT_EQ(g.friction, mj->geom_friction[3 * id]) << g.name;
    else EXPECT_EQ(mj->geom_friction[3 * id], 1.0) << g.name;
    EXPECT_EQ(g.margin, mj->geom_margin[id]) << g.name;
    EXPECT_EQ(g.condim, mj->geom_condim[id]) << g.name;
    EXPECT_EQ(g.priority, mj->geom_priority[id]) << g.name;
  }
  mj_deleteModel(mj);
}

// Torsional / rolling friction: geom condim 4 / 6 and friction's 2nd / 3rd values
// (MuJoCo's defaults 0.005 / 0.0001 where not given), and a pair's condim and
// friction's 3rd / 4th values, compile to MuJoCo's geom_condim / geom_friction and
// pair_dim / pair_friction.
TEST(MujocoReference, GeomCondimFourSixMatch) {
  const std::string xml = R"(<mujoco>
    <default><default class="spin"><geom condim="6" friction="0.8 0.02 0.003"/></default></default>
    <worldbody><geom name="floor" type="plane" size="1 1 0.1" condim="4" friction="0.9 0.01"/>
      <body name="a"><freejoint/><geom name="a0" size="0.05" class="spin"/><geom name="a1" size="0.05" pos="0 0 0.2" condim="4"/></body>
      <body name="b" pos="1 0 0"><freejoint/><geom name="b0" size="0.05" condim="6" friction="0.3"/></body>
    </worldbody>
    <contact><pair geom1="a0" geom2="b0" condim="6" friction="0.4 0.4 0.03 0.002 0.002"/>
      <pair geom1="a1" geom2="b0" condim="4"/></contact></mujoco>)";
  const Model ours = model_from_mjcf(xml, "model.xml");
  mjModel* mj = load_mujoco(xml);
  ASSERT_NE(mj, nullptr);
  for (const Geom& g : ours.geoms) {
    const int id = mj_name2id(mj, mjOBJ_GEOM, g.name.c_str());
    ASSERT_GE(id, 0) << g.name;
    EXPECT_EQ(g.condim, mj->geom_condim[id]) << g.name;
    EXPECT_EQ(g.torsion, mj->geom_friction[3 * id + 1]) << g.name;
    EXPECT_EQ(g.roll, mj->geom_friction[3 * id + 2]) << g.name;
  }
  ASSERT_EQ(mj->npair, 2);
  ASSERT_EQ(ours.contact_pairs.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(ours.contact_pairs[i].condim, mj->pair_dim[i]) << i;
    EXPECT_EQ(ours.contact_pairs[i].torsion, mj->pair_friction[5 * i + 2]) << i;
    EXPECT_EQ(ours.contact_pairs[i].roll, mj->pair_friction[5 * i + 3]) << i;
  }
  mj_deleteModel(mj);
}

// The same spin-down and roll-out as test_spin_friction.cpp in MuJoCo 2.2.2 itself
// (elliptic cone, dt 1e-3): MuJoCo's torsional / rolling friction limits the torque at
// torsion f_n / roll f_n, so its spinner stops at about w0 I / (mu_t m g) and its ball
// after about v0^2 (I + m r^2) / (2 mu_r m g r), the answers Pliant's potential is tested
// against. MuJoCo's soft constraints (default solref / solimp) let the contact give
// way, so it is approximate: measured spinner 0.4750 s (+16.5%), roller 0.1849 m
// (+3.6%); bounds 20% / 6%: a check that the coefficients mean the same thing (a
// factor 2 or a radius in the torque would fail), not an agreement figure.
double mujoco_spin_roll(const std::string& attrs, double w0, double v0, double t_end, double* x_end) {
  const std::string xml = "<mujoco><option timestep=\"0.001\" cone=\"elliptic\"/><worldbody>"
                          "<geom type=\"plane\" size=\"5 5 0.1\"/><body pos=\"0 0 0.1\"><freejoint/>"
                          "<geom type=\"sphere\" size=\"0.1\" mass=\"1\" " + attrs + "/></body></worldbody></mujoco>";
  mjModel* mj = load_mujoco(xml);
  if (!mj) return -1;
  mjData* d = mj_makeData(mj);
  d->qvel[0] = v0;
  d->qvel[4] = v0 / 0.1;
  d->qvel[5] = w0;
  double t_stop = -1;
  while (d->time < t_end) {
    mj_step(mj, d);
    if (t_stop < 0 && w0 > 0 && d->qvel[5] < 0.01 * w0) t_stop = d->time;
  }
  *x_end = d->qpos[0];
  mj_deleteData(d);
  mj_deleteModel(mj);
  return t_stop;
}

TEST(MujocoReference, SpinAndRollStopWhereTheAnalyticAnswersSay) {
  double x;
  const double t = mujoco_spin_roll("condim=\"4\" friction=\"1 0.01 0\"", 10, 0, 0.6, &x);
  const double roll_stop = 0.25 * 1.4 * 0.1 / (2 * 0.01 * 9.81);
  double x_roll;
  mujoco_spin_roll("condim=\"6\" friction=\"1 0 0.01\"", 0, 0.5, 1.0, &x_roll);
  std::printf("MuJoCo: spinner stops at %.4f s (analytic %.4f), roller at %.4f m (analytic %.4f)\n", t,
              10 * 0.004 / (0.01 * 9.81), x_roll, roll_stop);
  EXPECT_NEAR(t, 10 * 0.004 / (0.01 * 9.81), 0.2 * 0.4077);
  EXPECT_NEAR(x_roll, roll_stop, 0.06 * roll_stop);
}

}  // namespace
}  // namespace pliant::articulated

namespace pliant::articulated {
namespace {

// Joint frictionloss means the same in both engines: the rotor of
// test_joint_friction.cpp (I = 0.01, w0 = 5 rad/s, F = 0.02 N m: stops after 2.5 s at
// 6.25 rad) in MuJoCo 2.2.2 (Euler, dt 1e-3) and in Pliant's PBAD3 at the same dt.
// MuJoCo's friction constraint is soft (default solreffriction); measured: stops at
// 2.476 s, 6.2476 rad. Pliant's PBAD3 at the same dt ends within 1% of it.
TEST(MujocoReference, JointFrictionlossSpinsDownAsInMuJoCo) {
  const std::string xml = R"(<mujoco><option timestep="0.001"/><worldbody><body>
      <joint axis="0 0 1" frictionloss="0.02"/>
      <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/></body></worldbody></mujoco>)";
  mjModel* mj = load_mujoco(xml);
  ASSERT_NE(mj, nullptr);
  EXPECT_NEAR(mj->dof_frictionloss[0], model_from_mjcf(xml, "rotor.xml").joints[0].frictionloss, 1e-15);
  mjData* d = mj_makeData(mj);
  d->qvel[0] = 5;
  double t_stop = -1;
  while (d->time < 3.0) {
    mj_step(mj, d);
    if (t_stop < 0 && d->qvel[0] < 0.01 * 5) t_stop = d->time;
  }
  const double angle = d->qpos[0];
  std::printf("MuJoCo: rotor stops at %.4f s (analytic 2.5), angle %.4f rad (analytic 6.25)\n", t_stop, angle);
  EXPECT_NEAR(t_stop, 2.5, 0.02 * 2.5);
  EXPECT_NEAR(angle, 6.25, 0.01 * 6.25);
  const Model ours = model_from_mjcf(xml, "rotor.xml");
  const SimOptions o = test::contact_free_options(Integrator::Pbad3, 0.001);
  State s = state_init(ours);
  s.qvel[0] = 5;
  SimWorkspace ws;
  while (s.time < 3.0 - 1e-9) ASSERT_TRUE(sim_step(ours, o, s, ws));
  EXPECT_NEAR(s.qpos[0], angle, 0.01 * angle);
  mj_deleteData(d);
  mj_deleteModel(mj);
}

}  // namespace
}  // namespace pliant::articulated
