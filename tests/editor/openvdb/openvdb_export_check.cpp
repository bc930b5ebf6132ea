// The "vdb" exporter plugin (plugins/openvdb_export): a 3D keyframe take exported
// with `pliant export --format vdb` reads back with OpenVDB as the same density:
// one file per frame, active voxels = cells >= 1e-4, same values.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "pliant/core/take.h"

namespace fs = std::filesystem;

TEST(OpenVdbExport, ThreeDTakeReadsBackVoxelForVoxel) {
  fs::path dir = fs::temp_directory_path() / ("pliant-vdb-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string pliant = PLIANT_BIN;
  const std::string scene = std::string(PLIANT_EDITOR_TEST_DIR) + "/scenes/keyframe_3d.json";
  ASSERT_EQ(std::system((pliant + " run " + scene + " --take " + (dir / "take").string() +
                         " --threads 1 > /dev/null").c_str()), 0);
  ASSERT_EQ(std::system((pliant + " export " + (dir / "take").string() + " --format vdb --out " +
                         (dir / "vdb").string() + " > /dev/null").c_str()), 0);
  pliant::TakeReader take(dir / "take");
  ASSERT_EQ(take.frame_count(), 11u);
  openvdb::initialize();
  for (size_t f = 0; f < take.frame_count(); f += 5) {
    pliant::Record r = take.read_frame_at(f);
    const pliant::Field* d = r.find("density");
    ASSERT_NE(d, nullptr);
    ASSERT_EQ(d->shape.size(), 3u);
    char name[64];
    std::snprintf(name, sizeof name, "frame_%05d.vdb", int(r.index));
    openvdb::io::File file((dir / "vdb" / name).string());
    file.open();
    openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
    file.close();
    ASSERT_TRUE(grid);
    const int nz = int(d->shape[0]), ny = int(d->shape[1]), nx = int(d->shape[2]);
    size_t expected_active = 0;
    auto acc = grid->getConstAccessor();
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const float v = d->data[(size_t(k) * ny + j) * nx + i];
          if (v >= 1e-4f) {
            ++expected_active;
            ASSERT_EQ(acc.getValue(openvdb::Coord(i, j, k)), v) << i << "," << j << "," << k;
          }
        }
    EXPECT_GT(expected_active, 0u);
    EXPECT_EQ(grid->activeVoxelCount(), expected_active) << name;
    EXPECT_NEAR(grid->voxelSize()[0], 1.0 / 16, 1e-12);
  }
  fs::remove_all(dir);
}
