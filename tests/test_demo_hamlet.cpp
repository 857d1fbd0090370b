// The built-in hamlet: deterministic at any thread count, varied summaries,
// the parts the UVW atlas layout's demo scene has.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "formats/vdb/scene_vdb.h"
#include "libvox/scene/demo_hamlet.h"
#include "test_util.h"

using namespace vox;

namespace {
HamletOptions hamlet(uint32_t resolution, unsigned threads) {
  HamletOptions o;
  o.resolution = resolution;
  o.threads = threads;
  return o;
}
}  // namespace

TEST(DemoHamlet, SameSceneAtAnyThreadCountAndThroughVdb) {
  voxtest::TempDir dir;
  const Scene one = buildHamlet(hamlet(96, 1));
  for (unsigned threads : {2u, 2u, 3u, 7u}) {
    const Scene other = buildHamlet(hamlet(96, threads));
    const SceneDifference d = compareScenes(one, other);
    EXPECT_TRUE(d.same()) << "threads " << threads << ": " << d.headerNote << " " << d.firstNote;
  }
  writeSceneVdb(one, dir.file("a.vdb"));
  writeSceneVdb(buildHamlet(hamlet(96, 2)), dir.file("b.vdb"));
  const SceneDifference d = compareScenes(readSceneVdb(dir.file("a.vdb")), readSceneVdb(dir.file("b.vdb")));
  EXPECT_TRUE(d.same()) << d.headerNote << " " << d.firstNote;
  EXPECT_EQ(d.voxelsCompared, one.occupiedCount());
}

TEST(DemoHamlet, HasVariedVotesTiesAndEveryMaterial) {
  const Scene s = buildHamlet(hamlet(128, 2));
  std::set<uint64_t> totals;
  std::set<uint32_t> topShares;
  uint64_t multi = 0, ties = 0, interior = 0;
  s.forEachVoxel([&](const VoxelView& v) {
    const uint64_t total = v.totalVotes();
    totals.insert(total);
    uint32_t top = 0, second = 0;
    for (const ClassVotes& c : v.votes) {
      if (c.votes > top) second = top, top = c.votes;
      else if (c.votes > second) second = c.votes;
    }
    topShares.insert(uint32_t(top * 255 / total));
    if (v.votes.size() > 1) ++multi;
    if (v.votes.size() > 1 && top == second) ++ties;
    if (!v.surface) ++interior;
  });
  EXPECT_GT(totals.size(), 200u) << "obs must vary";
  EXPECT_GT(topShares.size(), 100u) << "conf must vary";
  EXPECT_GT(multi, s.occupiedCount() / 10);
  EXPECT_GT(ties, 100u) << "some exact ties exercise the lowest-id rule";
  EXPECT_GT(interior, 0u);
  EXPECT_EQ(s.classesPresent().size(), 7u) << "grass, dirt, stone, plank, snow, sand, water";
  const SceneStats st = s.stats();
  EXPECT_EQ(st.bounds.min.v, 0);
  EXPECT_EQ(s.surfaceCount(), st.surface) << "leaf-mask count equals the voxel walk";
  EXPECT_EQ(s.header().dims, (Dims{128, 128, 128}));
}

TEST(DemoHamlet, ResolutionOneAndLimits) {
  const Scene tiny = buildHamlet(hamlet(1, 4));
  EXPECT_EQ(tiny.header().dims, (Dims{1, 1, 1}));
  EXPECT_LE(tiny.occupiedCount(), 1u);
  EXPECT_THROW(buildHamlet(hamlet(0, 1)), Error);
  EXPECT_THROW(buildHamlet(hamlet(5000, 1)), Error);
}
