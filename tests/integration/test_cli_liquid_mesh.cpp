// `pliant validate` on liquid scenes with mesh containers: a closed mesh (the
// shipped mug) validates; a mesh with a hole, or a file that cannot be loaded,
// exits 2 naming the mesh file and the problem.
#include "cli_fixture.h"

namespace pliant::test {
namespace {

class LiquidMeshCli : public CliTest {};

nlohmann::json mesh_scene(const nlohmann::json& container) {
  return {{"pliant", 1},
          {"kind", "liquid"},
          {"dim", 2},
          {"domain", {{"min_m", {-0.1, 0}}, {"max_m", {0.3, 0.3}}, {"cell_size_m", 0.01}}},
          {"time", {{"frames", 2}}},
          {"source", {{"container", container}, {"position_m", {0, 0.05}}}}};
}

TEST_F(LiquidMeshCli, ClosedMeshValidatesOpenMeshExitsTwo) {
  const fs::path good = write_scene(
      "mug.json", mesh_scene((kRepo / "assets/containers/mug.json").string()));
  const ProcessResult ok = pliant({"validate", good.string()});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;

  const fs::path open = write_scene(
      "open.json", mesh_scene({{"shape", "mesh"}, {"file", (kRepo / "tests/meshes/open_box.obj").string()}}));
  const ProcessResult r = pliant({"validate", open.string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "open_box.obj")) << r.err;
  EXPECT_TRUE(contains(r.err, "not closed")) << r.err;
  EXPECT_TRUE(contains(r.err, "/source/container/file")) << r.err;

  const fs::path missing = write_scene("missing.json", mesh_scene({{"shape", "mesh"}, {"file", "no_such_mug.obj"}}));
  const ProcessResult m = pliant({"validate", missing.string()});
  EXPECT_EQ(m.exit_code, 2) << m.err;
  EXPECT_TRUE(contains(m.err, "no_such_mug.obj")) << m.err;
}

}  // namespace
}  // namespace pliant::test
