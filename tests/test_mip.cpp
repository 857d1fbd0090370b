#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <tuple>

#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/scene/demo_hamlet.h"
#include "libvox/scene/mip.h"
#include "test_util.h"

namespace {

vox::SceneHeader smallHeader(vox::Dims d) {
  vox::SceneHeader h;
  h.dims = d;
  h.voxelSize = 0.5;
  h.origin = {1, 2, 3};
  h.classes.add({1, "a", {}, {}});
  h.classes.add({2, "b", {}, {}});
  h.classes.add({3, "c", {}, {}});
  return h;
}

std::vector<vox::ClassVotes> votesAt(const vox::Scene& s, vox::Coord3 c, bool* surface = nullptr,
                                     std::optional<vox::RgbLinear>* color = nullptr) {
  std::vector<vox::ClassVotes> storage;
  auto v = s.voxel(c, storage);
  if (!v) return {};
  if (surface) *surface = v->surface;
  if (color) *color = v->color;
  return std::vector<vox::ClassVotes>(v->votes.begin(), v->votes.end());
}

TEST(Mip, HandComputedLevelOne) {
  vox::SceneBuilder b(smallHeader({3, 3, 3}));
  // Block (0,0,0): children (0,0,0) class 1 x5 surface, (1,0,0) class 1 x7 + class 2 x2 interior,
  // (1,1,1) class 2 x9 interior.
  b.addVotes({0, 0, 0}, 1, 5, true);
  b.addVotes({1, 0, 0}, 1, 7, false);
  b.addVotes({1, 0, 0}, 2, 2, false);
  b.addVotes({1, 1, 1}, 2, 9, false);
  b.setColor({0, 0, 0}, {0.2f, 0.4f, 0.6f});
  b.setColor({1, 1, 1}, {0.6f, 0.0f, 0.2f});
  // Block (1,1,1) at the odd edge: only voxel (2,2,2) is inside the domain -> 1 child.
  b.addVotes({2, 2, 2}, 3, 4, false);
  // Block (1,0,0): one child of 4 inside the domain ((2,0..1,0..1)) -> 1 of 4 occupied.
  b.addVotes({2, 0, 0}, 3, 1, true);
  const vox::Scene fine = std::move(b).build();

  const vox::Scene any = vox::reduceScene(fine, vox::MipOccupancy::Any, 1);
  EXPECT_EQ(any.header().dims, (vox::Dims{2, 2, 2}));
  EXPECT_DOUBLE_EQ(any.header().voxelSize, 1.0);
  EXPECT_EQ(any.header().origin, (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(any.header().mipLevel, 1);
  EXPECT_EQ(any.occupiedCount(), 3u);
  bool surface = false;
  std::optional<vox::RgbLinear> color;
  auto v = votesAt(any, {0, 0, 0}, &surface, &color);
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0], (vox::ClassVotes{1, 12}));
  EXPECT_EQ(v[1], (vox::ClassVotes{2, 11}));
  EXPECT_TRUE(surface);  // OR of children
  ASSERT_TRUE(color);    // average of the two coloured children only
  EXPECT_FLOAT_EQ(color->r, 0.4f);
  EXPECT_FLOAT_EQ(color->g, 0.2f);
  EXPECT_FLOAT_EQ(color->b, 0.4f);
  v = votesAt(any, {1, 1, 1}, &surface, &color);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0], (vox::ClassVotes{3, 4}));
  EXPECT_FALSE(surface);
  EXPECT_FALSE(color);  // no coloured child
  EXPECT_EQ(votesAt(any, {1, 0, 0}).size(), 1u);

  // Majority: block (0,0,0) has 3 of 8 -> empty; (1,1,1) 1 of 1 -> kept; (1,0,0) 1 of 4 -> empty.
  const vox::Scene maj = vox::reduceScene(fine, vox::MipOccupancy::Majority, 1);
  EXPECT_EQ(maj.occupiedCount(), 1u);
  EXPECT_EQ(votesAt(maj, {1, 1, 1}).size(), 1u);
  EXPECT_EQ(maj.classesPresent(), std::vector<uint8_t>{3});  // only classes present keep a grid
  EXPECT_TRUE(maj.hasColor());  // the channel stays (it is a property of the scene)
}

TEST(Mip, MajorityTieKeepsTheVoxel) {
  vox::SceneBuilder b(smallHeader({2, 2, 2}));
  for (int i = 0; i < 4; ++i) b.addVotes({i & 1, i >> 1, 0}, 1, 1, true);  // a wall: 4 of 8
  const vox::Scene fine = std::move(b).build();
  EXPECT_EQ(vox::reduceScene(fine, vox::MipOccupancy::Majority).occupiedCount(), 1u);
  vox::SceneBuilder c(smallHeader({2, 2, 2}));
  for (int i = 0; i < 3; ++i) c.addVotes({i & 1, i >> 1, 0}, 1, 1, true);  // 3 of 8
  EXPECT_EQ(vox::reduceScene(std::move(c).build(), vox::MipOccupancy::Majority).occupiedCount(), 0u);
}

TEST(Mip, VotesSaturateAtInt32Max) {
  vox::SceneBuilder b(smallHeader({2, 1, 1}));
  b.addVotes({0, 0, 0}, 1, vox::kMaxVotesPerClass, true);
  b.addVotes({1, 0, 0}, 1, vox::kMaxVotesPerClass, true);
  b.addVotes({1, 0, 0}, 2, 3, true);
  const vox::Scene coarse = vox::reduceScene(std::move(b).build(), vox::MipOccupancy::Any);
  const auto v = votesAt(coarse, {0, 0, 0});
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].votes, vox::kMaxVotesPerClass);
  EXPECT_EQ(v[1].votes, 3u);
}

// A direct (map-based) reduction to check the leaf-wise one on a real scene.
vox::Scene bruteForceReduce(const vox::Scene& fine, bool majority) {
  std::map<std::tuple<int, int, int>, std::tuple<int, bool, std::map<uint8_t, uint64_t>>> acc;
  fine.forEachVoxel([&](const vox::VoxelView& v) {
    auto& a = acc[{v.at.u / 2, v.at.v / 2, v.at.w / 2}];
    ++std::get<0>(a);
    std::get<1>(a) = std::get<1>(a) || v.surface;
    for (const auto& c : v.votes) std::get<2>(a)[c.classId] += c.votes;
  });
  vox::SceneHeader h = fine.header();
  h.dims = vox::mipDims(h.dims, 1);
  h.voxelSize *= 2;
  h.mipLevel += 1;
  vox::SceneBuilder b(h);
  const vox::Dims fd = fine.header().dims;
  for (const auto& [k, a] : acc) {
    const auto [x, y, z] = k;
    auto in = [](int c, uint32_t d) { return 2 * c + 1 < int(d) ? 2 : 1; };
    const int children = in(x, fd.x) * in(y, fd.y) * in(z, fd.z);
    if (majority && 2 * std::get<0>(a) < children) continue;
    for (const auto& [cls, n] : std::get<2>(a))
      b.addVotes({x, y, z}, cls, uint32_t(std::min<uint64_t>(n, vox::kMaxVotesPerClass)), std::get<1>(a));
  }
  return std::move(b).build();
}

TEST(Mip, MatchesBruteForceOnTheHamletAtAnOddResolution) {
  vox::HamletOptions ho;
  ho.resolution = 45;
  const vox::Scene fine = vox::buildHamlet(ho);
  for (bool majority : {false, true}) {
    const auto mode = majority ? vox::MipOccupancy::Majority : vox::MipOccupancy::Any;
    const vox::Scene got = vox::reduceScene(fine, mode, 1);
    const vox::SceneDifference d = vox::compareScenes(got, bruteForceReduce(fine, majority));
    EXPECT_TRUE(d.same()) << d.headerNote << " " << d.firstNote;
    // Any thread count gives the same scene.
    EXPECT_TRUE(vox::compareScenes(got, vox::reduceScene(fine, mode, 3)).same());
  }
}

TEST(Mip, PyramidLevelsAndStoppingRules) {
  EXPECT_EQ(vox::maxMipLevels({256, 256, 256}), 8);
  EXPECT_EQ(vox::maxMipLevels({5, 1, 1}), 3);
  EXPECT_EQ(vox::maxMipLevels({1, 1, 1}), 0);
  EXPECT_EQ(vox::mipDims({5, 9, 1}, 2), (vox::Dims{2, 3, 1}));
  vox::HamletOptions ho;
  ho.resolution = 32;
  const vox::Scene fine = vox::buildHamlet(ho);
  vox::MipSettings s;
  const auto levels = vox::buildMipPyramid(fine, s);
  ASSERT_EQ(levels.size(), 5u);  // 16, 8, 4, 2, 1
  for (size_t i = 0; i < levels.size(); ++i) {
    EXPECT_EQ(levels[i].header().mipLevel, int(i) + 1);
    EXPECT_EQ(levels[i].header().dims.x, 32u >> (i + 1));
    EXPECT_DOUBLE_EQ(levels[i].header().voxelSize, fine.header().voxelSize * double(2u << i));
  }
  EXPECT_EQ(levels.back().occupiedCount(), 1u);
  // The root holds every vote of the scene.
  uint64_t total0 = 0, totalRoot = 0;
  fine.forEachVoxel([&](const vox::VoxelView& v) { total0 += v.totalVotes(); });
  levels.back().forEachVoxel([&](const vox::VoxelView& v) { totalRoot += v.totalVotes(); });
  EXPECT_EQ(total0, totalRoot);
  // Explicit level counts, and too many.
  s.levels = 2;
  EXPECT_EQ(vox::buildMipPyramid(fine, s).size(), 2u);
  s.levels = 6;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::buildMipPyramid(fine, s); }, vox::ErrorKind::Usage, {"at most 5"}));
  // One voxel in a big grid: nothing new below level 0.
  vox::SceneBuilder b(smallHeader({64, 64, 64}));
  b.addVotes({63, 0, 5}, 1, 1, true);
  EXPECT_TRUE(vox::buildMipPyramid(std::move(b).build(), vox::MipSettings{}).empty());
  // Two far-apart voxels: levels until they merge.
  vox::SceneBuilder c(smallHeader({64, 64, 64}));
  c.addVotes({0, 0, 0}, 1, 1, true);
  c.addVotes({63, 63, 63}, 2, 1, true);
  EXPECT_EQ(vox::buildMipPyramid(std::move(c).build(), vox::MipSettings{}).size(), 6u);
}

TEST(Mip, ComparisonAgainstDirectVoxelization) {
  vox::HamletOptions ho;
  ho.resolution = 64;
  const vox::Scene fine = vox::buildHamlet(ho);
  ho.resolution = 32;
  const vox::Scene direct = vox::buildHamlet(ho);
  const vox::Scene any = vox::reduceScene(fine, vox::MipOccupancy::Any);
  EXPECT_EQ(vox::placementMismatch(any.header(), direct.header()), "");
  const vox::MipComparison self = vox::compareWithReference(direct, direct);
  EXPECT_EQ(self.iou, 1.0);
  EXPECT_EQ(self.classDisagreement, 0.0);
  const vox::MipComparison c = vox::compareWithReference(any, direct);
  EXPECT_EQ(c.both + c.onlyMip, any.occupiedCount());
  EXPECT_EQ(c.both + c.onlyReference, direct.occupiedCount());
  EXPECT_GT(c.iou, 0.3);
  EXPECT_LT(c.iou, 1.0);
  // `any` is conservative: it misses nothing the direct voxelization has? Not exactly
  // (sampling at centres), but it has at least as many voxels.
  EXPECT_GE(any.occupiedCount(), direct.occupiedCount());
  ho.resolution = 31;
  EXPECT_NE(vox::placementMismatch(any.header(), vox::buildHamlet(ho).header()), "");
}

TEST(Mip, PyramidFileRoundTrip) {
  voxtest::TempDir dir;
  vox::SceneBuilder b(smallHeader({9, 4, 6}));
  b.addVotes({0, 0, 0}, 1, 5, true);
  b.addVotes({8, 3, 5}, 2, 7, false);
  b.addVotes({4, 2, 1}, 3, 1, true);
  b.setColor({0, 0, 0}, {0.25f, 0.5f, 1.0f});
  const vox::Scene base = std::move(b).build();
  const auto levels = vox::buildMipPyramid(base, vox::MipSettings{});
  ASSERT_EQ(levels.size(), 4u);
  std::vector<const vox::Scene*> all{&base};
  for (const auto& l : levels) all.push_back(&l);
  const std::string path = dir.file("p.vdb");
  vox::writePyramidVdb(all, vox::MipOccupancy::Any, path);
  EXPECT_TRUE(vox::isPyramidVdb(path));
  // Level 0 reads as a plain scene.
  EXPECT_TRUE(vox::compareScenes(vox::readSceneVdb(path), base).same());
  const auto back = vox::readPyramidVdb(path);
  ASSERT_EQ(back.size(), 5u);
  for (size_t i = 0; i < back.size(); ++i) {
    const vox::SceneDifference d = vox::compareScenes(back[i], *all[i]);
    EXPECT_TRUE(d.same()) << i << ": " << d.headerNote << " " << d.firstNote;
  }
  // A plain scene is a one-level pyramid.
  vox::writeSceneVdb(base, dir.file("s.vdb"));
  EXPECT_FALSE(vox::isPyramidVdb(dir.file("s.vdb")));
  EXPECT_EQ(vox::readPyramidVdb(dir.file("s.vdb")).size(), 1u);
}

}  // namespace

TEST(Mip, PyramidFileRefusals) {
  voxtest::TempDir dir;
  vox::SceneBuilder b(smallHeader({9, 4, 6}));
  b.addVotes({0, 0, 0}, 1, 5, true);
  b.addVotes({8, 3, 5}, 2, 7, false);
  const vox::Scene base = std::move(b).build();
  const auto levels = vox::buildMipPyramid(base, vox::MipSettings{});
  std::vector<const vox::Scene*> all{&base};
  for (const auto& l : levels) all.push_back(&l);
  const std::string good = dir.file("p.vdb");
  vox::writePyramidVdb(all, vox::MipOccupancy::Majority, good);
  openvdb::io::File in(good);
  in.open();
  const openvdb::GridPtrVecPtr grids = in.getGrids();
  const openvdb::MetaMap meta = *in.getMetadata();
  in.close();
  auto rewrite = [&](const std::string& name, openvdb::GridPtrVec g, const openvdb::MetaMap& m) {
    openvdb::io::File out(dir.file(name));
    out.write(g, m);
    out.close();
    return dir.file(name);
  };
  auto refused = [](const std::string& path, std::initializer_list<std::string> needles) {
    return voxtest::throwsVoxError([&] { vox::readPyramidVdb(path); }, vox::ErrorKind::BadInput, needles);
  };
  // The file as written reads back; the recorded occupancy is the one given.
  EXPECT_EQ(vox::readPyramidVdb(rewrite("same.vdb", *grids, meta)).size(), levels.size() + 1);
  EXPECT_NE(vox::readPyramidMetadata(good).find("\"occupancy\":\"majority\""), std::string::npos);
  // What `pack-chunks --mips` checks its options against: the stored occupancy and level count.
  const std::optional<vox::PyramidLevels> stored = vox::readPyramidLevels(good);
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->occupancy, vox::MipOccupancy::Majority);
  EXPECT_EQ(stored->levels, int(levels.size()));
  const std::string plain = dir.file("plain.vdb");
  vox::writeSceneVdb(base, plain);
  EXPECT_FALSE(vox::readPyramidLevels(plain).has_value());

  auto withPyramid = [&](const std::string& text) {
    openvdb::MetaMap m = meta;
    m.removeMeta("vox:pyramid");
    m.insertMeta("vox:pyramid", openvdb::StringMetadata(text));
    return m;
  };
  EXPECT_TRUE(refused(rewrite("json.vdb", *grids, withPyramid("{")), {"json.vdb", "'vox:pyramid'", "not valid JSON"}));
  EXPECT_TRUE(voxtest::throwsVoxError(
      [&] { vox::readPyramidLevels(rewrite("occ.vdb", *grids, withPyramid(R"({"occupancy":"most","levels":[]})"))); },
      vox::ErrorKind::BadInput, {"occ.vdb", "'vox:pyramid' 'occupancy': \"most\"", "\"any\" or \"majority\""}));
  EXPECT_TRUE(refused(rewrite("nolevels.vdb", *grids, withPyramid("{}")), {"'vox:pyramid'", "'levels'"}));
  EXPECT_TRUE(refused(rewrite("many.vdb", *grids, withPyramid(R"({"levels":[1,2,3,4,5]})")),
                      {"'vox:pyramid'", "lists 5 levels", "at most 4"}));
  // One level fewer in the table: the grids of the last level belong to no level.
  EXPECT_TRUE(refused(rewrite("stray.vdb", *grids, withPyramid(R"({"levels":[1,2,3]})")),
                      {"grid 'mip4.occupancy'", "mip<level>.<grid>"}));
  // A level without its occupancy grid, and a level grid of the wrong type.
  openvdb::GridPtrVec noOcc;
  for (const auto& g : *grids)
    if (g->getName() != "mip2.occupancy") noOcc.push_back(g);
  EXPECT_TRUE(refused(rewrite("noocc.vdb", noOcc, meta), {"level 2", "no grid named 'mip2.occupancy'"}));
  openvdb::GridPtrVec wrongType = noOcc;
  auto f = openvdb::FloatGrid::create(0);
  f->setName("mip2.occupancy");
  wrongType.push_back(f);
  EXPECT_TRUE(refused(rewrite("type.vdb", wrongType, meta), {"level 2", "'mip2.occupancy'", "expected bool"}));
  // Level 1's votes at a voxel its occupancy does not hold.
  openvdb::GridPtrVec moved;
  for (const auto& g : *grids) {
    if (g->getName() != "mip1.votes.1") {
      moved.push_back(g);
      continue;
    }
    auto v = openvdb::gridPtrCast<openvdb::Int32Grid>(g)->deepCopy();
    v->tree().setValueOn(openvdb::Coord(2, 1, 1), 3);
    moved.push_back(v);
  }
  EXPECT_TRUE(refused(rewrite("moved.vdb", moved, meta), {"level 1", "'mip1.votes.1'", "unoccupied voxel (2, 1, 1)"}));
}
