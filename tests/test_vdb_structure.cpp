// Corrupt .vdb files: the structure walk (formats/vdb/vdb_structure.h) and
// CheckedVdbFile (formats/vdb/vdb_checked_file.h) in front of OpenVDB's reader.
//
// Scenes and pyramids written by vox, and level sets and fog volumes written by
// OpenVDB, corrupted deterministically (every truncation step, seeded bit
// flips anywhere and inside grid payloads, compressed block sizes replaced by
// huge, negative and off-by-one values): each read must either succeed or
// throw vox::Error (BadInput) naming the file, and never crash. A read that
// succeeds returns the same scene unless the flip landed in a value (vote
// count, colour, surface flag) that no check can tell from a valid one; those
// reads still pass every scene invariant (readSceneVdb checks them).
// With VOX_VDB_CORRUPT_DIR set, every corrupted file is also kept there, to be
// replayed under ASan by the fuzz binary (docs/reliability.md).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>

#include "formats/core/file_util.h"
#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "formats/vdb/vdb_checked_file.h"
#include "formats/vdb/vdb_grid_input.h"
#include "formats/vdb/vdb_structure.h"
#include "libvox/scene/demo_hamlet.h"
#include "libvox/scene/mip.h"
#include "libvox/scene/scene_grids.h"
#include "test_util.h"

using namespace vox;
using voxtest::TempDir;
using voxtest::throwsVoxError;

namespace {

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
}
template <typename T>
void poke(std::string& bytes, size_t at, T v) {
  std::memcpy(bytes.data() + at, &v, sizeof v);
}
template <typename T>
T peek(const std::string& bytes, size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

void writeGrids(const std::string& path, const openvdb::GridPtrVec& grids, uint32_t compression = 0x6) {
  openvdb::io::File f(path);
  f.setCompression(compression);
  f.write(grids);
  f.close();
}

Scene hamlet(uint32_t res) {
  HamletOptions o;
  o.resolution = res;
  return buildHamlet(o);
}

/// A level set sphere and a fog volume with an active tile, as other tools write them.
openvdb::FloatGrid::Ptr levelSet() {
  auto ls = openvdb::FloatGrid::create(1.0f);
  ls->setName("ball");
  ls->setGridClass(openvdb::GRID_LEVEL_SET);
  ls->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
  for (int x = -5; x <= 5; ++x)
    for (int y = -5; y <= 5; ++y)
      for (int z = -5; z <= 5; ++z) {
        const float d = (std::sqrt(float(x * x + y * y + z * z)) - 2.5f) * 0.5f;
        if (std::abs(d) < 1.0f) ls->tree().setValue(openvdb::Coord(x + 8, y + 8, z + 8), d);
        else if (d < 0) ls->tree().setValueOff(openvdb::Coord(x + 8, y + 8, z + 8), -1.0f);
      }
  return ls;
}
openvdb::FloatGrid::Ptr fog() {
  auto g = openvdb::FloatGrid::create(0.0f);
  g->setName("density");
  g->setGridClass(openvdb::GRID_FOG_VOLUME);
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 3; ++z) g->tree().setValue(openvdb::Coord(x, y, z), x < 5 ? 1.0f : 0.1f);
  g->tree().addTile(1, openvdb::Coord(128, 0, 0), 0.75f, true);
  return g;
}

/// Offsets of Blosc blocks (their int64 size field) found by their headers.
std::vector<size_t> bloscBlockSizeFields(const std::string& b) {
  std::vector<size_t> out;
  for (size_t p = 0; p + 24 <= b.size(); ++p) {
    const int64_t n = peek<int64_t>(b, p);
    if (n < 16 || uint64_t(n) > b.size() - p - 8) continue;
    if (uint8_t(b[p + 8]) != 2 || peek<uint32_t>(b, p + 8 + 12) != uint64_t(n)) continue;
    out.push_back(p);
  }
  return out;
}

struct Outcomes {
  int same = 0, refused = 0, differentButValid = 0;
  std::string summary() const {
    return std::to_string(same) + " same, " + std::to_string(refused) + " refused, " +
           std::to_string(differentButValid) + " read with other values";
  }
};

/// Kept copies of corrupted files for the ASan replay (VOX_VDB_CORRUPT_DIR).
void keep(const std::string& bytes, const std::string& tag) {
  static int n = 0;
  if (const char* dir = std::getenv("VOX_VDB_CORRUPT_DIR"))
    writeBytes(std::string(dir) + "/" + tag + "-" + std::to_string(n++) + ".vdb", bytes);
}

/// Writes `bytes` to `path`, runs `read` (returns true when the result equals
/// the original), and records the outcome; anything but success or BadInput
/// naming the file fails the test.
void tryRead(const std::string& bytes, const std::string& path, const std::string& tag,
             const std::function<bool()>& read, Outcomes& o, const std::string& what) {
  writeBytes(path, bytes);
  keep(bytes, tag);
  try {
    if (read()) ++o.same;
    else ++o.differentButValid;
  } catch (const Error& e) {
    if (e.kind != ErrorKind::BadInput && e.kind != ErrorKind::Usage)
      ADD_FAILURE() << what << ": error of kind " << int(e.kind) << ": " << e.what();
    else if (std::string(e.what()).find(path) == std::string::npos)
      ADD_FAILURE() << what << ": message does not name the file: " << e.what();
    ++o.refused;
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": not a vox::Error: " << e.what();
  }
}

/// Every corruption of `original` this file tries, read with `read`; the
/// outcomes by kind of corruption (printed for docs/reliability.md) and in total.
Outcomes corruptAll(const std::string& original, const std::string& path, const std::string& tag,
                    const std::function<bool()>& read) {
  std::map<std::string, Outcomes> kinds;
  Outcomes o;
  const VdbFrame frame = checkVdbStructure(reinterpret_cast<const uint8_t*>(original.data()), original.size(), "x");
  // Truncation at every step.
  const size_t step = std::max<size_t>(1, original.size() / 150);
  for (size_t n = 0; n < original.size(); n += step)
    tryRead(original.substr(0, n), path, tag, read, kinds["truncation"], "cut at " + std::to_string(n));
  // Seeded single bit flips anywhere.
  std::mt19937_64 rng(13);
  for (int i = 0; i < 300; ++i) {
    std::string b = original;
    const size_t at = size_t(rng() % b.size());
    b[at] = char(b[at] ^ (1 << (rng() % 8)));
    tryRead(b, path, tag, read, kinds["bit flip anywhere"], "bit flip at " + std::to_string(at));
  }
  // Bit flips inside grid payloads (node masks, origins, metadata bytes, values).
  for (int i = 0; i < 300; ++i) {
    const VdbGridFrame& g = frame.grids[size_t(rng() % frame.grids.size())];
    std::string b = original;
    const size_t at = size_t(g.gridPos) + size_t(rng() % uint64_t(g.endPos - g.gridPos));
    b[at] = char(b[at] ^ (1 << (rng() % 8)));
    tryRead(b, path, tag, read, kinds["bit flip in a grid payload"], "payload bit flip at " + std::to_string(at));
  }
  // Compressed block sizes replaced.
  const std::vector<size_t> blocks = bloscBlockSizeFields(original);
  EXPECT_GT(blocks.size(), 0u);
  for (size_t k = 0; k < blocks.size(); k += std::max<size_t>(1, blocks.size() / 40)) {
    const int64_t n = peek<int64_t>(original, blocks[k]);
    const uint32_t raw = peek<uint32_t>(original, blocks[k] + 8 + 4);
    for (int64_t v : {int64_t(-1), -int64_t(raw) - 8, -int64_t(raw) * 64, -(int64_t(1) << 40), INT64_MIN, INT64_MAX,
                      int64_t(1) << 40, n + 1, n - 1, int64_t(0), int64_t(15)}) {
      std::string b = original;
      poke(b, blocks[k], v);
      tryRead(b, path, tag, read, kinds["block size replaced"],
              "block size at " + std::to_string(blocks[k]) + " set to " + std::to_string(v));
    }
    // The Blosc header's own sizes.
    for (uint32_t field : {4u, 12u}) {
      std::string b = original;
      poke(b, blocks[k] + 8 + field, peek<uint32_t>(original, blocks[k] + 8 + field) * 16 + 1000);
      tryRead(b, path, tag, read, kinds["Blosc header size enlarged"], "Blosc header field " + std::to_string(field));
    }
  }
  for (const auto& [kind, k] : kinds) {
    std::cout << "[ " << tag << " / " << kind << " ] " << k.summary() << "\n";
    o.same += k.same;
    o.refused += k.refused;
    o.differentButValid += k.differentButValid;
  }
  return o;
}

}  // namespace

TEST(VdbStructure, AcceptsEveryValueTypeCompressionAndTransformOpenVdbWrites) {
  ensureOpenVdbInitialized();
  TempDir dir;
  auto fill = [](auto grid, auto value) {
    for (int i = 0; i < 40; ++i) grid->tree().setValue(openvdb::Coord(i * 3, -i, i * i % 17), value);
    grid->tree().addTile(2, openvdb::Coord(-256, 0, 0), value, true);  // 128^3 active tile
    grid->tree().addTile(3, openvdb::Coord(8192, 0, 0), value, false);  // root tile
    return openvdb::GridBase::Ptr(grid);
  };
  openvdb::GridPtrVec grids = {
      fill(openvdb::BoolGrid::create(false), true),
      fill(openvdb::MaskGrid::create(false), true),
      fill(openvdb::FloatGrid::create(0.5f), 2.5f),
      fill(openvdb::DoubleGrid::create(0.0), -3.25),
      fill(openvdb::Int32Grid::create(7), 11),
      fill(openvdb::Int64Grid::create(0), int64_t(1) << 40),
      fill(openvdb::Vec3IGrid::create(), openvdb::Vec3i(1, 2, 3)),
      fill(openvdb::Vec3SGrid::create(), openvdb::Vec3s(1, 2, 3)),
      fill(openvdb::Vec3DGrid::create(), openvdb::Vec3d(1, 2, 3)),
  };
  const char* names[] = {"bool", "mask", "float", "double", "int32", "int64", "vec3i", "vec3s", "vec3d"};
  for (size_t i = 0; i < grids.size(); ++i) grids[i]->setName(names[i]);
  grids[2]->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
  openvdb::Mat4d affine = openvdb::Mat4d::identity();
  affine.setToRotation(openvdb::Vec3d(0, 0, 1), 0.3);
  affine.postTranslate(openvdb::Vec3d(1, 2, 3));
  grids[3]->setTransform(openvdb::math::Transform::createLinearTransform(affine));
  using openvdb::math::MapBase;
  grids[4]->setTransform(std::make_shared<openvdb::math::Transform>(
      MapBase::Ptr(new openvdb::math::UnitaryMap(openvdb::Vec3d(0, 1, 0), 0.7))));
  grids[5]->setTransform(std::make_shared<openvdb::math::Transform>(
      MapBase::Ptr(new openvdb::math::TranslationMap(openvdb::Vec3d(4, 5, 6)))));
  grids[6]->setTransform(std::make_shared<openvdb::math::Transform>(
      MapBase::Ptr(new openvdb::math::ScaleMap(openvdb::Vec3d(1, 2, 3)))));
  grids[0]->setTransform(std::make_shared<openvdb::math::Transform>(
      MapBase::Ptr(new openvdb::math::ScaleTranslateMap(openvdb::Vec3d(1, 2, 3), openvdb::Vec3d(-1, 0, 1)))));
  grids[7]->setTransform(openvdb::math::Transform::createFrustumTransform(
      openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(10)), 0.5, 2.0, 0.1));
  grids[7]->setSaveFloatAsHalf(true);
  grids[8]->setSaveFloatAsHalf(true);
  auto inst = grids[2]->copyGrid();  // an instance: shares the float grid's tree
  inst->setName("instance");
  grids.push_back(inst);
  for (uint32_t compression : {0x6u, 0x4u, 0x3u, 0x1u, 0x2u, 0x0u}) {
    const std::string path = dir.file("all" + std::to_string(compression) + ".vdb");
    writeGrids(path, grids, compression);
    const VdbFrame frame = checkVdbStructure(path);
    ASSERT_EQ(frame.grids.size(), grids.size());
    for (const VdbGridFrame& g : frame.grids) EXPECT_TRUE(g.checked) << g.uniqueName << ": " << g.uncheckedWhy;
    CheckedVdbFile file(path);
    for (const auto& want : grids) {
      const openvdb::GridBase::Ptr got = file.readGrid(want->getName());
      EXPECT_EQ(got->type(), want->type()) << want->getName();
      EXPECT_EQ(got->activeVoxelCount(), want->activeVoxelCount()) << want->getName() << " compression " << compression;
      EXPECT_EQ(got->baseTree().leafCount(), want->baseTree().leafCount()) << want->getName();
      EXPECT_EQ(got->transform().mapType(), want->transform().mapType()) << want->getName();
      // The walk's counts, which the memory guards use before any grid is read.
      const auto g = std::find_if(frame.grids.begin(), frame.grids.end(),
                                  [&](const VdbGridFrame& f) { return f.uniqueName == want->getName(); });
      ASSERT_NE(g, frame.grids.end()) << want->getName();
      if (!g->instanceParent.empty()) continue;
      EXPECT_EQ(g->leafCount, want->baseTree().leafCount()) << want->getName();
      EXPECT_EQ(g->activeLeafVoxels, want->baseTree().activeLeafVoxelCount()) << want->getName();
    }
  }
}

TEST(VdbStructure, NamesTheGridTheLeafAndTheField) {
  TempDir dir;
  const std::string path = dir.file("scene.vdb");
  writeSceneVdb(hamlet(12), path);
  const std::string good = readBytes(path);
  const VdbFrame frame = checkVdbStructure(path);
  const VdbGridFrame& votes = *std::find_if(frame.grids.begin(), frame.grids.end(),
                                            [](const VdbGridFrame& g) { return g.uniqueName.rfind("votes.", 0) == 0; });
  // The first leaf buffer: value mask (64 bytes), compression metadata (1), block size.
  const size_t sizeAt = size_t(votes.blockPos) + 65;
  const std::string cut = dir.file("neg.vdb");
  std::string b = good;
  poke(b, sizeAt, -(int64_t(1) << 20));  // OpenVDB would copy 1 MB into a leaf of 512 values
  writeBytes(cut, b);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(cut); }, ErrorKind::BadInput,
                             {cut, "grid '" + votes.uniqueName + "'", "leaf at (", "leaf values",
                              "uncompressed block of 1048576 bytes"}));
  poke(b, sizeAt, int64_t(1) << 40);
  writeBytes(cut, b);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(cut); }, ErrorKind::BadInput,
                             {cut, "grid '" + votes.uniqueName + "'", "leaf at (",
                              "compressed block of 1099511627776 bytes overruns the file"}));
  // The Blosc header claims more compressed bytes than the block holds (Blosc
  // would read past OpenVDB's buffer).
  b = good;
  poke(b, sizeAt + 8 + 12, peek<uint32_t>(good, sizeAt + 8 + 12) + 4000);
  writeBytes(cut, b);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(cut); }, ErrorKind::BadInput, {cut, "Blosc header claims"}));
  // A leaf's value mask in the buffers no longer matches the topology.
  b = good;
  b[size_t(votes.blockPos)] = char(b[size_t(votes.blockPos)] ^ 1);
  writeBytes(cut, b);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(cut); }, ErrorKind::BadInput, {cut, "leaf value mask differs"}));
  // An old file format.
  b = good;
  poke(b, 8, uint32_t(221));
  writeBytes(cut, b);
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(cut); }, ErrorKind::BadInput, {cut, "221", "older than vox reads"}));
}

TEST(VdbStructure, RefusesWhatItCannotCheckAndNonRegularFiles) {
  ensureOpenVdbInitialized();
  TempDir dir;
  const std::string path = dir.file("v.vdb");
  auto g = openvdb::FloatGrid::create(0.0f);
  g->setName("d");
  g->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
  writeGrids(path, {g});
  std::string b = readBytes(path);
  const size_t at = b.find("Tree_float_5_4_3");
  ASSERT_NE(at, std::string::npos);
  b.replace(at, 16, "Tree_vec2s_5_4_3");  // same length: a type OpenVDB 10 does not register
  writeBytes(path, b);
  const VdbFrame frame = checkVdbStructure(path);
  ASSERT_EQ(frame.grids.size(), 1u);
  EXPECT_FALSE(frame.grids[0].checked);
  EXPECT_TRUE(throwsVoxError([&] { CheckedVdbFile f(path); f.readGrid("d"); }, ErrorKind::BadInput, {path}));
  VdbGridInputOptions o;
  o.resolution = 8;
  o.threshold = 0.5;
  o.gridName = "d";
  EXPECT_TRUE(throwsVoxError([&] { readVdbGridAsScene(path, o); }, ErrorKind::BadInput, {path}));

  const std::string fifo = dir.file("pipe.vdb");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_TRUE(throwsVoxError([&] { CheckedVdbFile f(fifo); }, ErrorKind::BadInput, {fifo, "not a regular file"}));
  EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(fifo); }, ErrorKind::BadInput, {fifo, "not a regular file"}));
  EXPECT_TRUE(throwsVoxError([&] { CheckedVdbFile f(dir.path().string()); }, ErrorKind::BadInput, {"directory"}));
}

/// The message checkVdbFileOpenable throws for `path`, or "" when it accepts it.
std::string openableMessage(const std::string& path) {
  try {
    checkVdbFileOpenable(path);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind, ErrorKind::BadInput) << e.what();
    return e.what();
  }
  return "";
}

TEST(VdbStructure, NonVdbInputsAreRefusedWithTheirOwnWords) {
  TempDir dir;
  const std::string vdb = dir.file("s.vdb");
  HamletOptions o;
  o.resolution = 8;
  writeSceneVdb(buildHamlet(o), vdb);
  EXPECT_EQ(openableMessage(vdb), "");
  EXPECT_EQ(openableMessage(dir.file("none.vdb")), dir.file("none.vdb") + ": no such file");
  EXPECT_EQ(openableMessage(dir.file("none/x.vdb")), dir.file("none/x.vdb") + ": no such file");
  EXPECT_EQ(openableMessage(dir.path().string()), dir.path().string() + ": is a directory, expected a .vdb file");
  const std::string fifo = dir.file("pipe.vdb");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(openableMessage(fifo), fifo +
                                       ": is not a regular file (a FIFO, socket or device); vox reads .vdb files only "
                                       "from regular files");
  EXPECT_EQ(openableMessage("/dev/null"),
            "/dev/null: is not a regular file (a FIFO, socket or device); vox reads .vdb files only from regular files");
  const std::string text = dir.file("t.vdb");
  writeBytes(text, "not a vdb at all");
  EXPECT_EQ(openableMessage(text), text + ": not an OpenVDB file (wrong magic number)");
  // A symbolic link is followed: to the scene it is accepted, to the directory refused as one.
  const std::string toScene = dir.file("l.vdb"), toDir = dir.file("ld.vdb");
  std::filesystem::create_symlink(vdb, toScene);
  std::filesystem::create_directory(dir.file("sub"));
  std::filesystem::create_symlink(dir.file("sub"), toDir);
  EXPECT_EQ(openableMessage(toScene), "");
  EXPECT_EQ(openableMessage(toDir), toDir + ": is a directory, expected a .vdb file");
  // Unreadable (not for root, who reads it anyway): the system's reason.
  const std::string locked = dir.file("locked.vdb");
  std::filesystem::copy_file(vdb, locked);
  ASSERT_EQ(chmod(locked.c_str(), 0), 0);
  if (::geteuid() != 0) {
    EXPECT_EQ(openableMessage(locked), locked + ": cannot open the file: Permission denied");
  }
  chmod(locked.c_str(), 0600);
  // Every other input keeps requireRegularFile's own words.
  EXPECT_TRUE(throwsVoxError([&] { requireRegularFile(fifo); }, ErrorKind::BadInput,
                             {fifo + ": is a FIFO (named pipe), expected a regular file"}));
  EXPECT_TRUE(throwsVoxError([&] { requireRegularFile(dir.path().string()); }, ErrorKind::BadInput,
                             {dir.path().string() + ": is a directory, expected a regular file"}));
}

TEST(VdbStructure, CorruptScenesAreRefusedOrReadNeverCrash) {
  TempDir dir;
  const Scene scene = hamlet(12);
  const std::string path = dir.file("scene.vdb");
  writeSceneVdb(scene, path);
  const std::string original = readBytes(path);
  const Outcomes o = corruptAll(original, path, "scene", [&] { return compareScenes(readSceneVdb(path), scene).same(); });
  std::cout << "[ scene    ] " << original.size() << " bytes: " << o.summary() << "\n";
  EXPECT_GT(o.refused, 0);
  EXPECT_GT(o.same, 0);
}

TEST(VdbStructure, CorruptPyramidsAreRefusedOrReadNeverCrash) {
  TempDir dir;
  const Scene base = hamlet(8);
  MipSettings settings;
  const std::vector<Scene> levels = buildMipPyramid(base, settings);
  std::vector<const Scene*> ptrs;
  for (const Scene& s : levels) ptrs.push_back(&s);
  const std::string path = dir.file("pyramid.vdb");
  writePyramidVdb(ptrs, MipOccupancy::Any, path);
  const std::string original = readBytes(path);
  const Outcomes o = corruptAll(original, path, "pyramid", [&] {
    const std::vector<Scene> got = readPyramidVdb(path);
    bool same = got.size() == levels.size();
    for (size_t i = 0; same && i < got.size(); ++i) same = compareScenes(got[i], levels[i]).same();
    return same;
  });
  std::cout << "[ pyramid  ] " << original.size() << " bytes: " << o.summary() << "\n";
  EXPECT_GT(o.refused, 0);
  EXPECT_GT(o.same, 0);
}

TEST(VdbStructure, CorruptLevelSetsAndFogVolumesAreRefusedOrReadNeverCrash) {
  ensureOpenVdbInitialized();
  TempDir dir;
  for (const auto& [name, grid] : {std::pair<std::string, openvdb::FloatGrid::Ptr>{"levelset", levelSet()},
                                   std::pair<std::string, openvdb::FloatGrid::Ptr>{"fog", fog()}}) {
    const std::string path = dir.file(name + ".vdb");
    writeGrids(path, {grid});
    const std::string original = readBytes(path);
    VdbGridInputOptions opt;
    opt.resolution = 12;
    if (name == "fog") opt.threshold = 0.5;  // a level set refuses one
    const Scene want = readVdbGridAsScene(path, opt);
    const Outcomes o = corruptAll(original, path, name, [&] {
      return compareScenes(readVdbGridAsScene(path, opt), want, /*ignoreSources=*/true).same();
    });
    std::cout << "[ " << name << " ] " << original.size() << " bytes: " << o.summary() << "\n";
    EXPECT_GT(o.refused, 0);
  }
}

TEST(VdbStructure, FuzzSeedsReadAndRegressionInputsAreRefusedCleanly) {
  ensureOpenVdbInitialized();
  namespace fs = std::filesystem;
  int seeds = 0, regressions = 0;
  for (const char* sub : {"tests/fuzz/vdb_seeds", "tests/fuzz/vdb_regressions"}) {
    const fs::path d = fs::path(voxtest::sourceDir()) / sub;
    if (!fs::is_directory(d)) continue;
    for (const auto& e : fs::directory_iterator(d)) {
      const std::string path = e.path().string();
      const bool seed = std::string(sub).find("seeds") != std::string::npos;
      (seed ? seeds : regressions)++;
      auto each = [&](const std::function<void()>& read) {
        try {
          read();
        } catch (const Error& err) {
          EXPECT_TRUE(err.kind == ErrorKind::BadInput || err.kind == ErrorKind::Usage) << path << ": " << err.what();
          EXPECT_NE(std::string(err.what()).find(path), std::string::npos) << err.what();
        } catch (const std::exception& err) {
          ADD_FAILURE() << path << ": not a vox::Error: " << err.what();
        }
      };
      if (seed) {
        EXPECT_NO_THROW(checkVdbStructure(path)) << path;
      }
      each([&] { readSceneVdb(path); });
      each([&] { readPyramidVdb(path); });
      // Without a threshold (level sets read) and with one (fog volumes read).
      for (const bool fog : {false, true})
        each([&] {
          VdbGridInputOptions o;
          o.resolution = 12;
          if (fog) o.threshold = 0.5;
          readVdbGridAsScene(path, o);
        });
    }
  }
  EXPECT_GE(seeds, 6);
  // What each regression input is refused for (it crashed or was undefined
  // behaviour before the fix).
  const fs::path reg = fs::path(voxtest::sourceDir()) / "tests/fuzz/vdb_regressions";
  for (const char* f : {"leaf_block_size_negative.vdb", "leaf_block_size_negative_1g.vdb"}) {
    const std::string path = (reg / f).string();
    EXPECT_TRUE(throwsVoxError([&] { readSceneVdb(path); }, ErrorKind::BadInput, {path, "leaf at (", "uncompressed block"}));
  }
  {
    const std::string path = (reg / "levelset_transform_beyond_index_range.vdb").string();
    VdbGridInputOptions o;
    o.resolution = 12;
    EXPECT_TRUE(throwsVoxError([&] { readVdbGridAsScene(path, o); }, ErrorKind::BadInput,
                               {path, "grid 'ball'", "beyond +-"}));
  }
  std::cout << "[ replayed ] " << seeds << " seeds, " << regressions << " regression inputs\n";
}
