// The one-pass scene reader (formats/vdb/vdb_scene_direct_read.h) against
// OpenVDB's: every scene is read both ways (readVdbSceneFile with
// VdbSceneReader::Auto and ::OpenVdb), and the two results must hold the same
// metadata, header and grids: type, name, half-float flag, metadata entries,
// transform, background, node counts and, leaf by leaf, the value mask and
// all 512 values. Scenes: written by the direct writer (hamlet at several
// resolutions, a city box, colour with several classes and saturated counts,
// solid interior runs, an empty scene) and by OpenVDB's writer (the same
// scenes, a pyramid). Files not of voxbake's form (tiles, half floats, other
// grid types) must fall back and read as before. With VOX_DIRECT_READ_DIR
// set (tests/cli/direct_read_test.sh: scenes made by `vox voxelize` from a
// coloured mesh, a solid fill, a block map, region parts, the city and more),
// every .vdb file there is compared too. The same files are read as leaves
// (formats/vdb/vdb_scene_leaves.h, what `vox pack-chunks` packs): a file the
// one-pass reader takes must be taken, its page file the same bytes as the
// one packed from the scene (every layout, two chunk sides, 1 and 3 threads);
// others, and scenes a check refuses, must be left to the usual reader.
// As render sources (formats/vdb/vdb_leaves_render.h, what `vox-render.so`
// renders), the leaves of a file, whole or occupancy only, must give the ray
// grid, summary bytes and colours that the scene read with OpenVDB gives
// (libvox/scene/render_scene.h).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <random>

#include "formats/core/file_util.h"
#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pack_chunks.h"
#include "formats/scene/scene_vdb_direct.h"
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/vdb_leaves_render.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_scene_direct_read.h"
#include "formats/vdb/vdb_scene_grids.h"
#include "formats/vdb/vdb_scene_leaves.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/mesh/voxel_blocks.h"
#include "libvox/scene/demo_city.h"
#include "libvox/scene/demo_hamlet.h"
#include "libvox/scene/mip.h"
#include "libvox/scene/render_scene.h"
#include "libvox/scene/scene_grids.h"
#include "test_util.h"

using namespace vox;
using voxtest::TempDir;

namespace {

std::string text(const openvdb::Coord& c) { return toString(Coord3{c.x(), c.y(), c.z()}); }

/// Empty when `a` and `b` hold the same tree, else what differs.
template <typename GridT>
std::string treeDifference(const GridT& a, const GridT& b) {
  if (a.background() != b.background()) return "background";
  if (a.tree().nodeCount() != b.tree().nodeCount()) return "node counts";
  if (a.tree().activeTileCount() != b.tree().activeTileCount()) return "active tile counts";
  for (auto it = a.tree().cbeginLeaf(); it; ++it) {
    const auto* other = b.tree().probeConstLeaf(it->origin());
    const std::string at = " of the leaf at " + text(it->origin());
    if (!other) return "no leaf" + at;
    if (it->getValueMask() != other->getValueMask()) return "value mask" + at;
    for (openvdb::Index i = 0; i < GridT::TreeType::LeafNodeType::SIZE; ++i)
      if (it->getValue(i) != other->getValue(i)) return "value " + std::to_string(i) + at;
  }
  // Tiles and inactive values of the internal nodes, in iteration order.
  auto x = a.tree().cbeginValueAll();
  auto y = b.tree().cbeginValueAll();
  for (; x && y; ++x, ++y)
    if (x.getLevel() > 0 || y.getLevel() > 0)
      if (x.getLevel() != y.getLevel() || x.getCoord() != y.getCoord() || *x != *y || x.isValueOn() != y.isValueOn())
        return "tile or internal value at " + text(x.getCoord());
  if (bool(x) != bool(y)) return "value counts";
  return "";
}

std::string gridDifference(const openvdb::GridBase::Ptr& a, const openvdb::GridBase::Ptr& b) {
  if (a->type() != b->type()) return "type " + a->type() + " vs " + b->type();
  if (a->getName() != b->getName()) return "name";
  if (a->saveFloatAsHalf() != b->saveFloatAsHalf()) return "half-float flag";
  if (a->str() != b->str()) return "metadata: " + a->str() + " vs " + b->str();
  if (a->transform() != b->transform()) return "transform";
  if (auto t = openvdb::GridBase::grid<openvdb::BoolGrid>(a)) return treeDifference(*t, *openvdb::GridBase::grid<openvdb::BoolGrid>(b));
  if (auto t = openvdb::GridBase::grid<openvdb::Int32Grid>(a)) return treeDifference(*t, *openvdb::GridBase::grid<openvdb::Int32Grid>(b));
  if (auto t = openvdb::GridBase::grid<openvdb::Vec3SGrid>(a)) return treeDifference(*t, *openvdb::GridBase::grid<openvdb::Vec3SGrid>(b));
  if (auto t = openvdb::GridBase::grid<openvdb::FloatGrid>(a)) return treeDifference(*t, *openvdb::GridBase::grid<openvdb::FloatGrid>(b));
  return "grid type not compared: " + a->type();
}

/// The page file packed from `path`'s leaves against the one packed from the
/// scene, or both refusals alike. `direct`: the leaves reader must take the file.
void expectSamePack(const std::string& path, bool direct) {
  SCOPED_TRACE("packed from leaves: " + path);
  const std::optional<SceneLeaves> leaves = readSceneLeaves(path);
  ASSERT_EQ(leaves.has_value(), direct);
  if (!leaves) return;
  const Scene scene = readSceneVdb(path);
  for (const pagefile::LayoutCodec& layout : pagefile::layoutTable())
    for (uint32_t chunk : {8u, 16u})
      for (unsigned threads : {1u, 3u}) {
        SCOPED_TRACE(std::string(layout.name) + ", chunk " + std::to_string(chunk) + ", threads " + std::to_string(threads));
        PackSettings s;
        s.layout = layout.id;
        s.chunkSide = chunk;
        s.alignment = chunk == 8 ? 64 : 4096;
        s.threads = threads;
        std::vector<uint8_t> want;
        try {
          want = packChunks({&scene}, s).bytes;
        } catch (const Error& e) {  // a layout that cannot hold the scene refuses it both ways
          EXPECT_TRUE(voxtest::throwsVoxError([&] { packChunks(*leaves, s); }, e.kind, {}));
          continue;
        }
        const PlannedPack got = packChunks(*leaves, s);
        const std::string out = path + ".leaves.vpk";
        pagefile::writePlannedFile(out, got.plan, got.chunks, out);
        EXPECT_TRUE(readFileBytes(out) == std::string(want.begin(), want.end()));
        std::filesystem::remove(out);
      }
}

/// Empty when the two ray grids are the same structure, else what differs.
std::string rayGridDifference(const RayGrid& a, const RayGrid& b) {
  if (a.occupiedCount() != b.occupiedCount()) return "occupied counts";
  if (a.brickCount() != b.brickCount() || a.memoryBytes() != b.memoryBytes()) return "bricks";
  if (a.contentMin() != b.contentMin() || a.contentEnd() != b.contentEnd()) return "content box";
  if (a.occupiedMin() != b.occupiedMin() || a.occupiedEnd() != b.occupiedEnd()) return "occupied box";
  if (a.occupiedVoxels() != b.occupiedVoxels()) return "occupied voxels";
  if (a.hasDistanceField() != b.hasDistanceField()) return "distance field";
  const Dims& d = a.dims();
  const int64_t bx = (int64_t(d.x) + 7) / 8, by = (int64_t(d.y) + 7) / 8, bz = (int64_t(d.z) + 7) / 8;
  if (a.hasDistanceField())
    for (int64_t x = 0; x < bx; ++x)
      for (int64_t y = 0; y < by; ++y)
        for (int64_t z = 0; z < bz; ++z)
          if (a.emptyBricksAround(x, y, z) != b.emptyBricksAround(x, y, z)) return "distance field";
  return "";
}

/// The leaves of `path` as a render source against the scene read with
/// OpenVDB: the same ray grid (whole read and occupancy only), summaries and
/// colours of every occupied voxel, of empty ones and of ones outside the dims.
void expectSameRenderSource(const std::string& path) {
  SCOPED_TRACE("render source from leaves: " + path);
  const Scene scene = readSceneVdb(path);
  const RayGrid want = rayGridFromScene(scene);
  const std::optional<SceneLeaves> all = readSceneLeaves(path, SceneLeafParts::All);
  const std::optional<SceneLeaves> occ = readSceneLeaves(path, SceneLeafParts::OccupancyOnly);
  ASSERT_TRUE(all && occ);
  EXPECT_TRUE(occ->votes.empty() && !occ->hasColor);
  EXPECT_TRUE(occ->header.dims == scene.header().dims);
  EXPECT_EQ(rayGridDifference(rayGridFromLeaves(*all), want), "");
  EXPECT_EQ(rayGridDifference(rayGridFromLeaves(*occ), want), "");
  std::vector<Coord3> voxels = want.occupiedVoxels();
  const Dims& d = scene.header().dims;
  std::mt19937 rng(7);
  for (int i = 0; i < 2000; ++i)  // mostly empty voxels, some outside the dims on either side
    voxels.push_back({int32_t(rng() % (d.x + 20)) - 10, int32_t(rng() % (d.y + 20)) - 10, int32_t(rng() % (d.z + 20)) - 10});
  const SceneLeavesLookup lookup(*all);
  EXPECT_TRUE(lookup.summaries(voxels) == sceneSummaries(scene, voxels));
  EXPECT_TRUE(lookup.colors(voxels) == sceneColors(scene, voxels));
  EXPECT_EQ(all->hasColor, scene.hasColor());
}

/// Reads `path` both ways (whole and occupancy only) and compares. With
/// `direct`, the one-pass reader must take the file; without, it must
/// leave it to OpenVDB.
void expectSameBothWays(const std::string& path, bool direct = true) {
  SCOPED_TRACE(path);
  ASSERT_EQ(readVdbSceneFileDirect(path, false).has_value(), direct);
  for (bool occupancyOnly : {false, true}) {
    const VdbSceneFile a = readVdbSceneFile(path, occupancyOnly, VdbSceneReader::Auto);
    const VdbSceneFile b = readVdbSceneFile(path, occupancyOnly, VdbSceneReader::OpenVdb);
    EXPECT_TRUE(a.metadata == b.metadata);
    EXPECT_TRUE(sceneFileMetadata(a.header) == sceneFileMetadata(b.header));
    ASSERT_EQ(a.grids.size(), b.grids.size());
    for (size_t i = 0; i < a.grids.size(); ++i)
      EXPECT_EQ(gridDifference(a.grids[i], b.grids[i]), "") << "grid " << b.grids[i]->getName();
  }
  // The checked scene, as every command gets it.
  const VdbSceneFile b = readVdbSceneFile(path, false, VdbSceneReader::OpenVdb);
  Scene want;
  want.header() = b.header;
  want.grids() = levelGridsFromVdb(b.grids, "", b.header, path, true);
  const SceneDifference diff = compareScenes(readSceneVdb(path), want);
  EXPECT_TRUE(diff.same()) << diff.headerNote << " " << diff.firstNote;
  // Read through a walk kept from its topology (vox merge's parts): the
  // frame a full walk gives, then the same scene; the walk is finished once.
  {
    VdbTopologyWalk walked(path);
    const VdbFrame full = checkVdbStructure(path);
    ASSERT_EQ(walked.frame().grids.size(), full.grids.size());
    for (size_t i = 0; i < full.grids.size(); ++i) {
      const VdbGridFrame &a = walked.frame().grids[i], &b = full.grids[i];
      EXPECT_TRUE(a.uniqueName == b.uniqueName && a.type == b.type && a.checked == b.checked &&
                  a.leafCount == b.leafCount && a.activeLeafVoxels == b.activeLeafVoxels &&
                  a.upperNodes == b.upperNodes && a.lowerNodes == b.lowerNodes)
          << "grid " << b.uniqueName;
    }
    EXPECT_TRUE(walked.frame().metadataNames == full.metadataNames);
    const SceneDifference viaWalk = compareScenes(readSceneVdb(walked), want);
    EXPECT_TRUE(viaWalk.same()) << viaWalk.headerNote << " " << viaWalk.firstNote;
    EXPECT_TRUE(voxtest::throwsVoxError([&] { readSceneVdb(walked); }, ErrorKind::Internal, {"already finished"}));
  }
  expectSamePack(path, direct);
  if (direct) expectSameRenderSource(path);
  else EXPECT_FALSE(readSceneLeaves(path, SceneLeafParts::OccupancyOnly).has_value());
}

SceneHeader testHeader(Dims dims) {
  SceneHeader h;
  h.dims = dims;
  h.voxelSize = 0.05;
  h.origin = {-2.0, 0.5, 1.0};
  h.classes.add({1, "stone", {120, 120, 120}, std::nullopt});
  h.classes.add({3, "moss", {80, 170, 90}, std::nullopt});
  h.classes.add({9, "glass", {40, 80, 200}, std::nullopt});
  h.sources.push_back({"x.obj", "mesh", std::string(64, 'b'), 99});
  return h;
}

/// Random surface voxels of three classes with colour on some and
/// saturated counts, and solid interior runs (whole blocks of one count).
VoxelBlocks mixedBlocks(const Dims& d, uint32_t seed) {
  VoxelBlocks b;
  std::mt19937 rng(seed);
  const uint8_t ids[3] = {1, 3, 9};
  for (int i = 0; i < 4000; ++i) {
    const Coord3 c{int32_t(rng() % d.x), int32_t(rng() % d.y), int32_t(rng() % d.z)};
    b.addVotes(c, ids[rng() % 3], i % 97 == 0 ? kMaxVotesPerClass : 1 + rng() % 1000, rng() % 3 != 0);
    if (rng() % 2) b.setColor(c, {float(rng() % 256) / 255.0f, 0.25f, float(rng() % 5) / 4.0f});
  }
  for (int32_t w = 0; w < 16; ++w)  // two solid blocks of interior runs
    for (int32_t v = 40; v < 48; ++v) b.addRun({40, v, 40 + w}, 8, w < 8 ? 3 : 9, 7, false);
  return b;
}

std::string writeDirect(const TempDir& dir, const std::string& name, const SceneHeader& h, VoxelBlocks blocks) {
  const std::string path = dir.file(name);
  writeSceneVdbDirect(h, blocks, path, 2);
  return path;
}

std::string writeThroughOpenVdb(const TempDir& dir, const std::string& name, const Scene& scene) {
  const std::string path = dir.file(name);
  writeSceneVdb(scene, path);
  return path;
}

}  // namespace

TEST(DirectRead, HamletAtSeveralResolutionsBothWriters) {
  TempDir dir;
  for (uint32_t res : {8u, 40u, 96u}) {
    HamletOptions o;
    o.resolution = res;
    SceneHeader h;
    VoxelBlocks blocks = buildHamletBlocks(o, h);
    expectSameBothWays(writeDirect(dir, "h" + std::to_string(res) + ".vdb", h, std::move(blocks)));
    expectSameBothWays(writeThroughOpenVdb(dir, "hv" + std::to_string(res) + ".vdb", buildHamlet(o)));
  }
}

TEST(DirectRead, ColourClassesRunsCityEmptyAndPyramid) {
  TempDir dir;
  const SceneHeader h = testHeader({300, 90, 5000});  // several root children along z
  expectSameBothWays(writeDirect(dir, "mixed.vdb", h, mixedBlocks(h.dims, 5)));
  expectSameBothWays(writeThroughOpenVdb(dir, "mixedv.vdb", SceneBuilder(mixedBlocks(h.dims, 5), h).build()));
  expectSameBothWays(writeDirect(dir, "empty.vdb", testHeader({16, 16, 16}), VoxelBlocks()));

  CityOptions city;
  city.extent = {256, 96, 256};
  city.box = {{40, 0, 40}, {200, 95, 170}};
  expectSameBothWays(writeDirect(dir, "city.vdb", cityHeader(city.extent), buildCityBlocks(city)));

  HamletOptions o;
  o.resolution = 24;
  const std::vector<Scene> levels = buildMipPyramid(buildHamlet(o), MipSettings{});
  std::vector<const Scene*> ptrs;
  for (const Scene& s : levels) ptrs.push_back(&s);
  const std::string pyramid = dir.file("pyramid.vdb");
  writePyramidVdb(ptrs, MipOccupancy::Any, pyramid);
  expectSameBothWays(pyramid);
  const std::vector<Scene> back = readPyramidVdb(pyramid);
  ASSERT_EQ(back.size(), levels.size());
  for (size_t i = 0; i < back.size(); ++i) EXPECT_TRUE(compareScenes(back[i], levels[i]).same()) << "level " << i;
}

TEST(DirectRead, SameGridsAtAnyThreadCount) {
  TempDir dir;
  HamletOptions o;
  o.resolution = 64;
  SceneHeader h;
  VoxelBlocks blocks = buildHamletBlocks(o, h);
  const std::string path = writeDirect(dir, "h.vdb", h, std::move(blocks));
  const Scene want = readSceneVdb(path);
  for (size_t threads : {1, 2, 3}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    EXPECT_TRUE(compareScenes(readSceneVdb(path), want).same()) << threads << " threads";
  }
}

namespace {

Scene hamlet16() {
  HamletOptions o;
  o.resolution = 16;
  return buildHamlet(o);
}

/// `scene`'s grids (shallow copies), changed by `change`, written through OpenVDB as a scene file at `path`.
std::string writeChanged(const std::string& path, const Scene& scene, const std::function<void(openvdb::GridPtrVec&)>& change) {
  ensureOpenVdbInitialized();
  openvdb::GridPtrVec grids;
  appendSceneGrids(scene, "", {}, grids);
  change(grids);
  openvdb::MetaMap meta;
  insertVdbMetadata(meta, sceneFileMetadata(scene.header()));
  writeVdbFile(path, grids, meta, "scene");
  return path;
}

}  // namespace

TEST(DirectRead, FilesOfAnotherFormAreReadByOpenVdb) {
  TempDir dir;
  const Scene scene = hamlet16();
  // Occupancy and votes of one 8^3 block stored as active tiles (other writers do).
  const std::string tiles = writeChanged(dir.file("tiles.vdb"), scene, [&](openvdb::GridPtrVec& grids) {
    for (auto& g : grids) {
      auto copy = g->deepCopyGrid();
      if (auto b = openvdb::GridBase::grid<openvdb::BoolGrid>(copy)) b->tree().addTile(1, openvdb::Coord(0), true, true);
      if (auto v = openvdb::GridBase::grid<openvdb::Int32Grid>(copy)) v->tree().addTile(1, openvdb::Coord(0), 3, true);
      if (auto c = openvdb::GridBase::grid<openvdb::Vec3SGrid>(copy)) c->tree().addTile(1, openvdb::Coord(0), openvdb::Vec3s(0.5f), true);
      g = copy;
    }
  });
  expectSameBothWays(tiles, /*direct=*/false);
  // A user's float grid beside the scene's grids.
  const std::string extra = writeChanged(dir.file("extra.vdb"), scene, [&](openvdb::GridPtrVec& grids) {
    auto f = openvdb::FloatGrid::create(0.0f);
    f->setName("density");
    f->tree().setValue(openvdb::Coord(1, 2, 3), 0.5f);
    grids.push_back(f);
  });
  expectSameBothWays(extra, /*direct=*/false);
  // Colour stored as half floats.
  const std::string half = writeChanged(dir.file("half.vdb"), scene, [&](openvdb::GridPtrVec& grids) {
    auto c = openvdb::Vec3SGrid::create();
    c->setName(kColorGridName);
    c->setSaveFloatAsHalf(true);
    grids.push_back(c);
  });
  EXPECT_FALSE(readVdbSceneFileDirect(half, false).has_value());
  EXPECT_FALSE(readSceneLeaves(half).has_value());
  EXPECT_FALSE(readSceneLeaves(half, SceneLeafParts::OccupancyOnly).has_value());
}

TEST(DirectRead, CheckMessagesNameTheFirstVoxel) {
  TempDir dir;
  const Scene scene = hamlet16();
  // Counts of 0 and -4 in two leaves of the first vote grid (deep copies: the scene stays intact).
  openvdb::Coord first;
  const std::string path = writeChanged(dir.file("zero.vdb"), scene, [&](openvdb::GridPtrVec& grids) {
    auto votes = openvdb::GridBase::grid<openvdb::Int32Grid>(grids[1])->deepCopy();
    std::vector<openvdb::Coord> on;
    for (auto it = votes->cbeginValueOn(); it; ++it) on.push_back(it.getCoord());
    ASSERT_GT(on.size(), 40u);
    first = on[on.size() / 3];
    votes->tree().setValue(on.back(), 0);
    votes->tree().setValue(first, -4);
    grids[1] = votes;
  });
  const std::string at = toString(Coord3{first.x(), first.y(), first.z()});
  for (size_t threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    EXPECT_TRUE(voxtest::throwsVoxError([&] { readSceneVdb(path); }, ErrorKind::BadInput,
                                        {path, "vote count -4 at " + at, "counts must be >= 1"}));
  }
  // An occupied voxel without votes; a vote at an unoccupied voxel.
  const openvdb::Coord lone(15, 15, 15);
  ASSERT_FALSE(scene.grids().occupancy->tree().isValueOn(lone));
  const std::string unvoted = writeChanged(dir.file("unvoted.vdb"), scene, [&](openvdb::GridPtrVec& grids) {
    auto occ = openvdb::GridBase::grid<openvdb::BoolGrid>(grids[0])->deepCopy();
    occ->tree().setValueOn(lone, true);
    grids[0] = occ;
  });
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readSceneVdb(unvoted); }, ErrorKind::BadInput,
                                      {unvoted, "occupied voxel (15, 15, 15) has no votes"}));
  const std::string stray = writeChanged(dir.file("stray.vdb"), scene, [&](openvdb::GridPtrVec& grids) {
    auto votes = openvdb::GridBase::grid<openvdb::Int32Grid>(grids[1])->deepCopy();
    votes->tree().setValueOn(lone, 2);
    grids[1] = votes;
  });
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readSceneVdb(stray); }, ErrorKind::BadInput,
                                      {stray, "grid '" + voteGridName(scene.grids().votes[0].classId) + "' has a vote at an unoccupied voxel (15, 15, 15)"}));
  // Read through a walk kept from its topology: the same messages.
  for (const std::string& refused : {path, unvoted, stray}) {
    std::string message;
    try {
      readSceneVdb(refused);
    } catch (const Error& e) {
      message = e.what();
    }
    ASSERT_FALSE(message.empty());
    VdbTopologyWalk walked(refused);
    EXPECT_TRUE(voxtest::throwsVoxError([&] { readSceneVdb(walked); }, ErrorKind::BadInput, {message})) << refused;
  }
  // The leaves reader leaves each to the usual reader, which names the fault.
  for (const std::string& refused : {path, unvoted, stray}) EXPECT_FALSE(readSceneLeaves(refused).has_value()) << refused;
  // Occupancy only, the vote grids are not read (nor checked), as readSceneVdb's SceneParts::OccupancyOnly.
  for (const std::string& taken : {path, unvoted, stray}) {
    const std::optional<SceneLeaves> occ = readSceneLeaves(taken, SceneLeafParts::OccupancyOnly);
    ASSERT_TRUE(occ.has_value()) << taken;
    EXPECT_EQ(rayGridDifference(rayGridFromLeaves(*occ), rayGridFromScene(readSceneVdb(taken, SceneParts::OccupancyOnly))), "")
        << taken;
  }
  // A truncated file: the walk's message, as readSceneVdb gives it.
  const std::string bytes = readFileBytes(path);
  const std::string cut = dir.file("cut.vdb");
  writeFileBytes(cut, bytes.data(), bytes.size() * 2 / 3, cut);
  std::string message;
  try {
    readSceneVdb(cut);
  } catch (const Error& e) {
    message = e.what();
  }
  ASSERT_FALSE(message.empty());
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readSceneLeaves(cut); }, ErrorKind::BadInput, {message}));
  EXPECT_TRUE(voxtest::throwsVoxError([&] { VdbTopologyWalk walked(cut); readSceneVdb(walked); }, ErrorKind::BadInput, {message}));
}

TEST(DirectRead, ScenesMadeByTheCommandLine) {
  const char* dir = std::getenv("VOX_DIRECT_READ_DIR");
  if (!dir) GTEST_SKIP() << "VOX_DIRECT_READ_DIR not set (tests/cli/direct_read_test.sh sets it)";
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".vdb") {
      expectSameBothWays(e.path().string());
      ++files;
    }
  EXPECT_GE(files, 8);
  std::cout << "[ compared ] " << files << " scenes made by vox\n";
}
