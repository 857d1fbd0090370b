// Merging the page files of a region bake's parts (formats/pagefile/page_merge.h):
// the merged bytes equal the single-process pack of the whole scene, for every
// layout, chunk side and tile count, parts in any order; bad sets of parts are
// refused naming the part. Parts are made here by cropping the world scene to
// its tiles (what `vox voxelize --region I/N` bakes).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pack_chunks.h"
#include "formats/pagefile/page_merge.h"
#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_meta.h"
#include "libvox/core/regions.h"
#include "libvox/scene/demo_hamlet.h"
#include "libvox/scene/mip.h"
#include "libvox/scene/scene.h"
#include "test_util.h"

namespace {

using vox::pagefile::Layout;
using vox::pagefile::Reader;

// Tile `i` of `n` of `world`: the world's header with a region record, and
// only the voxels inside the tile.
vox::Scene cropToTile(const vox::Scene& world, uint32_t i, uint32_t n, const std::string& settings = "test") {
  vox::SceneHeader h = world.header();
  const vox::IndexBox box = vox::regionTile(h.dims, i, n);
  h.region = vox::SceneRegion{i, n, box, vox::regionWorldKey(world.header(), settings)};
  vox::SceneBuilder b(h);
  world.forEachVoxel([&](const vox::VoxelView& v) {
    const vox::Coord3 c = v.at;
    if (box.empty() || c.u < box.min.u || c.u > box.max.u || c.v < box.min.v || c.v > box.max.v ||
        c.w < box.min.w || c.w > box.max.w)
      return;
    for (const vox::ClassVotes& cv : v.votes) b.addVotes(c, cv.classId, cv.votes, v.surface);
    if (v.color) b.setColor(c, *v.color);
  });
  return std::move(b).build();
}

// How the levels are made: none (no --mips), or buildMipPyramid with an
// occupancy rule and `--levels` (0: automatic).
struct Mips {
  bool on = false;
  vox::MipOccupancy occupancy = vox::MipOccupancy::Any;
  int levels = 0;
  std::string name() const {
    return on ? std::string("--mips --occupancy ") + vox::mipOccupancyName(occupancy) + " --levels " + std::to_string(levels)
              : "no mips";
  }
};

// What `vox pack-chunks SCENE --mips ...` writes (mipLevelsToBuild: a part
// gets its levels up to the seam level).
std::vector<uint8_t> pack(const vox::Scene& s, vox::PackSettings ps, const Mips& mips = {}) {
  std::vector<vox::Scene> levels;
  std::vector<const vox::Scene*> ptrs{&s};
  if (mips.on) {
    vox::MipSettings ms;
    ms.occupancy = mips.occupancy;
    ms.levels = vox::mipLevelsToBuild(s.header(), mips.levels);
    levels = vox::buildMipPyramid(s, ms);
    for (const vox::Scene& l : levels) ptrs.push_back(&l);
    ps.mipOccupancy = vox::mipOccupancyName(mips.occupancy);
    ps.mipLevelsAsked = uint32_t(mips.levels);
  }
  return vox::packChunks(ptrs, ps).bytes;
}

// A coloured scene over several tiles: coloured surface voxels in the low x
// half only, so the parts on the high side have no colour channel.
vox::Scene colouredScene() {
  vox::SceneHeader h;
  h.dims = {150, 40, 97};
  h.voxelSize = 0.5;
  h.origin = {-3, 0, 1};
  h.classes.add({1, "a", {}, {}});
  h.classes.add({2, "b", {}, {}});
  h.classes.add({7, "g", {}, {}});
  vox::SceneBuilder b(h);
  for (int i = 0; i < 4000; ++i) {
    const vox::Coord3 c{(i * 37) % 150, (i * 13) % 40, (i * 29) % 97};
    b.addVotes(c, uint8_t(i % 3 == 0 ? 7 : 2), uint32_t(1 + i % 11), true);
    b.addVotes(c, 1, uint32_t(i % 5), true);
    if (c.u < 70) b.setColor(c, {float(i % 10) / 9.f, 0.25f, float(i % 4) / 3.f});
  }
  return std::move(b).build();
}

// Interior voxels (a solid block) only near the origin, surface voxels
// elsewhere: most parts have no surface channel.
vox::Scene interiorScene() {
  vox::SceneHeader h;
  h.dims = {130, 24, 110};
  h.voxelSize = 1;
  h.classes.add({1, "rock", {}, {}});
  h.classes.add({3, "moss", {}, {}});
  vox::SceneBuilder b(h);
  for (int z = 2; z < 20; ++z)
    for (int y = 0; y < 10; ++y)
      for (int x = 3; x < 25; ++x) {
        const bool edge = x == 3 || x == 24 || y == 0 || y == 9 || z == 2 || z == 19;
        b.addVotes({x, y, z}, 1, uint32_t(1 + (x + y + z) % 9), edge);
      }
  for (int i = 0; i < 3000; ++i) b.addVotes({(i * 41) % 130, (i * 7) % 24, (i * 23) % 110}, 3, uint32_t(1 + i % 6), true);
  return std::move(b).build();
}

struct Merged {
  std::vector<std::vector<uint8_t>> partBytes;
  std::vector<Reader> readers;
};

// The parts of `world` in tiles of `n`, packed, opened in the order `order` gives.
Merged packParts(const vox::Scene& world, uint32_t n, const vox::PackSettings& ps, const Mips& mips = {}) {
  Merged m;
  for (uint32_t i = 0; i < n; ++i) m.partBytes.push_back(pack(cropToTile(world, i, n), ps, mips));
  for (uint32_t i = 0; i < n; ++i)
    m.readers.push_back(Reader::fromMemory(m.partBytes[i].data(), m.partBytes[i].size(), "part" + std::to_string(i) + ".vpk"));
  return m;
}

// The merged file's bytes (written to a temporary file, read back).
std::vector<uint8_t> merge(std::span<const Reader* const> parts, unsigned threads = 1, vox::MergeResult* result = nullptr) {
  vox::MergeSettings ms;
  ms.threads = threads;
  const voxtest::TempDir dir;
  const std::string path = dir.file("merged.vpk");
  const vox::MergeResult r = vox::mergePageFiles(parts, ms, path);
  if (result) *result = r;
  std::ifstream in(path, std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes.size(), r.fileBytes);
  return bytes;
}

std::vector<const Reader*> ptrs(const Merged& m) {
  std::vector<const Reader*> out;
  for (const Reader& r : m.readers) out.push_back(&r);
  return out;
}

// Every layout, chunk side and tile count of the issue: merged == whole.
void expectMergeIsWhole(const vox::Scene& world, const std::string& what, const Mips& mips = {}) {
  for (const auto& layout : vox::pagefile::layoutTable())
    for (uint32_t chunk : {8u, 16u, 32u}) {
      vox::PackSettings ps;
      ps.layout = layout.id;
      ps.chunkSide = chunk;
      ps.alignment = chunk == 16 ? 0 : 64;  // 0: auto, chosen again by the merge
      const std::vector<uint8_t> whole = pack(world, ps, mips);
      for (uint32_t n : {1u, 2u, 3u, 7u}) {
        const Merged m = packParts(world, n, ps, mips);
        std::vector<const Reader*> order = ptrs(m);
        std::rotate(order.begin(), order.begin() + n / 2, order.end());  // any order
        std::reverse(order.begin(), order.end());
        const std::vector<uint8_t> merged = merge(order, 1 + n % 2);
        EXPECT_TRUE(merged == whole) << what << ", " << mips.name() << ": layout " << layout.name << ", chunk " << chunk << ", N = " << n
                                     << ": " << merged.size() << " bytes merged, " << whole.size() << " whole";
      }
    }
}

TEST(PageMerge, HamletPartsMergeToTheWholeFile) {
  vox::HamletOptions ho;
  ho.resolution = 128;
  expectMergeIsWhole(vox::buildHamlet(ho), "hamlet 128");
}

TEST(PageMerge, ColouredPartsWithAndWithoutColourMergeToTheWholeFile) {
  expectMergeIsWhole(colouredScene(), "coloured");
}

TEST(PageMerge, PartsWithoutInteriorVoxelsMergeToTheWholeFile) { expectMergeIsWhole(interiorScene(), "interior"); }

const Mips kAnyAuto{true, vox::MipOccupancy::Any, 0};
const Mips kMajorityAuto{true, vox::MipOccupancy::Majority, 0};

TEST(PageMerge, HamletWithMipsMergesToTheWholeFile) {
  vox::HamletOptions ho;
  ho.resolution = 128;
  const vox::Scene hamlet = vox::buildHamlet(ho);
  expectMergeIsWhole(hamlet, "hamlet 128", kAnyAuto);
  expectMergeIsWhole(hamlet, "hamlet 128", kMajorityAuto);
}

// The merge's paths are all taken: copies, chunks of mip levels joined from
// several parts, levels rebuilt from the seam voxels.
TEST(PageMerge, MipsTakeEveryPath) {
  vox::HamletOptions ho;
  ho.resolution = 128;
  const vox::Scene hamlet = vox::buildHamlet(ho);
  vox::PackSettings ps;
  ps.chunkSide = 8;
  ps.layout = Layout::Svo;
  const Merged m = packParts(hamlet, 7, ps, kAnyAuto);
  vox::MergeResult r;
  const std::vector<uint8_t> bytes = merge(ptrs(m), 1, &r);
  EXPECT_GT(r.stats.copiedChunks, 0u);
  EXPECT_GT(r.stats.joinedChunks, 0u);
  EXPECT_GT(r.stats.rebuiltChunks, 0u);
  EXPECT_GT(r.stats.seamVoxels, 1u);
  EXPECT_EQ(r.levels.size(), 8u);  // 128 -> 1: levels 0..7
  EXPECT_EQ(bytes, pack(hamlet, ps, kAnyAuto));
}

TEST(PageMerge, HamletAtResolution256WithAndWithoutMips) {
  vox::HamletOptions ho;
  ho.resolution = 256;
  ho.threads = 2;
  const vox::Scene hamlet = vox::buildHamlet(ho);
  expectMergeIsWhole(hamlet, "hamlet 256");
  expectMergeIsWhole(hamlet, "hamlet 256", kAnyAuto);
}

TEST(PageMerge, ColouredAndInteriorScenesWithMips) {
  expectMergeIsWhole(colouredScene(), "coloured", kAnyAuto);
  expectMergeIsWhole(colouredScene(), "coloured", kMajorityAuto);
  expectMergeIsWhole(interiorScene(), "interior", kAnyAuto);
  expectMergeIsWhole(interiorScene(), "interior", kMajorityAuto);
}

// --levels below, at and past the seam level.
TEST(PageMerge, LevelsAskedMergeToTheWholeFile) {
  for (int levels : {1, 3, 4, 5, 7}) expectMergeIsWhole(colouredScene(), "coloured", {true, vox::MipOccupancy::Any, levels});
}

// A sparse world whose automatic pyramid stops early (a level with one voxel)
// while most parts are empty.
TEST(PageMerge, AutomaticPyramidThatStopsEarly) {
  vox::SceneHeader h;
  h.dims = {200, 30, 180};
  h.classes.add({1, "a", {}, {}});
  for (const std::vector<vox::Coord3>& pts : std::vector<std::vector<vox::Coord3>>{
           {{5, 5, 5}}, {{5, 5, 5}, {6, 5, 5}}, {{0, 0, 0}, {150, 20, 170}}, {{31, 0, 31}, {32, 0, 32}, {33, 1, 33}}}) {
    vox::SceneBuilder b(h);
    for (const vox::Coord3& c : pts) b.addVotes(c, 1, 3, true);
    const vox::Scene s = std::move(b).build();
    expectMergeIsWhole(s, std::to_string(pts.size()) + " voxels", kAnyAuto);
    expectMergeIsWhole(s, std::to_string(pts.size()) + " voxels", kMajorityAuto);
  }
}

// `--region-box` parts (tile 0 of 1 with their own box, y cut too) merge into
// the file of their union.
TEST(PageMerge, RegionBoxPartsMergeToTheirUnion) {
  const vox::Scene world = colouredScene();  // 150 x 40 x 97
  const std::vector<vox::IndexBox> boxes = {{{0, 0, 0}, {63, 31, 96}}, {{64, 0, 0}, {127, 39, 63}}, {{0, 32, 0}, {31, 39, 31}}};
  auto inside = [](const vox::IndexBox& b, const vox::Coord3& c) {
    return c.u >= b.min.u && c.u <= b.max.u && c.v >= b.min.v && c.v <= b.max.v && c.w >= b.min.w && c.w <= b.max.w;
  };
  // crop(world, boxes, region): the voxels inside any of the boxes.
  auto crop = [&](const std::vector<vox::IndexBox>& in, std::optional<vox::SceneRegion> region) {
    vox::SceneHeader h = world.header();
    h.region = region;
    vox::SceneBuilder b(h);
    world.forEachVoxel([&](const vox::VoxelView& v) {
      if (std::none_of(in.begin(), in.end(), [&](const vox::IndexBox& x) { return inside(x, v.at); })) return;
      for (const vox::ClassVotes& cv : v.votes) b.addVotes(v.at, cv.classId, cv.votes, v.surface);
      if (v.color) b.setColor(v.at, *v.color);
    });
    return std::move(b).build();
  };
  const std::string key = vox::regionWorldKey(world.header(), "test");
  const vox::Scene unionScene = crop(boxes, std::nullopt);
  for (const Mips& mips : {Mips{}, Mips{true, vox::MipOccupancy::Any, 0}})
    for (const auto& layout : vox::pagefile::layoutTable()) {
      vox::PackSettings ps;
      ps.layout = layout.id;
      ps.chunkSide = 16;
      ps.alignment = 64;
      std::vector<std::vector<uint8_t>> bytes;
      for (const vox::IndexBox& b : boxes) bytes.push_back(pack(crop({b}, vox::SceneRegion{0, 1, b, key}), ps, mips));
      std::vector<Reader> readers;
      for (size_t i = 0; i < bytes.size(); ++i)
        readers.push_back(Reader::fromMemory(bytes[i].data(), bytes[i].size(), "box" + std::to_string(i) + ".vpk"));
      std::vector<const Reader*> ptrs;
      for (const Reader& r : readers) ptrs.push_back(&r);
      EXPECT_TRUE(merge(ptrs) == pack(unionScene, ps, mips)) << layout.name << ", " << mips.name();
    }
}

TEST(PageMerge, IdenticalBytesAtAnyThreadCount) {
  const vox::Scene world = colouredScene();
  vox::PackSettings ps;
  ps.layout = Layout::Svo;
  const Merged m = packParts(world, 7, ps);
  vox::MergeResult r;
  const std::vector<uint8_t> one = merge(ptrs(m), 1, &r);
  EXPECT_GT(r.stats.reencodedChunks, 0u);  // the parts without colour
  EXPECT_GT(r.stats.copiedChunks, 0u);
  EXPECT_EQ(one, merge(ptrs(m), 2));
  EXPECT_EQ(one, merge(ptrs(m), 0));
}

// --align auto: each part chooses its own alignment from its own payloads, but
// the merge chooses again over the world's chunks, as the single-process pack
// does. Four full 32^3 chunks in tile 0 (page alignment costs them ~3%)
// beside single voxels in tile 1, one per chunk (a chunk of ~4-8 KiB of
// bitmaps: 4 KiB padding costs them ~45%): with few single voxels the world
// keeps 4 KiB, with many it takes 64 bytes, while the parts are 4 KiB and 64
// bytes either way.
TEST(PageMerge, AutomaticAlignmentIsChosenOverTheWorld) {
  vox::SceneHeader h;
  h.dims = {128, 32, 1600};
  h.classes.add({1, "a", {}, {}});
  const vox::IndexBox dense = vox::regionTile(h.dims, 0, 2), sparse = vox::regionTile(h.dims, 1, 2);
  std::vector<vox::Coord3> chunkCorners;  // of tile 1, on the 32-voxel chunk grid
  for (int z = (sparse.min.w + 31) / 32 * 32; z + 31 <= sparse.max.w; z += 32)
    for (int x = (sparse.min.u + 31) / 32 * 32; x + 31 <= sparse.max.u; x += 32) chunkCorners.push_back({x, 0, z});
  ASSERT_GE(chunkCorners.size(), 60u);
  ASSERT_TRUE(dense.max.u - dense.min.u >= 63 && dense.max.w - dense.min.w >= 63 && dense.min.u % 32 == 0 &&
              dense.min.w % 32 == 0);
  for (const int singles : {4, 60}) {
    SCOPED_TRACE(std::to_string(singles) + " single voxels");
    vox::SceneBuilder b(h);
    for (int z = dense.min.w; z < dense.min.w + 64; ++z)
      for (int y = 0; y < 32; ++y)
        for (int x = dense.min.u; x < dense.min.u + 64; ++x) b.addVotes({x, y, z}, 1, 2, false);
    for (int i = 0; i < singles; ++i) b.addVotes(chunkCorners[size_t(i)], 1, 1, true);
    const vox::Scene world = std::move(b).build();
    vox::PackSettings ps;
    ps.chunkSide = 32;
    ASSERT_EQ(ps.alignment, 0u) << "auto is the default";
    const std::vector<uint8_t> whole = pack(world, ps);
    const Reader w = Reader::fromMemory(whole.data(), whole.size(), "whole.vpk");
    const Merged m = packParts(world, 2, ps);
    EXPECT_EQ(m.readers[0].header().alignLog2, vox::pagefile::kAutoAlignPageLog2);
    EXPECT_EQ(m.readers[1].header().alignLog2, vox::pagefile::kAutoAlignCompactLog2);
    EXPECT_EQ(w.header().alignLog2, singles == 4 ? vox::pagefile::kAutoAlignPageLog2 : vox::pagefile::kAutoAlignCompactLog2);
    vox::MergeResult r;
    const std::vector<uint8_t> merged = merge(ptrs(m), 1, &r);
    EXPECT_TRUE(merged == whole) << merged.size() << " bytes merged, " << whole.size() << " whole";
    EXPECT_EQ(r.alignment, 1u << w.header().alignLog2);
    // A part packed with an explicit alignment is not of the same bake's settings.
    vox::PackSettings fixed = ps;
    fixed.alignment = 1u << m.readers[1].header().alignLog2;
    const std::vector<uint8_t> odd = pack(cropToTile(world, 1, 2), fixed);
    const Reader o = Reader::fromMemory(odd.data(), odd.size(), "fixed.vpk");
    EXPECT_TRUE(voxtest::throwsVoxError([&] { merge(std::vector<const Reader*>{&m.readers[0], &o}); },
                                        vox::ErrorKind::BadInput, {"fixed.vpk", "payload alignment", "auto"}));
  }
}

class PageMergeErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    vox::HamletOptions ho;
    ho.resolution = 64;
    world = vox::buildHamlet(ho);
    ps.chunkSide = 8;
    ps.alignment = 64;
    m = packParts(world, 3, ps);
  }
  ::testing::AssertionResult refused(const std::vector<const Reader*>& parts, std::initializer_list<std::string> needles) {
    return voxtest::throwsVoxError([&] { merge(parts); }, vox::ErrorKind::BadInput, needles);
  }
  vox::Scene world;
  vox::PackSettings ps;
  Merged m;
};

TEST_F(PageMergeErrors, MissingRepeatedForeignAndWholeFiles) {
  EXPECT_TRUE(refused({&m.readers[0], &m.readers[2]}, {"1 of 3"}));  // tile 1 missing
  EXPECT_TRUE(refused({&m.readers[0], &m.readers[1], &m.readers[1], &m.readers[2]}, {"part1.vpk"}));
  const std::vector<uint8_t> foreign = pack(cropToTile(world, 1, 3, "another bake"), ps);
  const Reader f = Reader::fromMemory(foreign.data(), foreign.size(), "foreign.vpk");
  EXPECT_TRUE(refused({&m.readers[0], &f, &m.readers[2]}, {"foreign.vpk"}));
  const std::vector<uint8_t> whole = pack(world, ps);
  const Reader w = Reader::fromMemory(whole.data(), whole.size(), "whole.vpk");
  EXPECT_TRUE(refused({&m.readers[0], &w, &m.readers[2]}, {"whole.vpk", "region"}));
  // A tile of another tiling overlaps.
  const std::vector<uint8_t> half = pack(cropToTile(world, 0, 2), ps);
  const Reader o = Reader::fromMemory(half.data(), half.size(), "half.vpk");
  EXPECT_TRUE(refused({&m.readers[0], &m.readers[1], &m.readers[2], &o}, {"half.vpk"}));
}

TEST_F(PageMergeErrors, PartsPackedWithOtherSettings) {
  for (int which = 0; which < 3; ++which) {
    vox::PackSettings other = ps;
    if (which == 0) other.chunkSide = 16;
    if (which == 1) other.layout = Layout::Columns;
    if (which == 2) other.alignment = 128;
    const std::vector<uint8_t> bytes = pack(cropToTile(world, 2, 3), other);
    const Reader r = Reader::fromMemory(bytes.data(), bytes.size(), "odd.vpk");
    EXPECT_TRUE(refused({&m.readers[0], &m.readers[1], &r},
                        {"odd.vpk", which == 0 ? "chunk side" : which == 1 ? "layout" : "alignment"}));
  }
}

TEST_F(PageMergeErrors, PartsWithOtherMipSettings) {
  const Mips any{true, vox::MipOccupancy::Any, 0};
  const Merged withMips = packParts(world, 3, ps, any);
  const std::vector<uint8_t> none = pack(cropToTile(world, 2, 3), ps);  // no --mips
  const Reader r0 = Reader::fromMemory(none.data(), none.size(), "nomips.vpk");
  // Named as packed without --mips, whichever part comes first.
  EXPECT_TRUE(refused({&withMips.readers[0], &withMips.readers[1], &r0},
                      {"nomips.vpk: packed without --mips, but part0.vpk has mip levels (occupancy 'any')"}));
  EXPECT_TRUE(refused({&r0, &withMips.readers[0], &withMips.readers[1]},
                      {"nomips.vpk: packed without --mips, but part0.vpk has mip levels"}));
  const std::vector<uint8_t> maj = pack(cropToTile(world, 2, 3), ps, {true, vox::MipOccupancy::Majority, 0});
  const Reader r1 = Reader::fromMemory(maj.data(), maj.size(), "majority.vpk");
  EXPECT_TRUE(refused({&withMips.readers[0], &withMips.readers[1], &r1}, {"majority.vpk", "mip occupancy"}));
  const std::vector<uint8_t> five = pack(cropToTile(world, 2, 3), ps, {true, vox::MipOccupancy::Any, 5});
  const Reader r2 = Reader::fromMemory(five.data(), five.size(), "five.vpk");
  EXPECT_TRUE(refused({&withMips.readers[0], &withMips.readers[1], &r2}, {"five.vpk", "--levels"}));
  // Levels that came from a `vox mip` pyramid file.
  vox::PackSettings fromFile = ps;
  const vox::Scene part = cropToTile(world, 2, 3);
  vox::MipSettings ms;
  ms.levels = vox::mipLevelsToBuild(part.header(), 0);
  const std::vector<vox::Scene> levels = vox::buildMipPyramid(part, ms);
  std::vector<const vox::Scene*> lp{&part};
  for (const vox::Scene& l : levels) lp.push_back(&l);
  fromFile.mipOccupancy = "from part2_mips.vdb";
  const std::vector<uint8_t> pyr = vox::packChunks(lp, fromFile).bytes;
  const Reader r3 = Reader::fromMemory(pyr.data(), pyr.size(), "pyramid.vpk");
  const Reader* all3[] = {&withMips.readers[0], &withMips.readers[1], &r3};
  EXPECT_TRUE(voxtest::throwsVoxError([&] { merge(all3); }, vox::ErrorKind::BadInput, {"pyramid.vpk"}));
}

TEST_F(PageMergeErrors, CorruptPayloadNamesThePartAndTheChunk) {
  std::vector<uint8_t> bad = m.partBytes[1];
  const Reader clean = Reader::fromMemory(bad.data(), bad.size(), "x");
  ASSERT_FALSE(clean.entries().empty());
  const uint64_t at = clean.entries()[clean.entries().size() / 2].offset;
  bad[at] ^= 0x10;
  const Reader r = Reader::fromMemory(bad.data(), bad.size(), "corrupt.vpk");
  EXPECT_TRUE(refused({&m.readers[0], &r, &m.readers[2]}, {"corrupt.vpk", "chunk"}));
}

// A chunk of a level the merge rebuilds from the seam voxels (never read
// otherwise) is CRC-checked too: a corrupt part is refused, naming it and the
// chunk, before the output exists.
TEST_F(PageMergeErrors, CorruptChunkOfARebuiltLevelIsRefused) {
  const Merged withMips = packParts(world, 3, ps, {true, vox::MipOccupancy::Any, 0});
  std::vector<uint8_t> bad = withMips.partBytes[1];
  const Reader clean = Reader::fromMemory(bad.data(), bad.size(), "x");
  const size_t last = clean.entries().size() - 1;
  ASSERT_GE(clean.entries()[last].level, vox::pagefile::kRegionSeamLevel);
  bad[clean.entries()[last].offset + clean.entries()[last].size - 1] ^= 0x01;
  const Reader r = Reader::fromMemory(bad.data(), bad.size(), "corrupt.vpk");
  EXPECT_TRUE(voxtest::throwsVoxError([&] { r.verify(); }, vox::ErrorKind::BadInput, {"crc32c"}));
  const voxtest::TempDir dir;
  const std::string out = dir.file("merged.vpk");
  const Reader* parts[] = {&withMips.readers[0], &r, &withMips.readers[2]};
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::mergePageFiles(parts, vox::MergeSettings{}, out); },
                                      vox::ErrorKind::BadInput,
                                      {"corrupt.vpk: " + r.describe(last) + ": field 'crc32c'"}));
  EXPECT_FALSE(std::ifstream(out).good()) << "a refused merge created its output";
}

}  // namespace
