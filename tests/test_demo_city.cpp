// The built-in city (libvox/scene/demo_city.h): deterministic at any thread
// count, a box equals the whole city cropped to it (the contract region bakes
// are built on), every feature present, surface flags against a brute-force
// neighbour walk, varied votes, limits.
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "libvox/scene/demo_city.h"
#include "test_util.h"

using namespace vox;

namespace {

CityOptions city(std::array<uint32_t, 3> extent, unsigned threads, IndexBox box = kWholeCity) {
  CityOptions o;
  o.extent = extent;
  o.threads = threads;
  o.box = box;
  return o;
}

bool inside(const IndexBox& b, Coord3 c) {
  return c.u >= b.min.u && c.u <= b.max.u && c.v >= b.min.v && c.v <= b.max.v && c.w >= b.min.w && c.w <= b.max.w;
}

/// `whole` restricted to `box`, voxel for voxel, with the same header.
Scene crop(const Scene& whole, const IndexBox& box) {
  SceneBuilder b(whole.header());
  whole.forEachVoxel([&](const VoxelView& v) {
    if (!inside(box, v.at)) return;
    for (const ClassVotes& c : v.votes) b.addVotes(v.at, c.classId, c.votes, v.surface);
  });
  return std::move(b).build();
}

/// Dense occupancy of a (small) scene, for brute-force checks.
struct Dense {
  Dims d;
  std::vector<uint8_t> cls;  // winning class, 0 = empty
  explicit Dense(const Scene& s) : d(s.header().dims), cls(d.count(), 0) {
    s.forEachVoxel([&](const VoxelView& v) {
      uint32_t best = 0;
      uint8_t id = 0;
      for (const ClassVotes& c : v.votes)
        if (c.votes > best) best = c.votes, id = c.classId;
      cls[index(v.at.u, v.at.v, v.at.w)] = id;
    });
  }
  size_t index(int32_t u, int32_t v, int32_t w) const { return (size_t(w) * d.y + size_t(v)) * d.x + size_t(u); }
  uint8_t at(int32_t u, int32_t v, int32_t w) const {
    if (u < 0 || v < 0 || w < 0 || uint32_t(u) >= d.x || uint32_t(v) >= d.y || uint32_t(w) >= d.z) return 0;
    return cls[index(u, v, w)];
  }
};

// A city with every feature: streets, buildings, parks with trees and a pond,
// a river with bridges (checked by the tests below).
constexpr std::array<uint32_t, 3> kTestExtent{768, 96, 576};

}  // namespace

TEST(DemoCity, SameSceneAtAnyThreadCount) {
  const Scene one = buildCity(city({512, 64, 320}, 1));
  for (unsigned threads : {2u, 3u}) {
    const SceneDifference d = compareScenes(one, buildCity(city({512, 64, 320}, threads)));
    EXPECT_TRUE(d.same()) << "threads " << threads << ": " << d.headerNote << " " << d.firstNote;
  }
  EXPECT_GT(one.occupiedCount(), 512u * 320u * 8u) << "at least the ground slab";
}

TEST(DemoCity, ABoxIsTheWholeCityCroppedToIt) {
  const Scene whole = buildCity(city(kTestExtent, 2));
  const Dense dense(whole);
  // Boxes that cut buildings, trees, the river and its bridges, tile edges
  // (not multiples of 8), a single column, boxes starting above the ground
  // (high ones skip whole tiles by their street blocks' height bound), and
  // one reaching past the domain (clipped).
  const std::vector<IndexBox> boxes = {
      {{100, 0, 100}, {300, 95, 260}},  {{13, 3, 41}, {77, 50, 99}},   {{520, 0, 0}, {767, 20, 575}},
      {{200, 9, 200}, {420, 60, 420}},  {{33, 0, 37}, {33, 95, 37}},   {{0, 5, 300}, {767, 12, 330}},
      {{700, 40, 500}, {900, 200, 700}}, {{40, 0, 230}, {190, 40, 380}}, {{0, 60, 0}, {767, 95, 575}}};
  std::set<uint8_t> cutClasses;
  for (const IndexBox& box : boxes) {
    const Scene part = buildCity(city(kTestExtent, 2, box));
    EXPECT_EQ(part.header(), whole.header()) << "the header does not depend on the box";
    const SceneDifference d = compareScenes(crop(whole, box), part);
    EXPECT_TRUE(d.same()) << toString(box.min) << ".." << toString(box.max) << ": " << d.voxelsDiffering
                          << " voxels differ, first " << d.firstNote;
    // The box cuts features: occupied voxels on its faces with occupied
    // neighbours outside it, of these classes.
    part.forEachVoxel([&](const VoxelView& v) {
      const Coord3 a = v.at;
      const Coord3 out[6] = {{a.u - 1, a.v, a.w}, {a.u + 1, a.v, a.w}, {a.u, a.v - 1, a.w},
                             {a.u, a.v + 1, a.w}, {a.u, a.v, a.w - 1}, {a.u, a.v, a.w + 1}};
      for (const Coord3& n : out)
        if (!inside(box, n) && dense.at(n.u, n.v, n.w)) cutClasses.insert(dense.at(a.u, a.v, a.w));
    });
  }
  for (uint8_t c : {1, 2, 3, 4, 6, 7}) EXPECT_TRUE(cutClasses.count(c)) << "no box cuts class " << int(c);
}

TEST(DemoCity, ThePartsOfAPartitionMergeIntoTheWholeCity) {
  // Six boxes tiling the x-z plane, cut at coordinates that are not
  // multiples of 8 (so parts share 8^3 blocks), each with every height.
  const std::array<uint32_t, 3> e{600, 80, 400};
  const Scene whole = buildCity(city(e, 2));
  const int32_t xs[] = {0, 203, 411, 600}, zs[] = {0, 157, 400};
  VoxelBlocks merged;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j)
      merged.merge(buildCityBlocks(city(e, 1, {{xs[i], 0, zs[j]}, {xs[i + 1] - 1, 79, zs[j + 1] - 1}})));
  const SceneDifference d = compareScenes(whole, SceneBuilder(std::move(merged), cityHeader(e)).build());
  EXPECT_TRUE(d.same()) << d.voxelsDiffering << " voxels differ, first " << d.firstNote;
  EXPECT_EQ(d.voxelsCompared, whole.occupiedCount());
}

TEST(DemoCity, EmptyBoxesGiveEmptyValidScenes) {
  const IndexBox empties[] = {IndexBox{},                                  // min > max
                              {{0, 95, 0}, {767, 95, 575}},               // above every roof of this height
                              {{800, 0, 0}, {900, 10, 10}}};              // outside the domain
  for (const IndexBox& box : empties) {
    const Scene s = buildCity(city(kTestExtent, 2, box));
    EXPECT_EQ(s.occupiedCount(), 0u);
    EXPECT_EQ(s.header(), cityHeader(kTestExtent));
  }
}

TEST(DemoCity, HasEveryFeature) {
  const Scene s = buildCity(city(kTestExtent, 2));
  const SceneStats st = s.stats();
  ASSERT_EQ(st.perClass.size(), 7u) << "grass, dirt, stone, plank, snow, sand, water";
  for (const SceneStats::PerClass& c : st.perClass) EXPECT_GT(c.modeVoxels, 1000u) << "class " << int(c.classId);
  EXPECT_EQ(st.bounds.min.v, 0);
  EXPECT_EQ(s.header().classes.size(), 7u);
  EXPECT_EQ(s.header().voxelSize, kCityVoxelSize);
  EXPECT_DOUBLE_EQ(s.header().origin[0], -768 * 0.25);
  EXPECT_DOUBLE_EQ(s.header().origin[2], -576 * 0.25);
  ASSERT_EQ(s.header().sources.size(), 1u);
  EXPECT_EQ(s.header().sources[0].path, "demo:city");
  EXPECT_EQ(s.header().sources[0].kind, "demo");

  const Dense d(s);
  const int32_t X = int32_t(d.d.x), Y = int32_t(d.d.y), Z = int32_t(d.d.z);
  // Ground slab everywhere: every column has a voxel at v = 0.
  uint64_t bare = 0;
  for (int32_t w = 0; w < Z; ++w)
    for (int32_t u = 0; u < X; ++u) bare += d.at(u, 0, w) == 0;
  EXPECT_EQ(bare, 0u);
  // Hollow buildings: empty voxels above the ground with occupied voxels in
  // all six directions (floors, walls, roofs around them).
  auto hits = [&](int32_t u, int32_t v, int32_t w, int du, int dv, int dw) {
    for (int k = 1; k < 200; ++k) {
      u += du, v += dv, w += dw;
      if (u < 0 || v < 0 || w < 0 || u >= X || v >= Y || w >= Z) return false;
      if (d.at(u, v, w)) return true;
    }
    return false;
  };
  uint64_t enclosed = 0, windows = 0, floorsAbove = 0;
  for (int32_t w = 0; w < Z; w += 3)
    for (int32_t u = 0; u < X; u += 3)
      for (int32_t v = 9; v < Y - 1; ++v) {
        if (d.at(u, v, w)) continue;
        if (hits(u, v, w, 0, -1, 0) && hits(u, v, w, 0, 1, 0) && hits(u, v, w, 1, 0, 0) && hits(u, v, w, -1, 0, 0) &&
            hits(u, v, w, 0, 0, 1) && hits(u, v, w, 0, 0, -1))
          ++enclosed;
        // A floor slab above the first one: an interior column whose voxel
        // below is empty and above is a floor.
        if (d.at(u, v - 1, w) == 0 && d.at(u, v + 1, w) && v > 14) ++floorsAbove;
      }
  // Windows: three empty rows between occupied ones in a column (floor
  // slabs are at least a storey, 6 rows, apart), open to the outside along
  // x or z on one side.
  for (int32_t w = 0; w < Z; ++w)
    for (int32_t u = 0; u < X; ++u)
      for (int32_t v = 10; v + 3 < Y; ++v)
        if (d.at(u, v - 1, w) && !d.at(u, v, w) && !d.at(u, v + 1, w) && !d.at(u, v + 2, w) && d.at(u, v + 3, w) &&
            (!hits(u, v, w, 1, 0, 0) || !hits(u, v, w, -1, 0, 0) || !hits(u, v, w, 0, 0, 1) || !hits(u, v, w, 0, 0, -1)))
          ++windows;
  EXPECT_GT(enclosed, 1000u) << "hollow building interiors";
  EXPECT_GT(floorsAbove, 1000u) << "floor slabs above the ground floor";
  EXPECT_GT(windows, 1000u) << "window openings";
  // Trees: trunks (Plank) standing on Grass park ground, canopies (Grass) above the ground.
  uint64_t trunks = 0, canopy = 0;
  for (int32_t w = 0; w < Z; ++w)
    for (int32_t u = 0; u < X; ++u) {
      if (d.at(u, 7, w) == 1 && d.at(u, 8, w) == 4 && d.at(u, 12, w) == 4) ++trunks;
      if (d.at(u, 20, w) == 1) ++canopy;
    }
  EXPECT_GT(trunks, 50u);
  EXPECT_GT(canopy, 500u);
}

TEST(DemoCity, SurfaceFlagsAgreeWithABruteForceNeighbourWalk) {
  const Scene s = buildCity(city({704, 72, 400}, 2));
  const Dense d(s);
  uint64_t checked = 0, wrong = 0, surface = 0;
  s.forEachVoxel([&](const VoxelView& v) {
    const Coord3 a = v.at;
    const bool expected = !d.at(a.u - 1, a.v, a.w) || !d.at(a.u + 1, a.v, a.w) || !d.at(a.u, a.v - 1, a.w) ||
                          !d.at(a.u, a.v + 1, a.w) || !d.at(a.u, a.v, a.w - 1) || !d.at(a.u, a.v, a.w + 1);
    ++checked;
    surface += expected;
    if (expected != v.surface && ++wrong <= 5) ADD_FAILURE() << "surface flag at " << toString(a);
  });
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(s.surfaceCount(), surface);
  EXPECT_LT(surface, checked) << "the ground has interior voxels";
  EXPECT_GT(checked, 704u * 400u * 8u);
}

TEST(DemoCity, HasVariedVotesAndTies) {
  const Scene s = buildCity(city({384, 64, 384}, 2));
  std::set<uint64_t> totals;
  uint64_t multi = 0, ties = 0;
  s.forEachVoxel([&](const VoxelView& v) {
    totals.insert(v.totalVotes());
    uint32_t top = 0, second = 0;
    for (const ClassVotes& c : v.votes) {
      if (c.votes > top) second = top, top = c.votes;
      else if (c.votes > second) second = c.votes;
    }
    if (v.votes.size() > 1) ++multi;
    if (v.votes.size() > 1 && top == second) ++ties;
  });
  EXPECT_GT(totals.size(), 300u) << "obs must vary";
  EXPECT_GT(multi, s.occupiedCount() / 8);
  EXPECT_GT(ties, 1000u) << "exact ties exercise the lowest-id rule";
}

TEST(DemoCity, FootprintEstimate) {
  const CityOptions o = city({1024, 128, 768}, 2);
  const VoxelBlocks blocks = buildCityBlocks(o);
  // Every tile sampled: exact.
  const CityFootprint all = estimateCityFootprint(o, 1u << 20);
  EXPECT_EQ(all.sampledTiles, all.tiles);
  EXPECT_EQ(uint64_t(all.blocks), blocks.blockCount());
  EXPECT_EQ(uint64_t(all.occupied), buildCity(o).occupiedCount());
  // Sampled: close.
  const CityFootprint some = estimateCityFootprint(o, 1024);
  EXPECT_EQ(some.sampledTiles, 1024u);
  EXPECT_NEAR(some.blocks / all.blocks, 1.0, 0.15);
  EXPECT_NEAR(some.occupied / all.occupied, 1.0, 0.15);
  // An empty box: nothing.
  EXPECT_EQ(estimateCityFootprint(city({64, 64, 64}, 1, IndexBox{}), 16).blocks, 0.0);
}

TEST(DemoCity, ExtentLimits) {
  const Scene tiny = buildCity(city({1, 1, 1}, 2));
  EXPECT_EQ(tiny.header().dims, (Dims{1, 1, 1}));
  EXPECT_EQ(tiny.occupiedCount(), 1u);
  EXPECT_TRUE(cityExtentProblem({65536, 4096, 65536}).empty());
  for (std::array<uint32_t, 3> bad : {std::array<uint32_t, 3>{0, 1, 1}, {1, 0, 1}, {65537, 8, 8}, {8, 4097, 8}, {8, 8, 65537}}) {
    EXPECT_FALSE(cityExtentProblem(bad).empty());
    EXPECT_TRUE(voxtest::throwsVoxError([&] { cityHeader(bad); }, ErrorKind::Usage, {"demo:city", "extent"}));
  }
}
