#include <gtest/gtest.h>

#include "pliant/core/error.h"
#include "pliant/core/scene.h"
#include "pliant/smoke/smoke.h"

namespace pliant::smoke {
namespace {

Scene scene_from(const std::string& text) { return parse_scene(text, "test.json"); }

// The pointer of the InputError thrown when compiling `text` ("" if none thrown).
std::string error_pointer(const std::string& text) {
  try {
    smoke_compile(scene_from(text));
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "test.json");
    return e.pointer();
  }
  return "<no error>";
}

const char* kMinimal2D = R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6]}})";

TEST(SmokeCompile, DefaultSceneCompiles) {
  const SmokeModel m = smoke_compile(load_scene(PLIANT_ASSETS_DIR "/scenes/plume_2d.json"));
  EXPECT_EQ(m.dim, 2);
  EXPECT_EQ(m.n[0], 96);
  EXPECT_EQ(m.n[1], 128);
  EXPECT_EQ(m.n[2], 1);
  EXPECT_DOUBLE_EQ(m.cell_size_m, 0.01);
  EXPECT_EQ(m.boundary, Boundary::Closed);
  EXPECT_EQ(m.frames, 100);
  EXPECT_EQ(m.advection, Advection::SemiLagrangian);
  EXPECT_DOUBLE_EQ(m.buoyancy_m_per_s2, 2.0);
  ASSERT_EQ(m.sources.size(), 1u);
  EXPECT_DOUBLE_EQ(m.sources[0].shape.radius_m, 0.07);
  EXPECT_DOUBLE_EQ(m.sources[0].velocity_m_per_s[1], 0.4);
  EXPECT_DOUBLE_EQ(m.sources[0].end_s, 1.5);
  ASSERT_EQ(m.forces.size(), 1u);
  EXPECT_EQ(m.forces[0].type, ForceField::Vortex);
  EXPECT_DOUBLE_EQ(m.forces[0].strength_per_s, 1.5);
  const SmokeModel m3 = smoke_compile(load_scene(PLIANT_ASSETS_DIR "/scenes/plume_3d.json"));
  EXPECT_EQ(m3.dim, 3);
  EXPECT_EQ(m3.n[2], 32);
}

TEST(SmokeCompile, DefaultsComeFromTheModel) {
  const SmokeModel m = smoke_compile(scene_from(kMinimal2D));
  const SmokeModel d;
  EXPECT_EQ(m.dt_s, d.dt_s);
  EXPECT_EQ(m.frames, d.frames);
  EXPECT_EQ(m.pressure_solver, d.pressure_solver);
  EXPECT_EQ(m.pressure_tolerance, d.pressure_tolerance);
  EXPECT_EQ(m.buoyancy_m_per_s2, d.buoyancy_m_per_s2);
  EXPECT_EQ(smoke_job_frames(scene_from(kMinimal2D)), d.frames + 1);  // + the initial state
}

TEST(SmokeCompile, ReadsEveryOption) {
  const SmokeModel m = smoke_compile(scene_from(R"({"pliant":1,"kind":"smoke","name":"x",
    "grid":{"resolution":[8,6,4],"cell_size_m":0.5,"boundary":"periodic"},
    "time":{"dt_s":0.1,"frames":3,"substeps":2}, "advection":"upwind", "buoyancy_m_per_s2":0,
    "gravity_m_per_s2":[0,-9.8,0], "pressure":{"solver":"jacobi_pcg","tolerance":1e-4,"max_iterations":7},
    "sources":[{"shape":"box","center_m":[1,1,1],"half_size_m":[1,2,3]}],
    "forces":[{"type":"uniform","acceleration_m_per_s2":[1,0,0]},
              {"type":"vortex","center_m":[1,2,1],"radius_m":1,"strength_per_s":3}],
    "initial_density":[{"shape":"sphere","center_m":[2,2,2],"radius_m":1}],
    "output":{"velocity":false,"every":2}})"));
  EXPECT_EQ(m.dim, 3);
  EXPECT_EQ(m.boundary, Boundary::Periodic);
  EXPECT_EQ(m.substeps, 2);
  EXPECT_EQ(m.advection, Advection::Upwind);
  EXPECT_EQ(m.gravity_m_per_s2[1], -9.8);
  EXPECT_EQ(m.pressure_solver, PressureSolver::JacobiPCG);
  EXPECT_EQ(m.pressure_max_iterations, 7);
  EXPECT_EQ(m.sources[0].shape.type, Shape::Box);
  EXPECT_EQ(m.sources[0].shape.half_size_m[2], 3);
  EXPECT_EQ(m.forces[1].radius_m, 1);
  EXPECT_EQ(m.initial_density.size(), 1u);
  EXPECT_FALSE(m.write_velocity);
  EXPECT_EQ(m.write_every, 2);
}

TEST(SmokeCompile, BadInputNamesThePointer) {
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[-8,6]}})"), "/grid/resolution/0");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6,4,2]}})"), "/grid/resolution");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{}})"), "/grid/resolution");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke"})"), "/grid");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6]},"gravity_m_per_s2":[0,-9.8,0]})"),
            "/gravity_m_per_s2");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6]},
      "sources":[{"radius_m":1},{"center_m":[1,2,3],"radius_m":1}]})"), "/sources/1/center_m");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6,5]},
      "forces":[{"type":"vortex","center_m":[1,2],"radius_m":1}]})"), "/forces/0/center_m");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6],"resoluton":1}})"),
            "/grid/resoluton");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6]},"time":{"dt_s":0}})"),
            "/time/dt_s");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6]},"pressure":{"tolerance":1}})"),
            "/pressure/tolerance");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6]},"advection":"upwnd"})"),
            "/advection");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6]},
      "initial_density":[{"shape":"box","center_m":[1,1]}]})"), "/initial_density/0/half_size_m");
  EXPECT_EQ(error_pointer(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6]},
      "output":{"every":0}})"), "/output/every");
}

TEST(SmokeCompile, UnknownFieldSuggestsTheNearestName) {
  try {
    smoke_compile(scene_from(R"({"pliant":1,"kind":"smoke","grid":{"resolution":[8,6]},"bouyancy_m_per_s2":1})"));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/bouyancy_m_per_s2");
    EXPECT_NE(std::string(e.what()).find("buoyancy_m_per_s2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pliant::smoke
