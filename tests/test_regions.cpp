// Region bakes' tiling and part records (libvox/core/regions.h,
// formats/scene/scene_meta.h): tiles are disjoint, aligned and cover the
// domain at every N; "I/N" is parsed strictly; the world key changes with
// every field that decides voxels; the region record round-trips through the
// scene and page-file metadata and malformed records are refused by key.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "formats/pagefile/pagefile_meta.h"
#include "formats/scene/scene_meta.h"
#include "libvox/core/regions.h"
#include "test_util.h"

using namespace vox;
using voxtest::throwsVoxError;

namespace {

uint64_t boxVoxels(const IndexBox& b) {
  if (b.empty()) return 0;
  return uint64_t(b.max.u - b.min.u + 1) * uint64_t(b.max.v - b.min.v + 1) * uint64_t(b.max.w - b.min.w + 1);
}

bool inside(const IndexBox& b, int u, int v, int w) {
  return !b.empty() && u >= b.min.u && u <= b.max.u && v >= b.min.v && v <= b.max.v && w >= b.min.w && w <= b.max.w;
}

}  // namespace

TEST(RegionTiling, TilesPartitionTheDomainAtEveryCount) {
  for (const Dims dims : {Dims{1, 1, 1}, Dims{100, 7, 33}, Dims{512, 64, 512}, Dims{4096, 16, 96}, Dims{31, 2, 700}}) {
    for (uint32_t n : {1u, 2u, 3u, 4u, 5u, 7u, 8u, 13u, 64u, 200u}) {
      const std::vector<IndexBox> tiles = regionTiles(dims, n);
      ASSERT_EQ(tiles.size(), n);
      uint64_t total = 0;
      for (const IndexBox& t : tiles) {
        EXPECT_TRUE(isRegionAligned(t, dims)) << toString(dims) << " N=" << n;
        total += boxVoxels(t);
      }
      EXPECT_EQ(total, dims.count()) << toString(dims) << " N=" << n;
      // Disjoint and covering: every voxel of a coarse sample lies in exactly one tile.
      for (uint32_t u = 0; u < dims.x; u += 1 + dims.x / 50)
        for (uint32_t w = 0; w < dims.z; w += 1 + dims.z / 50) {
          int hits = 0;
          for (const IndexBox& t : tiles) hits += inside(t, int(u), int(dims.y - 1), int(w));
          EXPECT_EQ(hits, 1) << "voxel " << u << "," << w << " N=" << n;
        }
    }
  }
}

TEST(RegionTiling, BalancedWhenTheDomainHasEnoughCells) {
  const Dims dims{1024, 32, 1024};  // 32 x 32 cells
  for (uint32_t n : {2u, 3u, 4u, 7u, 8u}) {
    uint64_t lo = UINT64_MAX, hi = 0;
    for (const IndexBox& t : regionTiles(dims, n)) {
      lo = std::min(lo, boxVoxels(t));
      hi = std::max(hi, boxVoxels(t));
    }
    EXPECT_GT(lo, 0u);
    EXPECT_LE(double(hi) / double(lo), 1.35) << "N=" << n;
  }
}

TEST(RegionTiling, MoreTilesThanCellsGivesEmptyTiles) {
  const Dims dims{40, 8, 20};  // 2 x 1 cells
  const auto tiles = regionTiles(dims, 4);
  int empty = 0;
  for (const IndexBox& t : tiles) empty += t.empty();
  EXPECT_EQ(empty, 2);
  EXPECT_EQ(boxVoxels(tiles[0]) + boxVoxels(tiles[1]) + boxVoxels(tiles[2]) + boxVoxels(tiles[3]), dims.count());
}

TEST(RegionTiling, TheDocumentedSplitsOfTwoAndThree) {
  const Dims dims{256, 10, 128};  // 8 x 4 cells: cut across x first
  const auto two = regionTiles(dims, 2);
  EXPECT_EQ(two[0].min.u, 0);
  EXPECT_EQ(two[0].max.u, 127);
  EXPECT_EQ(two[1].min.u, 128);
  EXPECT_EQ(two[1].max.w, 127);
  const auto three = regionTiles(dims, 3);  // 1 tile on the low side: round(8 / 3) = 3 cells
  EXPECT_EQ(three[0].max.u, 95);
  EXPECT_EQ(three[1].min.u, 96);  // the high side (5 x 4 cells) is then cut across x: 2 + 3 cells
  EXPECT_EQ(three[1].max.u, 159);
  EXPECT_EQ(three[2].min.u, 160);
}

TEST(RegionSpec, ParsesIOverN) {
  const RegionSpec s = parseRegionSpec("3/7");
  EXPECT_EQ(s.index, 3u);
  EXPECT_EQ(s.count, 7u);
  EXPECT_EQ(parseRegionSpec("0/1").count, 1u);
  for (const char* bad : {"5/4", "4/4", "0/0", "1", "/4", "1/", "-1/4", "1/4/2", "a/4", "1 /4", "1/99999999999", ""})
    EXPECT_TRUE(throwsVoxError([&] { parseRegionSpec(bad); }, ErrorKind::Usage, {"--region"})) << bad;
}

TEST(RegionWorldKey, ChangesWithEveryFieldThatDecidesVoxels) {
  SceneHeader h;
  h.dims = {64, 32, 64};
  h.voxelSize = 0.5;
  h.classes.add({1, "stone", {1, 2, 3}, std::nullopt});
  h.sources.push_back({"demo:city", "demo", "", 0});
  const std::string key = regionWorldKey(h, "fill=surface");
  EXPECT_EQ(key.size(), 64u);
  EXPECT_EQ(key, regionWorldKey(h, "fill=surface"));
  EXPECT_NE(key, regionWorldKey(h, "fill=solid"));
  SceneHeader other = h;
  other.dims.x = 65;
  EXPECT_NE(key, regionWorldKey(other, "fill=surface"));
  other = h;
  other.origin[1] = 1e-9;
  EXPECT_NE(key, regionWorldKey(other, "fill=surface"));
  other = h;
  other.classes.add({2, "water", {1, 2, 3}, std::nullopt});
  EXPECT_NE(key, regionWorldKey(other, "fill=surface"));
  other = h;
  other.sources[0].path = "demo:hamlet";
  EXPECT_NE(key, regionWorldKey(other, "fill=surface"));
  other = h;  // the region record itself is not part of the key
  other.region = SceneRegion{1, 2, regionTile(h.dims, 1, 2), key};
  EXPECT_EQ(key, regionWorldKey(other, "fill=surface"));
}

TEST(RegionRecord, RoundTripsThroughSceneAndPageMetadata) {
  SceneHeader h;
  h.dims = {300, 40, 200};
  h.classes.add({1, "stone", {1, 2, 3}, std::nullopt});
  for (uint32_t i = 0; i < 5; ++i) {
    h.region = SceneRegion{i, 5, regionTile(h.dims, i, 5), std::string(64, 'c')};
    EXPECT_EQ(sceneHeaderFromMetadata(sceneFileMetadata(h), "p.vdb"), h);
    pagefile::PageMeta meta;
    meta.levels.push_back({0, {300, 40, 200}, 1.0, 3, 4});
    meta.region = h.region;
    EXPECT_EQ(pagefile::readPageMeta(pagefile::writePageMeta(meta), "p.vpk"), meta);
  }
  h.region = SceneRegion{3, 9, IndexBox{}, "k"};  // an empty tile
  EXPECT_EQ(sceneHeaderFromMetadata(sceneFileMetadata(h), "p.vdb"), h);
}

TEST(RegionRecord, MalformedRecordsAreRefusedByKey) {
  const Dims dims{64, 8, 64};
  auto parse = [&](const char* text) { regionFromJson(nlohmann::json::parse(text), dims, "p.vdb: metadata 'vox:region'"); };
  for (const char* bad : {R"({"index": 2, "count": 2, "box": null, "world_key": "k"})",
                          R"({"index": 0, "count": 0, "box": null, "world_key": "k"})",
                          R"({"index": 0, "count": 2, "box": null, "world_key": ""})",
                          R"({"index": 0, "count": 2, "box": [0,0,0,64,7,63], "world_key": "k"})",
                          R"({"index": 0, "count": 2, "box": [5,0,0,4,7,63], "world_key": "k"})",
                          R"({"index": 0, "count": 2, "box": [0,0,0,1], "world_key": "k"})",
                          R"({"index": -1, "count": 2, "box": null, "world_key": "k"})", R"([1,2])"})
    EXPECT_TRUE(throwsVoxError([&] { parse(bad); }, ErrorKind::BadInput, {"'vox:region'"})) << bad;
}

namespace {

struct PartSet {
  std::vector<SceneHeader> headers;
  std::vector<RegionPart> parts() const {
    std::vector<RegionPart> out;
    for (size_t i = 0; i < headers.size(); ++i) out.push_back({"part" + std::to_string(i) + ".vdb", &headers[i]});
    return out;
  }
};

PartSet tiles(uint32_t n) {
  SceneHeader world;
  world.dims = {300, 40, 200};
  world.classes.add({1, "stone", {1, 2, 3}, std::nullopt});
  const std::string key = regionWorldKey(world, "s");
  PartSet set;
  for (uint32_t i = 0; i < n; ++i) {
    SceneHeader h = world;
    h.region = SceneRegion{i, n, regionTile(world.dims, i, n), key};
    set.headers.push_back(h);
  }
  return set;
}

}  // namespace

TEST(RegionParts, CompleteTilingsJoin) {
  for (uint32_t n : {1u, 2u, 3u, 7u}) {
    PartSet set = tiles(n);
    std::reverse(set.headers.begin(), set.headers.end());  // any order
    EXPECT_EQ(checkRegionParts(set.parts()), RegionPartSet::Tiles);
  }
}

TEST(RegionParts, MissingDuplicateAndForeignPartsAreNamed) {
  PartSet missing = tiles(3);
  missing.headers.erase(missing.headers.begin() + 1);
  EXPECT_TRUE(throwsVoxError([&] { checkRegionParts(missing.parts()); }, ErrorKind::BadInput,
                             {"tile 1 of 3 is missing", "--region 1/3"}));
  PartSet twice = tiles(3);
  twice.headers[2] = twice.headers[0];
  EXPECT_TRUE(throwsVoxError([&] { checkRegionParts(twice.parts()); }, ErrorKind::BadInput,
                             {"part2.vdb", "tile 0 of 3 is also part0.vdb"}));
  PartSet foreign = tiles(3);
  foreign.headers[1].region->worldKey = std::string(64, 'f');
  EXPECT_TRUE(throwsVoxError([&] { checkRegionParts(foreign.parts()); }, ErrorKind::BadInput,
                             {"part1.vdb", "another bake", "world key"}));
  PartSet classes = tiles(2);
  classes.headers[1].classes.add({2, "water", {0, 0, 9}, std::nullopt});
  EXPECT_TRUE(throwsVoxError([&] { checkRegionParts(classes.parts()); }, ErrorKind::BadInput, {"part1.vdb", "class table"}));
  PartSet mixedCount = tiles(2);
  PartSet three = tiles(3);
  mixedCount.headers[1] = three.headers[1];
  EXPECT_TRUE(throwsVoxError([&] { checkRegionParts(mixedCount.parts()); }, ErrorKind::BadInput, {"part1.vdb"}));
  PartSet whole = tiles(2);
  whole.headers[1].region.reset();
  EXPECT_TRUE(throwsVoxError([&] { checkRegionParts(whole.parts()); }, ErrorKind::BadInput,
                             {"part1.vdb", "not a part of a region bake"}));
}

TEST(RegionParts, BoxPartsMustBeDisjoint) {
  PartSet set = tiles(1);
  SceneHeader a = set.headers[0], b = a;
  a.region->box = IndexBox{{0, 0, 0}, {63, 39, 63}};
  b.region->box = IndexBox{{64, 0, 0}, {95, 31, 199}};
  set.headers = {a, b};
  EXPECT_EQ(checkRegionParts(set.parts()), RegionPartSet::Boxes);
  set.headers[1].region->box.min.u = 32;
  EXPECT_TRUE(throwsVoxError([&] { checkRegionParts(set.parts()); }, ErrorKind::BadInput, {"part1.vdb", "overlaps", "part0.vdb"}));
  PartSet mixed = tiles(2);
  mixed.headers[1].region = SceneRegion{0, 1, IndexBox{{0, 0, 0}, {31, 31, 31}}, mixed.headers[0].region->worldKey};
  EXPECT_TRUE(throwsVoxError([&] { checkRegionParts(mixed.parts()); }, ErrorKind::BadInput, {"--region-box"}));
}

// Parts of one bake may spell their sources' paths differently (./a.obj,
// a.obj): the merge keeps one part's, chosen by what the parts hold (tile 0;
// among boxes the first by z, y, x; then the paths), never by their order.
TEST(RegionParts, TheKeptHeaderDoesNotDependOnTheOrder) {
  auto withPath = [](SceneHeader h, const std::string& path) {
    h.sources = {SceneSource{path, "mesh", std::string(64, 'a'), 10}};
    return h;
  };
  PartSet set = tiles(3);
  set.headers = {withPath(set.headers[2], "c.obj"), withPath(set.headers[0], "./b.obj"),
                 withPath(set.headers[1], "a.obj")};
  EXPECT_EQ(worldHeaderPart(set.parts()), 1u);  // tile 0
  std::reverse(set.headers.begin(), set.headers.end());
  EXPECT_EQ(worldHeaderPart(set.parts()), 1u);

  PartSet boxes = tiles(1);
  SceneHeader a = withPath(boxes.headers[0], "z.obj"), b = withPath(boxes.headers[0], "y.obj");
  SceneHeader c = withPath(boxes.headers[0], "x.obj"), d = withPath(boxes.headers[0], "w.obj");
  a.region->box = IndexBox{{64, 0, 0}, {95, 31, 63}};  // first by z, then y, then x: before b despite its x
  b.region->box = IndexBox{{0, 0, 64}, {63, 39, 99}};
  c.region->box = IndexBox{};                          // empty boxes come last, then by path
  d.region->box = IndexBox{};
  boxes.headers = {b, c, a, d};
  EXPECT_EQ(worldHeaderPart(boxes.parts()), 2u);
  boxes.headers = {d, a, c, b};
  EXPECT_EQ(worldHeaderPart(boxes.parts()), 1u);
  boxes.headers = {c, d};
  EXPECT_EQ(worldHeaderPart(boxes.parts()), 1u);  // "w.obj" < "x.obj"
  boxes.headers = {d, c};
  EXPECT_EQ(worldHeaderPart(boxes.parts()), 0u);
}
