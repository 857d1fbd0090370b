// Scene model and .vdb round trip, voxel for voxel and metadata included, and
// every way a .vdb can be wrong.
#include <gtest/gtest.h>

#include <filesystem>
#include <openvdb/io/File.h>

#include "formats/scene/scene_meta.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_scene_grids.h"
#include "libvox/scene/scene.h"
#include "libvox/scene/scene_grids.h"
#include "libvox/scene/scene_pieces.h"
#include "test_util.h"

using namespace vox;
using voxtest::TempDir;
using voxtest::throwsVoxError;

namespace {

SceneHeader smallHeader() {
  SceneHeader h;
  h.dims = {5, 3, 70};
  h.voxelSize = 0.25;
  h.origin = {-1.5, 2.0, 1e6};
  h.classes.add({1, "ground", {10, 20, 30}, FacePalette{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}});
  h.classes.add({7, "wall", {200, 100, 50}, std::nullopt});
  h.classes.add({255, "last class", {255, 255, 255}, std::nullopt});
  h.sources.push_back({"in/mesh.obj", "mesh", std::string(64, 'a'), 1234});
  h.mipLevel = 2;
  h.blockWorld = BlockWorldPlacement{2.0, {64, 48, 64}};
  return h;
}

Scene smallScene(bool color) {
  SceneBuilder b(smallHeader());
  b.addVotes({0, 0, 0}, 1, 3, true);
  b.addVotes({0, 0, 0}, 7, 3, true);  // a tie
  b.addVotes({4, 2, 69}, 255, kMaxVotesPerClass, false);
  b.addVotes({4, 2, 69}, 255, 10, false);  // saturates
  b.addVotes({2, 1, 33}, 7, 1, false);
  b.addVotes({2, 1, 33}, 7, 0, true);  // zero votes change nothing
  if (color) b.setColor({0, 0, 0}, {0.25f, 0.5f, 1.0f});
  return std::move(b).build();
}

}  // namespace

TEST(Scene, BuilderSemantics) {
  Scene s = smallScene(true);
  EXPECT_EQ(s.occupiedCount(), 3u);
  EXPECT_EQ(s.classesPresent(), (std::vector<uint8_t>{1, 7, 255}));
  std::vector<ClassVotes> st;
  auto v = s.voxel({4, 2, 69}, st);
  ASSERT_TRUE(v);
  EXPECT_FALSE(v->surface);
  ASSERT_EQ(v->votes.size(), 1u);
  EXPECT_EQ(v->votes[0].votes, kMaxVotesPerClass);
  auto z = s.voxel({2, 1, 33}, st);
  ASSERT_TRUE(z);
  EXPECT_FALSE(z->surface) << "a zero-vote call must not set the surface flag";
  EXPECT_FALSE(s.voxel({1, 1, 1}, st));
  EXPECT_FALSE(s.voxel({-1, 0, 0}, st));
  const SceneStats stats = s.stats();
  EXPECT_EQ(stats.occupied, 3u);
  EXPECT_EQ(stats.surface, 1u);
  EXPECT_EQ(s.surfaceCount(), stats.surface);
  EXPECT_EQ(stats.colored, 1u);
  EXPECT_EQ(stats.bounds.min, (Coord3{0, 0, 0}));
  EXPECT_EQ(stats.bounds.max, (Coord3{4, 2, 69}));
  ASSERT_EQ(stats.perClass.size(), 3u);
  EXPECT_EQ(stats.perClass[0].modeVoxels, 1u) << "ties go to the lowest class id";
  EXPECT_EQ(stats.perClass[1].modeVoxels, 1u);
  EXPECT_EQ(stats.perClass[1].votes, 4u);
}

TEST(Scene, BuildRejectsVoxelsOutsideTheDomainOrUnknownClasses) {
  SceneBuilder outside(smallHeader());
  outside.addVotes({5, 0, 0}, 1, 1, true);
  EXPECT_TRUE(throwsVoxError([&] { std::move(outside).build(); }, ErrorKind::Internal, {"outside"}));
  SceneBuilder unknown(smallHeader());
  unknown.addVotes({0, 0, 0}, 3, 1, true);
  EXPECT_TRUE(throwsVoxError([&] { std::move(unknown).build(); }, ErrorKind::Internal, {"class id 3"}));
}

TEST(Scene, MergeIsOrderIndependent) {
  auto fill = [](SceneBuilder& b, int part) {
    for (int i = part; i < 200; i += 3) b.addVotes({i % 5, i % 3, i % 70}, uint8_t(i % 2 ? 1 : 7), uint32_t(i + 1), i % 4 == 0);
  };
  SceneBuilder a(smallHeader()), b(smallHeader()), c(smallHeader());
  fill(a, 0), fill(b, 1), fill(c, 2);
  a.merge(std::move(b));
  a.merge(std::move(c));
  SceneBuilder x(smallHeader()), y(smallHeader()), z(smallHeader());
  fill(x, 2), fill(y, 0), fill(z, 1);
  x.merge(std::move(y));
  x.merge(std::move(z));
  Scene s1 = std::move(a).build(), s2 = std::move(x).build();
  const SceneDifference d = compareScenes(s1, s2);
  EXPECT_TRUE(d.same()) << d.headerNote << " " << d.firstNote;
  EXPECT_GT(d.voxelsCompared, 50u);
}

TEST(Scene, PiecesVisitTheSerialOrderAndStatsDoNotDependOnThreads) {
  // Voxels over many leaves (the domain is 5 x 3 x 70: nine leaves along w),
  // some with colour, votes for three classes and ties.
  SceneBuilder b(smallHeader());
  for (int i = 0; i < 1000; ++i) {
    const Coord3 c{i % 5, (i / 5) % 3, i / 15};  // 1000 distinct voxels, w up to 66
    b.addVotes(c, uint8_t(i % 3 == 0 ? 1 : i % 3 == 1 ? 7 : 255), uint32_t(i % 4 + 1), i % 2 == 0);
    if (i % 5 == 0) b.setColor(c, {0.5f, 0.25f, 0.125f});
  }
  const Scene s = std::move(b).build();
  std::vector<Coord3> serial;
  s.forEachVoxel([&](const VoxelView& v) { serial.push_back(v.at); });
  ASSERT_GT(serial.size(), 100u);
  for (unsigned threads : {1u, 2u, 4u})
    for (size_t pieces : {size_t(1), size_t(3), size_t(64)}) {
      std::vector<std::vector<Coord3>> perPiece(pieces);
      forEachVoxelInPieces(s, threads, pieces, [&](const VoxelView& v, size_t p) { perPiece[p].push_back(v.at); });
      std::vector<Coord3> joined;
      for (const auto& part : perPiece) joined.insert(joined.end(), part.begin(), part.end());
      EXPECT_EQ(joined, serial) << threads << " threads, " << pieces << " pieces";
    }
  // stats() splits the voxels by the number of workers: compare with counts
  // taken serially.
  const SceneStats st = s.stats();
  uint64_t occupied = 0, surface = 0, colored = 0, votes7 = 0, wins7 = 0;
  s.forEachVoxel([&](const VoxelView& v) {
    ++occupied, surface += v.surface, colored += bool(v.color);
    uint32_t best = 0;
    uint8_t bestId = 0;
    for (const ClassVotes& c : v.votes) {
      if (c.classId == 7) votes7 += c.votes;
      if (c.votes > best) best = c.votes, bestId = c.classId;
    }
    wins7 += bestId == 7;
  });
  EXPECT_EQ(st.occupied, occupied);
  EXPECT_EQ(st.surface, surface);
  EXPECT_EQ(st.colored, colored);
  ASSERT_EQ(st.perClass.size(), 3u);
  EXPECT_EQ(st.perClass[1].classId, 7);
  EXPECT_EQ(st.perClass[1].votes, votes7);
  EXPECT_EQ(st.perClass[1].modeVoxels, wins7);
  EXPECT_EQ(st.bounds.min, (Coord3{0, 0, 0}));
  EXPECT_EQ(st.bounds.max, (Coord3{4, 2, 66}));
}

TEST(Scene, CompareFindsTheFirstDifference) {
  Scene a = smallScene(false);
  SceneBuilder b(smallHeader());
  b.addVotes({0, 0, 0}, 1, 3, true);
  b.addVotes({0, 0, 0}, 7, 3, true);
  b.addVotes({4, 2, 69}, 255, kMaxVotesPerClass, false);
  b.addVotes({2, 1, 33}, 7, 2, false);  // differs
  b.addVotes({3, 0, 40}, 7, 1, false);  // only in b
  Scene s = std::move(b).build();
  const SceneDifference d = compareScenes(a, s);
  EXPECT_FALSE(d.same());
  EXPECT_EQ(d.voxelsDiffering, 2u);
  ASSERT_TRUE(d.firstDifference);
  EXPECT_EQ(*d.firstDifference, (Coord3{2, 1, 33}));
  EXPECT_NE(d.firstNote.find("7:1"), std::string::npos) << d.firstNote;
}

TEST(SceneVdb, RoundTripVoxelForVoxelWithMetadata) {
  TempDir dir;
  for (bool color : {false, true}) {
    Scene s = smallScene(color);
    const std::string path = dir.file(color ? "c.vdb" : "n.vdb");
    writeSceneVdb(s, path);
    Scene r = readSceneVdb(path);
    EXPECT_EQ(r.header(), s.header());
    EXPECT_EQ(r.hasColor(), color);
    const SceneDifference d = compareScenes(s, r);
    EXPECT_TRUE(d.same()) << d.headerNote << " " << d.firstNote;
    EXPECT_EQ(d.voxelsCompared, 3u);
  }
}

TEST(SceneVdb, GridsCarryTheWorldTransformForOtherReaders) {
  TempDir dir;
  Scene s = smallScene(false);
  writeSceneVdb(s, dir.file("s.vdb"));
  openvdb::io::File f(dir.file("s.vdb"));
  f.open();
  openvdb::GridBase::Ptr g = f.readGrid("occupancy");
  // Voxel (u, v, w) has its centre at origin + (index + 0.5) * voxelSize.
  const openvdb::Vec3d centre = g->indexToWorld(openvdb::Vec3d(4, 2, 69));
  EXPECT_DOUBLE_EQ(centre.x(), -1.5 + 4.5 * 0.25);
  EXPECT_DOUBLE_EQ(centre.y(), 2.0 + 2.5 * 0.25);
  EXPECT_DOUBLE_EQ(centre.z(), 1e6 + 69.5 * 0.25);
  EXPECT_TRUE(f.hasGrid("votes.255"));
  EXPECT_FALSE(f.hasGrid("color")) << "no colour grid when the scene has no colour";
}

TEST(SceneVdb, EmptySceneRoundTrips) {
  TempDir dir;
  SceneHeader h = smallHeader();
  Scene s = SceneBuilder(h).build();
  writeSceneVdb(s, dir.file("e.vdb"));
  Scene r = readSceneVdb(dir.file("e.vdb"));
  EXPECT_EQ(r.occupiedCount(), 0u);
  EXPECT_EQ(r.header(), h);
  EXPECT_TRUE(r.stats().bounds.empty());
}

// ---------------------------------------------------------------- bad files

namespace {
void writeGrids(const std::string& path, openvdb::GridPtrVec grids, const openvdb::MetaMap& meta) {
  openvdb::io::File f(path);
  f.write(grids, meta);
  f.close();
}
openvdb::MetaMap goodMeta(const std::string& vdbWithMeta) {
  openvdb::io::File f(vdbWithMeta);
  f.open();
  openvdb::MetaMap m = *f.getMetadata();
  return m;
}
}  // namespace

TEST(SceneVdb, MissingAndNonVdbFiles) {
  TempDir dir;
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("nope.vdb")); }, ErrorKind::BadInput,
                             {"nope.vdb: no such file"}));
  voxtest::writeText(dir.file("text.vdb"), "hello, I am not a vdb");
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("text.vdb")); }, ErrorKind::BadInput,
                             {"text.vdb", "not an OpenVDB file"}));
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.path().string()); }, ErrorKind::BadInput, {}));
}

TEST(SceneVdb, TruncatedFilesAreRejectedNotCrashed) {
  TempDir dir;
  writeSceneVdb(smallScene(true), dir.file("full.vdb"));
  const std::string bytes = [&] {
    std::ifstream in(dir.file("full.vdb"), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  ASSERT_GT(bytes.size(), 200u);
  // Every prefix length up to 64 bytes, then a spread of lengths to the end.
  std::vector<size_t> lengths;
  for (size_t n = 0; n < 64; ++n) lengths.push_back(n);
  for (size_t n = 64; n < bytes.size(); n += std::max<size_t>(1, bytes.size() / 97)) lengths.push_back(n);
  for (size_t n : lengths) {
    const std::string path = dir.file("cut" + std::to_string(n) + ".vdb");
    voxtest::writeText(path, bytes.substr(0, n));
    EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(path); }, ErrorKind::BadInput, {"cut" + std::to_string(n)}))
        << "truncated at " << n << " of " << bytes.size();
  }
}

TEST(SceneVdb, WrongGridsOrTypes) {
  TempDir dir;
  writeSceneVdb(smallScene(false), dir.file("good.vdb"));
  const openvdb::MetaMap meta = goodMeta(dir.file("good.vdb"));

  // A level set from another tool: no voxbake metadata at all.
  auto fog = openvdb::FloatGrid::create(0);
  fog->setName("density");
  fog->tree().setValue(openvdb::Coord(1, 1, 1), 1.0f);
  writeGrids(dir.file("foreign.vdb"), {fog}, openvdb::MetaMap());
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("foreign.vdb")); }, ErrorKind::BadInput,
                             {"foreign.vdb", "vox:format", "not a voxbake scene"}));

  // Right metadata, no occupancy grid.
  writeGrids(dir.file("noocc.vdb"), {fog}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("noocc.vdb")); }, ErrorKind::BadInput,
                             {"noocc.vdb", "occupancy"}));

  // occupancy of the wrong type.
  auto wrong = openvdb::FloatGrid::create(0);
  wrong->setName("occupancy");
  writeGrids(dir.file("wrongtype.vdb"), {wrong}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("wrongtype.vdb")); }, ErrorKind::BadInput,
                             {"wrongtype.vdb", "'occupancy'", "expected bool"}));

  // A vote grid of the wrong type, and one for a class not in the table.
  auto occ = openvdb::BoolGrid::create(false);
  occ->setName("occupancy");
  occ->tree().setValueOn(openvdb::Coord(0, 0, 0), true);
  auto fvotes = openvdb::FloatGrid::create(0);
  fvotes->setName("votes.1");
  writeGrids(dir.file("votetype.vdb"), {occ, fvotes}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("votetype.vdb")); }, ErrorKind::BadInput,
                             {"'votes.1'", "expected int32"}));
  auto v9 = openvdb::Int32Grid::create(0);
  v9->setName("votes.9");
  v9->tree().setValueOn(openvdb::Coord(0, 0, 0), 1);
  writeGrids(dir.file("unknownclass.vdb"), {occ, v9}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("unknownclass.vdb")); }, ErrorKind::BadInput,
                             {"'votes.9'", "class 9"}));

  // Occupied voxel without votes; vote outside the dims; a negative vote.
  writeGrids(dir.file("novotes.vdb"), {occ}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("novotes.vdb")); }, ErrorKind::BadInput,
                             {"(0, 0, 0)", "no votes"}));
  auto v1 = openvdb::Int32Grid::create(0);
  v1->setName("votes.1");
  v1->tree().setValueOn(openvdb::Coord(0, 0, 0), -4);
  writeGrids(dir.file("negative.vdb"), {occ, v1}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("negative.vdb")); }, ErrorKind::BadInput,
                             {"'votes.1'", "-4"}));
  auto far = occ->deepCopy();
  far->tree().setValueOn(openvdb::Coord(100, 0, 0), true);
  writeGrids(dir.file("outside.vdb"), {far}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("outside.vdb")); }, ErrorKind::BadInput,
                             {"outside the dims"}));

  // Metadata of the wrong type.
  openvdb::MetaMap badMeta = meta;
  badMeta.removeMeta("vox:dims");
  badMeta.insertMeta("vox:dims", openvdb::StringMetadata("5,3,70"));
  writeGrids(dir.file("metatype.vdb"), {occ}, badMeta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("metatype.vdb")); }, ErrorKind::BadInput,
                             {"'vox:dims'", "expected vec3i"}));
  openvdb::MetaMap future = meta;
  future.removeMeta("vox:format_version");
  future.insertMeta("vox:format_version", openvdb::Int32Metadata(99));
  writeGrids(dir.file("future.vdb"), {occ}, future);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("future.vdb")); }, ErrorKind::BadInput,
                             {"version 99", "upgrade"}));
}

TEST(SceneVdb, ColourAndVotesOnlyAtOccupiedVoxels) {
  TempDir dir;
  writeSceneVdb(smallScene(false), dir.file("good.vdb"));
  const openvdb::MetaMap meta = goodMeta(dir.file("good.vdb"));
  auto occ = openvdb::BoolGrid::create(false);
  occ->setName("occupancy");
  occ->tree().setValueOn(openvdb::Coord(0, 0, 0), true);
  auto votes = openvdb::Int32Grid::create(0);
  votes->setName("votes.1");
  votes->tree().setValueOn(openvdb::Coord(0, 0, 0), 2);
  auto color = openvdb::Vec3SGrid::create();
  color->setName("color");
  color->tree().setValueOn(openvdb::Coord(1, 0, 0), openvdb::Vec3s(0.5f));
  writeGrids(dir.file("color.vdb"), {occ, votes, color}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("color.vdb")); }, ErrorKind::BadInput,
                             {"color.vdb", "'color'", "unoccupied voxel (1, 0, 0)"}));
  auto stray = votes->deepCopy();
  stray->tree().setValueOn(openvdb::Coord(2, 0, 0), 1);
  writeGrids(dir.file("stray.vdb"), {occ, stray}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("stray.vdb")); }, ErrorKind::BadInput,
                             {"'votes.1'", "unoccupied voxel (2, 0, 0)"}));
  // The occupancy-only read does not look at votes or colour.
  EXPECT_EQ(readSceneVdb(dir.file("color.vdb"), SceneParts::OccupancyOnly).occupiedCount(), 1u);
  auto badName = votes->deepCopy();
  badName->setName("votes.01");
  writeGrids(dir.file("name.vdb"), {occ, votes, badName}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("name.vdb")); }, ErrorKind::BadInput,
                             {"'votes.01'", "votes.<class id 1..255>"}));
  auto twice = votes->deepCopy();
  writeGrids(dir.file("twice.vdb"), {occ, votes, twice}, meta);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(dir.file("twice.vdb")); }, ErrorKind::BadInput,
                             {"two vote grids for class 1"}));
}

TEST(SceneVdb, MetadataEntriesSurviveAnOpenVdbMetaMap) {
  SceneHeader h = smallHeader();
  openvdb::MetaMap map;
  insertVdbMetadata(map, sceneFileMetadata(h));
  insertVdbMetadata(map, voteGridMetadata(h.classes, 7));
  map.insertMeta("other", openvdb::FloatMetadata(1.5f));
  const MetaEntries back = metaEntriesOf(map);
  MetaEntries want = sceneFileMetadata(h);
  want.merge(voteGridMetadata(h.classes, 7));
  want["other"] = ForeignMetaValue{"float"};
  EXPECT_EQ(back, want);
  EXPECT_EQ(sceneHeaderFromMetadata(back, "m"), h);
  EXPECT_TRUE(throwsVoxError([&] { insertVdbMetadata(map, {{"x", ForeignMetaValue{"float"}}}); },
                             ErrorKind::Internal, {"'x'"}));
}
