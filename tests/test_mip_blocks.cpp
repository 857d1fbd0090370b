// Mip levels reduced on voxel blocks from a scene read as leaves, written by
// the direct writer (libvox/scene/mip_blocks.h, formats/vdb/pyramid_direct.h),
// against OpenVDB's path (reduceScene, writePyramidVdb) on content the
// command-line matrix (tests/cli/lightmip_test.sh) rarely reaches: vote sums
// that saturate, odd dims under majority, colour on some voxels only, a
// region part's box. The bytes are compared there; here the levels as scenes.
#include <gtest/gtest.h>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <fstream>
#include <iterator>

#include "formats/vdb/pyramid_direct.h"
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/scene/mip.h"
#include "libvox/scene/scene_diff.h"
#include "test_util.h"

namespace {

using namespace vox;

SceneHeader header(Dims dims) {
  SceneHeader h;
  h.dims = dims;
  h.voxelSize = 0.05;
  h.origin = {-1.0, 0.5, 2.0};
  h.classes.add({1, "stone", {120, 120, 120}, std::nullopt});
  h.classes.add({3, "grass", {80, 170, 90}, std::nullopt});
  h.classes.add({9, "water", {40, 80, 200}, std::nullopt});
  return h;
}

/// Scattered voxels of up to three classes (some at the saturating count),
/// colour on about half, a solid 16^3 box whose level-1 and level-2 sums
/// saturate, voxels on the last slice of odd dims.
Scene makeScene(const SceneHeader& h, uint64_t seed) {
  SceneBuilder b(h);
  uint64_t x = seed;
  auto next = [&] {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    return x;
  };
  const uint8_t ids[3] = {1, 3, 9};
  const Dims d = h.dims;
  for (int i = 0; i < 4000; ++i) {
    const Coord3 c{int32_t(next() % d.x), int32_t(next() % d.y), int32_t(next() % d.z)};
    const uint32_t votes = next() % 5 == 0 ? kMaxVotesPerClass : uint32_t(1 + next() % 100000);
    b.addVotes(c, ids[next() % 3], votes, next() % 3 != 0);
    if (next() % 2) b.setColor(c, {float(next() % 1000) / 999.0f, 0.25f, float(next() % 7) / 6.0f});
  }
  if (d.x >= 24 && d.y >= 24 && d.z >= 24)
    for (int32_t u = 8; u < 24; ++u)
      for (int32_t v = 8; v < 24; ++v) b.addRun({u, v, 8}, 16, 3, kMaxVotesPerClass / 3, u == 8);
  for (int32_t u = 0; u < int32_t(d.x); u += 3) b.addVotes({u, int32_t(d.y) - 1, int32_t(d.z) - 1}, 9, 7, true);
  return std::move(b).build();
}

/// Reads `path` as leaves and writes its pyramid without OpenVDB (as `vox mip`'s light path does).
std::vector<MipBlocksLevel> directPyramid(const std::string& path, MipOccupancy occ, int levels, unsigned threads,
                                          const std::string& out) {
  std::optional<SceneLeaves> leaves = readSceneLeaves(path);
  EXPECT_TRUE(leaves && leaves->plainForm);
  std::optional<MipBlocksLevel> base = mipBlocksFromLeaves(std::move(*leaves), threads);
  EXPECT_TRUE(base);
  std::vector<MipBlocksLevel> all;
  all.push_back(std::move(*base));
  for (int n = 1; n <= levels; ++n) all.push_back(reduceBlocks(all.back(), occ, threads));
  std::vector<const MipBlocksLevel*> ptrs;
  for (const MipBlocksLevel& l : all) ptrs.push_back(&l);
  writePyramidVdbDirect(ptrs, occ, out, threads);
  return all;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(MipBlocks, LevelsEqualReduceSceneOnSaturatedColouredOddScenes) {
  voxtest::TempDir dir;
  for (const Dims dims : {Dims{45, 37, 29}, Dims{64, 64, 64}, Dims{33, 1, 70}}) {
    SceneHeader h = header(dims);
    const Scene scene = makeScene(h, 0x9e3779b97f4a7c15ull + dims.x);
    const std::string in = dir.file("in.vdb");
    writeSceneVdb(scene, in);
    for (MipOccupancy occ : {MipOccupancy::Any, MipOccupancy::Majority}) {
      SCOPED_TRACE(toString(dims) + " " + mipOccupancyName(occ));
      const int levels = maxMipLevels(dims);
      MipSettings settings;
      settings.occupancy = occ;
      settings.levels = levels;
      const std::vector<Scene> expected = buildMipPyramid(scene, settings);
      const std::string out1 = dir.file("d1.vdb"), out3 = dir.file("d3.vdb");
      directPyramid(in, occ, levels, 1, out1);
      const std::vector<MipBlocksLevel> blocks = directPyramid(in, occ, levels, 3, out3);
      EXPECT_EQ(readAll(out1), readAll(out3)) << "the bytes depend on the thread count";
      const std::vector<Scene> got = readPyramidVdb(out1);
      ASSERT_EQ(got.size(), expected.size() + 1);
      EXPECT_TRUE(diffScenes(got[0], scene).same());
      for (size_t n = 0; n < expected.size(); ++n) {
        const SceneDiff diff = diffScenes(got[n + 1], expected[n]);
        EXPECT_TRUE(diff.same()) << "level " << n + 1 << ": " << diff.voxelsDiffering << " voxels differ";
        EXPECT_EQ(blocks[n + 1].occupiedCount(), expected[n].occupiedCount());
        EXPECT_EQ(got[n + 1].hasColor(), expected[n].hasColor()) << "level " << n + 1;
        EXPECT_EQ(got[n + 1].classesPresent(), expected[n].classesPresent()) << "level " << n + 1;
      }
    }
  }
}

TEST(MipBlocks, RegionPartBoxesShrinkAsReduceSceneShrinksThem) {
  SceneHeader h = header({40, 40, 40});
  h.region = SceneRegion{};
  h.region->box = {{9, 0, 17}, {38, 31, 39}};
  const SceneHeader c = coarserMipHeader(h);
  EXPECT_EQ(c.dims, (Dims{20, 20, 20}));
  EXPECT_EQ(c.voxelSize, 0.1);
  EXPECT_EQ(c.mipLevel, 1);
  EXPECT_EQ(c.region->box.min, (Coord3{4, 0, 8}));
  EXPECT_EQ(c.region->box.max, (Coord3{19, 15, 19}));
}

TEST(MipBlocks, GridMetadataVoxbakeDoesNotWriteIsNotPlain) {
  voxtest::TempDir dir;
  const std::string path = dir.file("s.vdb"), edited = dir.file("e.vdb");
  writeSceneVdb(makeScene(header({24, 24, 24}), 7), path);
  std::optional<SceneLeaves> plain = readSceneLeaves(path);
  ASSERT_TRUE(plain);
  EXPECT_TRUE(plain->plainForm);
  // The same scene with a user's key on the occupancy grid: a rewrite through
  // OpenVDB keeps it, blocks cannot, so `vox mip` leaves the file to vox-cmds.so.
  openvdb::initialize();
  openvdb::io::File file(path);
  file.open();
  openvdb::GridPtrVec grids = *file.getGrids();
  const openvdb::MetaMap::Ptr meta = file.getMetadata();
  file.close();
  for (auto& g : grids)
    if (g->getName() == "occupancy") g->insertMeta("user_note", openvdb::StringMetadata("kept by a rewrite"));
  openvdb::io::File out(edited);
  out.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
  out.write(grids, *meta);
  out.close();
  std::optional<SceneLeaves> leaves = readSceneLeaves(edited);
  ASSERT_TRUE(leaves);
  EXPECT_FALSE(leaves->plainForm);
  EXPECT_FALSE(mipBlocksFromLeaves(std::move(*leaves)));
}

}  // namespace
