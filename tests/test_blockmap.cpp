// Block-map (map.json) import: placement, dims, surface flags, and every bad input.
#include <gtest/gtest.h>

#include "formats/vdb/blockmap_json.h"
#include "test_util.h"

using namespace vox;
using voxtest::throwsVoxError;

namespace {
Scene parse(const std::string& text, BlockMapOptions o = {}) { return parseBlockMap(text, "map.json", o); }
::testing::AssertionResult rejects(const std::string& text, std::initializer_list<std::string> needles,
                                   BlockMapOptions o = {}) {
  return throwsVoxError([&] { parse(text, o); }, ErrorKind::BadInput, needles);
}
/// The setting a refusal of `text` names for the fix.
Setting fixOf(const std::string& text, BlockMapOptions o = {}) {
  try {
    parse(text, o);
  } catch (const Error& e) {
    return e.setting;
  }
  return Setting::None;
}
}  // namespace

TEST(BlockMap, FormatExample) {
  Scene s = parse(R"({"sequence": 1, "worldScale": 2.0, "blocks": [
      {"position": [10, 5, 10], "blockType": "Stone"},
      {"position": [11, 5, 10], "blockType": "Grass"}]})");
  const SceneHeader& h = s.header();
  EXPECT_EQ(h.dims, (Dims{12, 6, 11})) << "dims run from 0 to the largest position + 1";
  EXPECT_EQ(h.voxelSize, 2.0);
  // block_to_world: (x - 64/2) * 2, y * 2, (z - 64/2) * 2 for the min corner of voxel 0.
  EXPECT_EQ(h.origin, (std::array<double, 3>{-64.0, 0.0, -64.0}));
  ASSERT_TRUE(h.blockWorld);
  EXPECT_EQ(h.blockWorld->gridSize, (std::array<uint32_t, 3>{64, 48, 64}));
  // World min corner of block (10, 5, 10) = ((10-32)*2, 5*2, (10-32)*2) as the format's block_to_world computes it.
  EXPECT_EQ(h.origin[0] + 10 * h.voxelSize, (10 - 32) * 2.0);
  EXPECT_EQ(h.origin[1] + 5 * h.voxelSize, 5 * 2.0);
  std::vector<ClassVotes> st;
  auto stone = s.voxel({10, 5, 10}, st);
  ASSERT_TRUE(stone);
  ASSERT_EQ(stone->votes.size(), 1u);
  EXPECT_EQ(stone->votes[0].classId, 3) << "the format's order: Air 0, Grass 1, Dirt 2, Stone 3";
  EXPECT_EQ(stone->votes[0].votes, 1u);
  EXPECT_TRUE(stone->surface);
  auto grass = s.voxel({11, 5, 10}, st);
  ASSERT_TRUE(grass);
  EXPECT_EQ(grass->votes[0].classId, 1);
  EXPECT_EQ(s.occupiedCount(), 2u);
  EXPECT_EQ(h.classes.size(), 7u);
  EXPECT_EQ(h.classes.find(7)->name, "Water");
}

TEST(BlockMap, InteriorBlocksAreNotSurfaceAndAirStaysEmpty) {
  std::string blocks;
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      for (int z = 0; z < 3; ++z) {
        if (!blocks.empty()) blocks += ",";
        blocks += "{\"position\":[" + std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(z) +
                  "],\"blockType\":\"Dirt\"}";
      }
  blocks += R"(,{"position":[5,0,0],"blockType":"Air"})";
  Scene s = parse(R"({"worldScale":1,"blocks":[)" + blocks + "]}");
  EXPECT_EQ(s.header().dims, (Dims{3, 3, 3})) << "Air blocks do not extend the dims";
  const SceneStats st = s.stats();
  EXPECT_EQ(st.occupied, 27u);
  EXPECT_EQ(st.surface, 26u) << "only the centre block has 6 solid neighbours";
  std::vector<ClassVotes> tmp;
  EXPECT_FALSE(s.voxel({1, 1, 1}, tmp)->surface);
}

TEST(BlockMap, GridSizeOption) {
  BlockMapOptions o;
  o.gridSize = {200, 10, 100};
  Scene s = parse(R"({"worldScale":0.5,"blocks":[{"position":[150,9,99],"blockType":"Sand"}]})", o);
  EXPECT_EQ(s.header().origin, (std::array<double, 3>{-50.0, 0.0, -25.0}));
  const std::string outside = R"({"worldScale":0.5,"blocks":[{"position":[150,10,0],"blockType":"Sand"}]})";
  EXPECT_TRUE(rejects(outside, {"block 0", "position y = 10", "outside the world grid 200,10,100", "larger block world grid"}, o));
  EXPECT_EQ(fixOf(outside, o), Setting::BlockWorldGrid);
  o.gridSize = {0, 10, 100};
  EXPECT_TRUE(throwsVoxError([&] { parse("{}", o); }, ErrorKind::Usage, {"block world's grid size", "1..2097152"}));
  EXPECT_EQ(fixOf("{}", o), Setting::BlockWorldGrid);
  EXPECT_EQ(BlockMapOptions{}.gridSize, kDefaultBlockWorldGrid);
}

TEST(BlockMap, BadInputsNameTheBlock) {
  EXPECT_TRUE(rejects("{not json", {"map.json", "not valid JSON"}));
  EXPECT_TRUE(rejects("[1,2]", {"JSON object"}));
  EXPECT_TRUE(rejects(R"({"blocks": []})", {"missing 'worldScale'"}));
  EXPECT_TRUE(rejects(R"({"worldScale": "big", "blocks": []})", {"'worldScale' must be a number"}));
  EXPECT_TRUE(rejects(R"({"worldScale": 0, "blocks": []})", {"'worldScale'", "> 0"}));
  EXPECT_TRUE(rejects(R"({"worldScale": -2, "blocks": []})", {"'worldScale'", "> 0"}));
  EXPECT_TRUE(rejects(R"({"worldScale": 1})", {"missing 'blocks'"}));
  EXPECT_TRUE(rejects(R"({"worldScale": 1, "blocks": {}})", {"'blocks' must be an array"}));
  EXPECT_TRUE(rejects(R"({"worldScale": 1, "blocks": []})", {"no solid blocks"}));
  EXPECT_TRUE(rejects(R"({"worldScale": 1, "blocks": [{"position":[0,0,0],"blockType":"Air"}]})", {"no solid blocks"}));
  const std::string ok = R"({"position":[0,0,0],"blockType":"Stone"},)";
  auto one = [&](const std::string& block) { return R"({"worldScale":1,"blocks":[)" + ok + block + "]}"; };
  EXPECT_TRUE(rejects(one(R"({"position":[1,0,0],"blockType":"Lava"})"), {"block 1", "unknown blockType 'Lava'", "Grass"}));
  EXPECT_TRUE(rejects(one(R"({"position":[1,0,0],"blockType":"stone"})"), {"block 1", "unknown blockType 'stone'"}));
  EXPECT_TRUE(rejects(one(R"({"position":[1,0,0],"blockType":3})"), {"block 1", "'blockType' must be a string"}));
  EXPECT_TRUE(rejects(one(R"({"position":[1,0,0]})"), {"block 1", "missing 'blockType'"}));
  EXPECT_TRUE(rejects(one(R"({"blockType":"Stone"})"), {"block 1", "missing 'position'"}));
  EXPECT_TRUE(rejects(one(R"({"position":[0,0,0],"blockType":"Dirt"})"), {"block 1", "already used by block 0"}));
  EXPECT_TRUE(rejects(one(R"({"position":[-1,0,0],"blockType":"Dirt"})"), {"block 1", "position x = -1", "negative"}));
  EXPECT_TRUE(rejects(one(R"({"position":[1.5,0,0],"blockType":"Dirt"})"), {"block 1", "position x = 1.5", "not an integer"}));
  EXPECT_TRUE(rejects(one(R"({"position":[2.0,0,0],"blockType":"Dirt"})"), {"block 1", "not an integer", "decimal point"}));
  EXPECT_TRUE(rejects(one(R"({"position":[1,"0",0],"blockType":"Dirt"})"), {"block 1", "position y is not a number"}));
  EXPECT_TRUE(rejects(one(R"({"position":[1,0],"blockType":"Dirt"})"), {"block 1", "array of 3 integers"}));
  EXPECT_TRUE(rejects(one(R"({"position":[64,0,0],"blockType":"Dirt"})"), {"block 1", "position x = 64", "outside the world grid 64,48,64"}));
  EXPECT_TRUE(rejects(one(R"({"position":[0,48,0],"blockType":"Dirt"})"), {"block 1", "position y = 48"}));
  EXPECT_TRUE(rejects(one(R"({"position":[0,0,99999999999999],"blockType":"Dirt"})"), {"block 1", "position z"}));
  EXPECT_TRUE(rejects(one(R"("Stone")"), {"block 1", "expected an object"}));
}

TEST(BlockMap, MissingFile) {
  EXPECT_TRUE(throwsVoxError([] { readBlockMap("/nonexistent/map.json"); }, ErrorKind::BadInput,
                             {"/nonexistent/map.json", "no such file"}));
}

TEST(BlockMap, RecordsItsSourceWithSha256) {
  voxtest::TempDir dir;
  const std::string path = dir.file("map.json");
  const std::string text = R"({"worldScale":1,"blocks":[{"position":[0,0,0],"blockType":"Snow"}]})";
  voxtest::writeText(path, text);
  Scene s = readBlockMap(path);
  ASSERT_EQ(s.header().sources.size(), 1u);
  EXPECT_EQ(s.header().sources[0].kind, "blockmap");
  EXPECT_EQ(s.header().sources[0].sha256.size(), 64u);
  EXPECT_EQ(s.header().sources[0].bytes, text.size());
}
