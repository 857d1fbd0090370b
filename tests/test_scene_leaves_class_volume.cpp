// The class volume of a scene read as leaves (formats/vdb/scene_leaves_class_volume.h,
// what the light export module exports) against the one built from OpenVDB's
// trees (libvox/scene/class_volume_scene.h): the same bricks, classes (ties
// to the lowest id), colours and colour bits, for the whole domain, regions
// cutting bricks, an empty region, and at several thread counts. The bytes
// of whole exports are compared in tests/cli/lightexport_test.sh.
#include <gtest/gtest.h>

#include "formats/vdb/scene_leaves_class_volume.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/scene/class_volume_scene.h"
#include "test_util.h"

namespace {

using namespace vox;

/// Scattered voxels of three classes with vote ties between classes (a tie
/// keeps the lowest id), saturated counts, colour on about half of them.
Scene tiedScene() {
  SceneHeader h;
  h.dims = {45, 37, 29};
  h.voxelSize = 0.05;
  h.origin = {-1.0, 0.5, 2.0};
  h.classes.add({1, "stone", {120, 120, 120}, std::nullopt});
  h.classes.add({3, "grass", {80, 170, 90}, std::nullopt});
  h.classes.add({9, "water", {40, 80, 200}, std::nullopt});
  SceneBuilder b(h);
  uint64_t x = 0x2545F4914F6CDD1Dull;
  auto next = [&] {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    return x;
  };
  const uint8_t ids[3] = {1, 3, 9};
  for (int i = 0; i < 3000; ++i) {
    const Coord3 c{int32_t(next() % h.dims.x), int32_t(next() % h.dims.y), int32_t(next() % h.dims.z)};
    const uint32_t votes = next() % 7 == 0 ? kMaxVotesPerClass : uint32_t(1 + next() % 4);  // small counts tie often
    b.addVotes(c, ids[next() % 3], votes, next() % 2 == 0);
    if (next() % 2 == 0) b.addVotes(c, ids[next() % 3], votes, false);  // a second class, often tied
    if (next() % 2) b.setColor(c, {float(next() % 1000) / 999.0f, 0.25f, float(next() % 7) / 6.0f});
  }
  return std::move(b).build();
}

void expectSameVolume(const ClassVolume& got, const ClassVolume& want) {
  ASSERT_EQ(got.bricks().size(), want.bricks().size());
  EXPECT_EQ(got.occupiedCount(), want.occupiedCount());
  for (size_t i = 0; i < want.bricks().size(); ++i) {
    const ClassVolume::Brick& g = got.bricks()[i];
    const ClassVolume::Brick& w = want.bricks()[i];
    ASSERT_EQ(g.origin, w.origin) << "brick " << i;
    EXPECT_EQ(g.classes, w.classes) << "brick at " << toString(w.origin);
    EXPECT_EQ(g.colored, w.colored) << "brick at " << toString(w.origin);
    EXPECT_EQ(g.colors, w.colors) << "brick at " << toString(w.origin);
    EXPECT_EQ(g.neighbours, w.neighbours) << "brick at " << toString(w.origin);
  }
}

TEST(SceneLeavesClassVolume, EqualsTheVolumeOfOpenVdbsTrees) {
  voxtest::TempDir dir;
  const Scene scene = tiedScene();
  const std::string path = dir.file("tied.vdb");
  writeSceneVdb(scene, path);
  const Scene read = readSceneVdb(path);
  const std::optional<SceneLeaves> leaves = readSceneLeaves(path);
  ASSERT_TRUE(leaves);
  const IndexBox boxes[] = {domainBox(scene.header().dims),
                            {{3, 5, 7}, {30, 20, 28}},  // cuts bricks on every side
                            {{44, 36, 28}, {44, 36, 28}},
                            IndexBox{}};  // empty
  for (const IndexBox& box : boxes)
    for (bool withColor : {false, true})
      for (unsigned threads : {1u, 3u}) {
        SCOPED_TRACE(toString(box.min) + ".." + toString(box.max) + (withColor ? " colour" : "") + " threads " +
                     std::to_string(threads));
        expectSameVolume(classVolumeFromLeaves(*leaves, box, withColor, threads),
                         classVolumeFromScene(read, box, withColor, 1));
      }
  // The ties were there to be broken.
  uint64_t tied = 0;
  read.forEachVoxel([&](const VoxelView& v) {
    if (v.votes.size() > 1 && v.votes[0].votes == v.votes[1].votes) ++tied;
  });
  EXPECT_GT(tied, 50u);
}

}  // namespace
