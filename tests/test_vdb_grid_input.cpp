// OpenVDB level sets and fog volumes as scene inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <openvdb/io/File.h>
#include <openvdb/tools/LevelSetSphere.h>

#include "formats/core/file_util.h"
#include "formats/vdb/vdb_grid_input.h"
#include "libvox/scene/scene_grids.h"
#include "test_util.h"

using namespace vox;

namespace {
void writeGrid(const std::string& path, openvdb::GridBase::Ptr g) {
  openvdb::io::File f(path);
  f.write({g});
  f.close();
}
}  // namespace

TEST(VdbGridInput, LevelSetSphereVolume) {
  ensureOpenVdbInitialized();
  voxtest::TempDir dir;
  auto ls = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(10.0f, openvdb::Vec3f(1, 2, 3), 0.25f);
  ls->setName("ball");
  writeGrid(dir.file("ball.vdb"), ls);
  VdbGridInputOptions o;
  o.voxelSize = 0.5;
  o.threads = 2;
  const Scene s = readVdbGridAsScene(dir.file("ball.vdb"), o);
  // Analytic: (4/3) pi r^3 / voxel volume, within 3% at 20 voxels per radius.
  const double want = 4.0 / 3.0 * M_PI * 1000.0 / 0.125;
  EXPECT_NEAR(double(s.occupiedCount()), want, want * 0.03);
  EXPECT_EQ(s.header().classes.find(1)->name, "ball");
  // 20 voxels of 0.5 per radius; the box of inside input voxels is up to one
  // input voxel (0.25) wider.
  EXPECT_GE(s.header().dims.x, 40u);
  EXPECT_LE(s.header().dims.x, 41u);
  ASSERT_EQ(s.header().sources.size(), 1u);
  EXPECT_EQ(s.header().sources[0].kind, "vdb");
  // Same with --res: 40 voxels on the longest axis.
  VdbGridInputOptions r;
  r.resolution = 40;
  const Scene s2 = readVdbGridAsScene(dir.file("ball.vdb"), r);
  EXPECT_EQ(std::max({s2.header().dims.x, s2.header().dims.y, s2.header().dims.z}), 40u);
  EXPECT_NEAR(double(s2.occupiedCount()), double(s.occupiedCount()), 0.05 * double(s.occupiedCount()));
  // A threshold would change nothing on a level set (its sign is the inside): refused, naming the setting.
  r.threshold = 0.5;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readVdbGridAsScene(dir.file("ball.vdb"), r); }, ErrorKind::Usage,
                                      {"ball.vdb", "grid 'ball' is a level set", "drop the threshold"}));
  try {
    readVdbGridAsScene(dir.file("ball.vdb"), r);
  } catch (const Error& e) {
    EXPECT_EQ(e.setting, Setting::GridThreshold) << "the CLI names --threshold";
  }
}

TEST(VdbGridInput, FogNeedsAThresholdAndBadFilesAreNamed) {
  ensureOpenVdbInitialized();
  voxtest::TempDir dir;
  auto fog = openvdb::FloatGrid::create(0.0f);
  fog->setName("density");
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 3; ++z) fog->tree().setValue(openvdb::Coord(x, y, z), x < 5 ? 1.0f : 0.1f);
  writeGrid(dir.file("fog.vdb"), fog);
  VdbGridInputOptions o;
  o.voxelSize = 1.0;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readVdbGridAsScene(dir.file("fog.vdb"), o); }, ErrorKind::Usage,
                                      {"density", "not a level set", "threshold"}));
  try {
    readVdbGridAsScene(dir.file("fog.vdb"), o);
  } catch (const Error& e) {
    EXPECT_EQ(e.setting, Setting::GridThreshold) << "the CLI names the option";
  }
  o.threshold = 0.5;
  const Scene s = readVdbGridAsScene(dir.file("fog.vdb"), o);
  EXPECT_EQ(s.occupiedCount(), 5u * 4 * 3);
  EXPECT_EQ(s.header().dims, (Dims{5, 4, 3}));
  o.gridName = "smoke";
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readVdbGridAsScene(dir.file("fog.vdb"), o); }, ErrorKind::BadInput,
                                      {"no grid named 'smoke'", "density"}));
  const std::string bytes = readFileBytes(dir.file("fog.vdb"));
  voxtest::writeText(dir.file("cut.vdb"), bytes.substr(0, bytes.size() - 10));
  o.gridName.clear();
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readVdbGridAsScene(dir.file("cut.vdb"), o); }, ErrorKind::BadInput,
                                      {"cut.vdb", "truncated"}));
}

// Double grids (written by some solvers and by Houdini at 64-bit precision)
// are read like float ones, compared in double: a density of 0.0999999999 is
// below a threshold of 0.1 although it rounds to 0.1f as a float.
TEST(VdbGridInput, DoubleGridsAreReadInTheirOwnPrecision) {
  ensureOpenVdbInitialized();
  voxtest::TempDir dir;
  auto fog = openvdb::DoubleGrid::create(0.0);
  fog->setName("density");
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 3; ++z) fog->tree().setValue(openvdb::Coord(x, y, z), x < 5 ? 0.1 : 0.0999999999);
  writeGrid(dir.file("fog64.vdb"), fog);
  VdbGridInputOptions o;
  o.voxelSize = 1.0;
  o.threshold = 0.1;
  const Scene s = readVdbGridAsScene(dir.file("fog64.vdb"), o);
  EXPECT_EQ(s.occupiedCount(), 5u * 4 * 3);
  EXPECT_EQ(s.header().dims, (Dims{5, 4, 3}));
  EXPECT_EQ(s.header().classes.find(1)->name, "density");

  // A double level set: the same voxels as the float sphere of the same shape
  // but where the two precisions round a distance across zero.
  auto ls64 = openvdb::tools::createLevelSetSphere<openvdb::DoubleGrid>(6.0, openvdb::Vec3d(0.3, 0.2, 0.1), 0.25);
  auto ls32 = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(6.0f, openvdb::Vec3f(0.3f, 0.2f, 0.1f), 0.25f);
  writeGrid(dir.file("ball64.vdb"), ls64);
  writeGrid(dir.file("ball32.vdb"), ls32);
  VdbGridInputOptions r;
  r.resolution = 48;
  const Scene a = readVdbGridAsScene(dir.file("ball64.vdb"), r), b = readVdbGridAsScene(dir.file("ball32.vdb"), r);
  EXPECT_EQ(a.header().dims, b.header().dims);
  EXPECT_NEAR(double(a.occupiedCount()), double(b.occupiedCount()), 1e-3 * double(b.occupiedCount()));
  const double want = 4.0 / 3.0 * M_PI * 216.0 / std::pow(a.header().voxelSize, 3);
  EXPECT_NEAR(double(a.occupiedCount()), want, want * 0.03);

  // Other value types are refused by name, with what is read.
  auto v = openvdb::Vec3SGrid::create();
  v->setName("velocity");
  v->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1, 0, 0));
  writeGrid(dir.file("vel.vdb"), v);
  VdbGridInputOptions q;
  q.voxelSize = 1.0;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readVdbGridAsScene(dir.file("vel.vdb"), q); }, ErrorKind::BadInput,
                                      {"vel.vdb", "no float or double grid", "velocity"}));
  q.gridName = "velocity";
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readVdbGridAsScene(dir.file("vel.vdb"), q); }, ErrorKind::BadInput,
                                      {"velocity", "vec3s", "float and double grids"}));
}
