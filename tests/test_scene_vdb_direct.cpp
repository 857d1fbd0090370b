// The direct scene writer (formats/scene/scene_vdb_direct.h) against OpenVDB's own:
// the same scene written both ways must give the same bytes, except the
// 36-character UUID and the `file_delayed_load` grid metadata OpenVDB adds to
// non-bool grids (an optional index for delayed loading, which readers drop),
// and must read back as the same scene.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "formats/vdb/scene_vdb.h"
#include "formats/scene/scene_vdb_direct.h"
#include "formats/scene/vdb_content_uuid.h"
#include "libvox/mesh/voxel_blocks.h"
#include "test_util.h"

namespace {

using namespace vox;

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

constexpr size_t kUuidAt = kVdbUuidOffset;  // magic 8, versions 12, offsets flag 1 (vdb_content_uuid.h)
constexpr size_t kHeaderBytes = kUuidAt + kVdbUuidChars;

// An OpenVDB-written file without its `file_delayed_load` metadata entries, the
// three stream positions of every grid moved back by the bytes removed.
std::string stripDelayedLoad(const std::string& b) {
  size_t p = kHeaderBytes;
  auto i32 = [&](size_t at) {
    int32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
  };
  auto skipString = [&](size_t at) { return at + 4 + size_t(i32(at)); };
  auto skipMeta = [&](size_t at) {
    const int32_t n = i32(at);
    at += 4;
    for (int32_t k = 0; k < n; ++k) {
      at = skipString(skipString(at));
      at += 4 + size_t(i32(at));
    }
    return at;
  };
  std::string out = b.substr(0, kHeaderBytes);
  size_t q = skipMeta(p);
  out += b.substr(p, q - p);
  p = q;
  const int32_t grids = i32(p);
  out += b.substr(p, 4);
  p += 4;
  int64_t shift = 0;
  for (int32_t g = 0; g < grids; ++g) {
    q = skipString(skipString(skipString(p)));
    out += b.substr(p, q - p);
    p = q;
    int64_t pos[3];
    std::memcpy(pos, b.data() + p, sizeof pos);
    const size_t posAt = out.size();
    out += b.substr(p, sizeof pos);
    p += sizeof pos;
    const int64_t gridPos = pos[0] - shift;
    out += b.substr(p, 4);  // compression flags
    p += 4;
    const int32_t n = i32(p);
    p += 4;
    std::string kept;
    int32_t keptCount = 0;
    for (int32_t k = 0; k < n; ++k) {
      const size_t start = p;
      const std::string name = b.substr(p + 4, size_t(i32(p)));
      p = skipString(skipString(p));
      p += 4 + size_t(i32(p));
      if (name == "file_delayed_load") {
        shift += int64_t(p - start);
      } else {
        kept += b.substr(start, p - start);
        ++keptCount;
      }
    }
    out.append(reinterpret_cast<const char*>(&keptCount), 4);
    out += kept;
    out += b.substr(p, size_t(pos[2]) - p);
    p = size_t(pos[2]);
    const int64_t fixed[3] = {gridPos, pos[1] - shift, pos[2] - shift};
    std::memcpy(out.data() + posAt, fixed, sizeof fixed);
  }
  EXPECT_EQ(p, b.size());
  return out;
}

SceneHeader header(Dims dims) {
  SceneHeader h;
  h.dims = dims;
  h.voxelSize = 0.0125;
  h.origin = {-1.5, 0.25, 3.0};
  h.classes.add({1, "stone", {120, 120, 120}, std::nullopt});
  h.classes.add({2, "grass", {80, 170, 90}, std::nullopt});
  h.classes.add({7, "water", {40, 80, 200}, std::nullopt});
  h.sources.push_back({"mesh.obj", "mesh", std::string(64, 'a'), 1234});
  return h;
}

/// Deterministic content: scattered voxels with votes of up to three classes,
/// colour on some, a full block, blocks on both sides of internal-node
/// boundaries (128 and 4096 voxels), saturated counts.
VoxelBlocks makeBlocks(const Dims& d, uint64_t seed, bool color) {
  VoxelBlocks b;
  uint64_t x = seed;
  auto next = [&] {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    return x;
  };
  const uint8_t ids[3] = {1, 2, 7};
  for (int i = 0; i < 3000; ++i) {
    const Coord3 c{int32_t(next() % d.x), int32_t(next() % d.y), int32_t(next() % d.z)};
    const uint8_t cls = ids[next() % 3];
    b.addVotes(c, cls, uint32_t(1 + next() % 100000), next() % 4 != 0);
    if (color && next() % 2) b.setColor(c, {float(next() % 1000) / 999.0f, 0.5f, float(next() % 7) / 6.0f});
  }
  auto inside = [&](Coord3 c) { return uint32_t(c.u) < d.x && uint32_t(c.v) < d.y && uint32_t(c.w) < d.z; };
  for (int32_t u = 8; u < 16; ++u)  // one full block, every voxel occupied
    for (int32_t v = 16; v < 24; ++v)
      if (inside({u, v, 31})) b.addRun({u, v, 24}, 8, 2, 3, (u + v) % 2);
  // Interior runs (no surface flag), kept as masks until they mix: one class and
  // count per block, then a second class, a different count and overlapping
  // runs that add up, in blocks of their own.
  if (inside({40, 40, 40})) {
    for (int32_t v = 32; v < 40; ++v) b.addRun({32, v, 32}, 8, 1, 65536, false);     // compact
    for (int32_t v = 32; v < 36; ++v) b.addRun({40, v, 32}, 8, 1, 65536, false);     // next block,
    for (int32_t v = 36; v < 40; ++v) b.addRun({40, v, 32}, 8, 2, 65536, false);     //  second class
    b.addRun({48, 32, 32}, 8, 7, 10, false), b.addRun({48, 33, 32}, 8, 7, 11, false);  // another count
    b.addRun({56, 32, 32}, 8, 1, 65536, false), b.addRun({56, 32, 34}, 3, 1, 65536, false);  // overlap: sums
    b.addRun({32, 40, 32}, 8, 2, 9, false), b.addVotes({32, 40, 33}, 2, 4, true);   // runs + plain votes
    b.addRun({33, 40, 30}, 20, 1, kMaxVotesPerClass, false), b.addRun({33, 40, 32}, 2, 1, kMaxVotesPerClass, false);
  }
  for (Coord3 c : {Coord3{127, 127, 127}, Coord3{128, 128, 128}, Coord3{4095, 0, 4096},
                   Coord3{int32_t(d.x) - 1, int32_t(d.y) - 1, int32_t(d.z) - 1}})
    if (inside(c)) b.addVotes(c, 7, kMaxVotesPerClass, true), b.addVotes(c, 7, 5, true);
  return b;
}

void expectSameAsOpenVdb(const SceneHeader& h, const std::function<VoxelBlocks()>& make,
                         bool uniformMap = true) {
  voxtest::TempDir dir;
  VoxelBlocks forDirect = make(), forDirect2 = make(), forVdb = make();
  const std::string direct = dir.file("direct.vdb"), direct2 = dir.file("direct2.vdb"), viaVdb = dir.file("vdb.vdb");
  const DirectWriteSummary s = writeSceneVdbDirect(h, forDirect, direct, 1);
  writeSceneVdbDirect(h, forDirect2, direct2, 2);
  const Scene scene = SceneBuilder(std::move(forVdb), h).build();
  writeSceneVdb(scene, viaVdb);

  const std::string a = readAll(direct), b = stripDelayedLoad(readAll(viaVdb));
  EXPECT_EQ(readAll(direct2), a) << "the bytes depend on the thread count";
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.substr(0, kUuidAt), b.substr(0, kUuidAt));
  size_t firstDiff = kHeaderBytes;
  while (firstDiff < a.size() && a[firstDiff] == b[firstDiff]) ++firstDiff;
  EXPECT_EQ(firstDiff, a.size()) << "first differing byte at offset " << firstDiff;
  EXPECT_EQ(s.fileBytes, a.size());
  EXPECT_NE(a.find("ScaleTranslateMap"), std::string::npos);
  EXPECT_EQ(a.find("UniformScaleTranslateMap") != std::string::npos, uniformMap);
  EXPECT_EQ(s.occupied, scene.occupiedCount());
  EXPECT_EQ(s.surface, scene.surfaceCount());
  EXPECT_EQ(s.classesPresent, scene.classesPresent());
  EXPECT_EQ(s.color, scene.hasColor());

  const Scene back = readSceneVdb(direct);
  const SceneDifference diff = compareScenes(back, scene);
  EXPECT_TRUE(diff.same()) << diff.headerNote << " " << diff.firstNote;

  // OpenVDB's writer drew a UUID at random; writeSceneVdb replaced it with the
  // content's (formats/scene/vdb_content_uuid.h): stamping it again changes
  // nothing, and the file still reads back.
  const std::string before = readAll(viaVdb);
  stampVdbContentUuid(viaVdb, "vdb.vdb");
  const std::string after = readAll(viaVdb);
  EXPECT_EQ(after.substr(kUuidAt, kVdbUuidChars), before.substr(kUuidAt, kVdbUuidChars)) << "the UUID is not the content's";
  EXPECT_TRUE(after == before) << "stamping changed more than the UUID";
  EXPECT_TRUE(compareScenes(readSceneVdb(viaVdb), scene).same());
}

TEST(SceneVdbDirect, ContentUuidFollowsTheContent) {
  voxtest::TempDir dir;
  const SceneHeader h = header({64, 64, 64});
  const std::string path = dir.file("s.vdb"), again = dir.file("again.vdb");
  writeSceneVdb(SceneBuilder(makeBlocks(h.dims, 99, false), h).build(), path);
  writeSceneVdb(SceneBuilder(makeBlocks(h.dims, 99, false), h).build(), again);
  std::string bytes = readAll(path);
  EXPECT_TRUE(readAll(again) == bytes) << "OpenVDB's writer gave different bytes for the same scene";
  const std::string uuid = bytes.substr(kUuidAt, kVdbUuidChars);
  EXPECT_EQ(uuid[14], '4') << uuid;  // version 4
  EXPECT_NE(std::string("89ab").find(uuid[19]), std::string::npos) << uuid;  // variant 1
  // One byte of content changed: another UUID.
  bytes[bytes.size() - 1] = char(bytes.back() ^ 1);
  std::ofstream(path, std::ios::binary) << bytes;
  stampVdbContentUuid(path, "s.vdb");
  EXPECT_NE(readAll(path).substr(kUuidAt, kVdbUuidChars), uuid);
  // Too short for a header: refused, naming the file.
  std::ofstream(dir.file("short.vdb"), std::ios::binary) << "VDB";
  try {
    stampVdbContentUuid(dir.file("short.vdb"), "short.vdb");
    ADD_FAILURE() << "a 3-byte file was stamped";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("short.vdb: cannot set the file's UUID"), std::string::npos) << e.what();
  }
}

TEST(SceneVdbDirect, SameBytesAsOpenVdbWithClassesAndColour) {
  const SceneHeader h = header({300, 200, 260});
  expectSameAsOpenVdb(h, [&] { return makeBlocks(h.dims, 12345, true); });
}

TEST(SceneVdbDirect, SameBytesAcrossTopLevelNodesAndWithoutColour) {
  const SceneHeader h = header({9000, 40, 5000});  // beyond 4096: several root children
  expectSameAsOpenVdb(h, [&] { return makeBlocks(h.dims, 777, false); });
}

TEST(SceneVdbDirect, SameBytesForAnEmptyScene) {
  const SceneHeader h = header({16, 16, 16});
  expectSameAsOpenVdb(h, [] { return VoxelBlocks(); });
}

TEST(SceneVdbDirect, SameTransformFarFromTheOrigin) {
  // Millimetre voxels a kilometre away: OpenVDB's stored scale differs per axis
  // in the last bits, so the map is written as a (non-uniform) ScaleTranslateMap.
  SceneHeader h = header({64, 64, 64});
  h.voxelSize = 0.001;
  h.origin = {1.0e6, -3.3e5, 7.77e5};
  h.mipLevel = 2;
  h.blockWorld = BlockWorldPlacement{2.0, {64, 48, 64}};
  expectSameAsOpenVdb(h, [&] { return makeBlocks(h.dims, 99, true); }, /*uniformMap=*/false);
}

TEST(SceneVdbDirect, RefusesWhatBuildRefuses) {
  voxtest::TempDir dir;
  SceneHeader h = header({8, 8, 8});
  VoxelBlocks outside;
  outside.addVotes({8, 0, 0}, 1, 1, true);
  EXPECT_TRUE(voxtest::throwsVoxError([&] { writeSceneVdbDirect(h, outside, dir.file("a.vdb")); },
                                      ErrorKind::Internal, {"(8, 0, 0)", "outside the scene domain"}));
  VoxelBlocks unknownClass;
  unknownClass.addVotes({1, 1, 1}, 42, 1, true);
  EXPECT_TRUE(voxtest::throwsVoxError([&] { writeSceneVdbDirect(h, unknownClass, dir.file("b.vdb")); },
                                      ErrorKind::Internal, {"class id 42"}));
  VoxelBlocks fine;
  fine.addVotes({1, 1, 1}, 1, 1, true);
  EXPECT_TRUE(voxtest::throwsVoxError([&] { writeSceneVdbDirect(h, fine, dir.file("no/such/dir/c.vdb")); },
                                      ErrorKind::Io, {"no/such/dir/c.vdb"}));
}

}  // namespace

namespace {

TEST(VoxelBlocks, RunsAddUpLikePlainVotes) {
  // The same votes through runs (compact masks) and through addVotes one voxel
  // at a time, merged in both orders, give the same scene.
  const SceneHeader h = header({24, 24, 24});
  auto viaRuns = [&](bool split) {
    VoxelBlocks a, b;
    a.addRun({1, 2, 3}, 12, 1, 65536, false);
    (split ? b : a).addRun({1, 2, 5}, 4, 1, 65536, false);  // overlaps: 2 x 65536 there
    (split ? b : a).addRun({1, 3, 0}, 16, 2, 7, false);
    b.addRun({9, 9, 9}, 5, 7, 3, false);
    a.merge(std::move(b));
    return SceneBuilder(std::move(a), h).build();
  };
  VoxelBlocks plain;
  for (int32_t w = 3; w < 15; ++w) plain.addVotes({1, 2, w}, 1, 65536, false);
  for (int32_t w = 5; w < 9; ++w) plain.addVotes({1, 2, w}, 1, 65536, false);
  for (int32_t w = 0; w < 16; ++w) plain.addVotes({1, 3, w}, 2, 7, false);
  for (int32_t w = 9; w < 14; ++w) plain.addVotes({9, 9, w}, 7, 3, false);
  const Scene expected = SceneBuilder(std::move(plain), h).build();
  for (bool split : {false, true}) {
    const SceneDifference d = compareScenes(viaRuns(split), expected);
    EXPECT_TRUE(d.same()) << "split " << split << ": " << d.firstNote;
  }
}

}  // namespace
