// The scene file's metadata keys and grid names (formats/scene/scene_meta.h)
// and the class table's JSON (formats/scene/class_table_json.h): what the
// writers write reads back equal, and every malformed value is refused with
// the key or entry named.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "formats/scene/class_table_json.h"
#include "formats/scene/scene_meta.h"
#include "test_util.h"

using namespace vox;
using nlohmann::json;
using voxtest::throwsVoxError;

namespace {

SceneHeader fullHeader() {
  SceneHeader h;
  h.dims = {5, 3, 70};
  h.voxelSize = 0.1 + 0.2;  // not a short decimal: must round-trip exactly
  h.origin = {-1.5, 2.0, 1e6};
  h.classes.add({1, "ground", {10, 20, 30}, FacePalette{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}});
  h.classes.add({7, "wall \"quoted\"", {200, 100, 50}, std::nullopt});
  h.classes.add({255, "last class", {255, 255, 255}, std::nullopt});
  h.sources.push_back({"in/mesh.obj", "mesh", std::string(64, 'a'), 1234});
  h.sources.push_back({"demo:hamlet", "demo", "", 0});
  h.mipLevel = 2;
  h.blockWorld = BlockWorldPlacement{2.0, {10, 20, 30}};
  return h;
}

/// The metadata of fullHeader() with `key` replaced by `value` (or removed when nullopt).
MetaEntries withKey(const std::string& key, std::optional<MetaValue> value) {
  MetaEntries meta = sceneFileMetadata(fullHeader());
  meta.erase(key);
  if (value) meta[key] = *value;
  return meta;
}

::testing::AssertionResult refused(const MetaEntries& meta, std::initializer_list<std::string> needles) {
  return throwsVoxError([&] { sceneHeaderFromMetadata(meta, "s.vdb"); }, ErrorKind::BadInput, needles);
}

/// The class array of fullHeader() with entry `i` replaced.
std::string classesWithEntry(size_t i, const json& entry) {
  json arr = classTableToJson(fullHeader().classes);
  arr[i] = entry;
  return arr.dump();
}

}  // namespace

TEST(SceneMeta, WriteThenReadGivesTheSameHeader) {
  const SceneHeader h = fullHeader();
  EXPECT_EQ(sceneHeaderFromMetadata(sceneFileMetadata(h), "s.vdb"), h);
  SceneHeader plain;
  plain.dims = {1, 1, 1};
  plain.classes.add({3, "only", {0, 0, 0}, std::nullopt});
  EXPECT_EQ(sceneHeaderFromMetadata(sceneFileMetadata(plain), "s.vdb"), plain);
  EXPECT_FALSE(sceneFileMetadata(plain).contains("vox:block_world"));
}

TEST(SceneMeta, KeysAndTypesAreTheDocumentedOnes) {
  const MetaEntries meta = sceneFileMetadata(fullHeader());
  const std::map<std::string, std::string> types = {
      {"vox:format", "string"},   {"vox:format_version", "int32"}, {"vox:tool_version", "string"},
      {"vox:dims", "vec3i"},      {"vox:voxel_size", "double"},    {"vox:origin", "vec3d"},
      {"vox:mip_level", "int32"}, {"vox:classes", "string"},       {"vox:sources", "string"},
      {"vox:block_world", "string"}};
  ASSERT_EQ(meta.size(), types.size());
  for (const auto& [key, type] : types) {
    ASSERT_TRUE(meta.contains(key)) << key;
    EXPECT_EQ(metaTypeName(meta.at(key)), type) << key;
  }
  EXPECT_EQ(std::get<std::string>(meta.at("vox:format")), "voxbake-scene");
  EXPECT_EQ(std::get<std::string>(meta.at("vox:block_world")), R"({"gridSize":[10,20,30],"worldScale":2.0})");
  const std::string firstClass =
      R"([{"bottom":[4,5,6],"color":[10,20,30],"id":1,"name":"ground","side":[7,8,9],"top":[1,2,3]},{)";
  EXPECT_EQ(std::get<std::string>(meta.at("vox:classes")).substr(0, firstClass.size()), firstClass);
}

TEST(SceneMeta, GridMetadata) {
  const ClassTable classes = fullHeader().classes;
  const MetaEntries votes = voteGridMetadata(classes, 7);
  EXPECT_EQ(std::get<int32_t>(votes.at("vox:class_id")), 7);
  EXPECT_EQ(std::get<std::string>(votes.at("vox:class_name")), "wall \"quoted\"");
  EXPECT_EQ(std::get<std::string>(voteGridMetadata(classes, 9).at("vox:class_name")), "");
  EXPECT_EQ(std::get<std::string>(colorGridMetadata().at("vox:color_space")), "linear");
  EXPECT_EQ(std::get<int32_t>(pyramidLevelGridMetadata(3).at("vox:mip_level")), 3);
}

TEST(SceneMeta, VoteGridNamesRoundTripAndOnlyThose) {
  for (int id = 1; id <= 255; ++id) EXPECT_EQ(classIdOfVoteGridName(voteGridName(uint8_t(id))), uint8_t(id));
  for (const char* bad : {"votes.0", "votes.01", "votes.256", "votes.", "votes.x", "votes.1x", "votes.+1", "votes.-1",
                          "votes.1000", "vote.1", "occupancy"})
    EXPECT_FALSE(classIdOfVoteGridName(bad)) << bad;
  EXPECT_TRUE(looksLikeVoteGridName("votes.x"));
  EXPECT_FALSE(looksLikeVoteGridName("mip1.votes.1"));
}

TEST(SceneMeta, RefusesMissingOrMistypedKeys) {
  for (const char* key : {"vox:format", "vox:format_version", "vox:dims", "vox:voxel_size", "vox:origin",
                          "vox:mip_level", "vox:classes"})
    EXPECT_TRUE(refused(withKey(key, std::nullopt), {"s.vdb", key, "missing"})) << key;
  EXPECT_TRUE(refused(withKey("vox:dims", std::string("5,3,70")), {"'vox:dims'", "type string", "expected vec3i"}));
  EXPECT_TRUE(refused(withKey("vox:voxel_size", int32_t(1)), {"'vox:voxel_size'", "expected double"}));
  EXPECT_TRUE(refused(withKey("vox:classes", ForeignMetaValue{"float"}), {"'vox:classes'", "type float"}));
  EXPECT_TRUE(refused(withKey("vox:sources", int32_t(0)), {"'vox:sources'", "expected string"}));
}

TEST(SceneMeta, RefusesValuesOutOfRange) {
  EXPECT_TRUE(refused(withKey("vox:format", std::string("other")), {"'other'", "voxbake-scene"}));
  EXPECT_TRUE(refused(withKey("vox:format_version", int32_t(99)), {"version 99", "upgrade"}));
  EXPECT_TRUE(refused(withKey("vox:format_version", int32_t(0)), {"version 0"}));
  EXPECT_TRUE(refused(withKey("vox:dims", std::array<int32_t, 3>{5, 0, 70}), {"'vox:dims'", ">= 1"}));
  for (double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_TRUE(refused(withKey("vox:voxel_size", bad), {"'vox:voxel_size'", "finite and > 0"})) << bad;
}

TEST(SceneMeta, RefusesMalformedJsonValues) {
  EXPECT_TRUE(refused(withKey("vox:classes", std::string("[{")), {"'vox:classes'", "not valid JSON"}));
  EXPECT_TRUE(refused(withKey("vox:classes", std::string("{}")), {"'vox:classes'", "array"}));
  EXPECT_TRUE(refused(withKey("vox:sources", std::string("{}")), {"'vox:sources'", "array"}));
  EXPECT_TRUE(refused(withKey("vox:sources", std::string(R"([{"path":"a","kind":"mesh","sha256":""}])")),
                      {"'vox:sources'[0]", "\"bytes\""}));
  EXPECT_TRUE(refused(withKey("vox:sources", std::string(R"([{"path":1,"kind":"mesh","sha256":"","bytes":1}])")),
                      {"'vox:sources'[0]", "\"path\""}));
  EXPECT_TRUE(refused(withKey("vox:block_world", std::string(R"({"gridSize":[1,2,3]})")),
                      {"'vox:block_world'", "worldScale"}));
  EXPECT_TRUE(refused(withKey("vox:block_world", std::string(R"({"worldScale":1,"gridSize":[1,2]})")),
                      {"'vox:block_world'", "gridSize"}));
  EXPECT_TRUE(refused(withKey("vox:block_world", std::string(R"({"worldScale":1,"gridSize":[1,-2,3]})")),
                      {"'vox:block_world'", "gridSize"}));
}

TEST(SceneMeta, RefusesEachMalformedClassEntry) {
  auto entry = [](const std::string& text) { return std::optional<MetaValue>(classesWithEntry(1, json::parse(text))); };
  const std::string where = "'vox:classes'[1]";
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"(7)")), {where, "object"}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"name":"w","color":[1,2,3]})")), {where, "\"id\""}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":"7","name":"w","color":[1,2,3]})")), {where, "\"id\""}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":0,"name":"w","color":[1,2,3]})")), {where, "1..255"}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":256,"name":"w","color":[1,2,3]})")), {where, "1..255"}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"color":[1,2,3]})")), {where, "\"name\""}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"name":""})")), {where, "\"color\""}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"name":"w","color":[1,2]})")), {where, "\"color\""}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"name":"w","color":[1,2,256]})")), {where, "0..255"}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"name":"w","color":"#010203"})")), {where, "\"color\""}))
      << "hex colours are the rules file's form only";
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"name":"","color":[1,2,3]})")), {"empty name"}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":1,"name":"w","color":[1,2,3]})")), {where, "used twice"}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"name":"ground","color":[1,2,3]})")), {where, "used twice"}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"name":"w","color":[1,2,3],"top":[1,1,1],"side":[2,2,2]})")),
                      {where, "all of \"top\", \"bottom\" and \"side\" or none"}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"name":"w","color":[1,2,3],"bottom":[1,1,1]})")),
                      {where, "or none"}));
  EXPECT_TRUE(refused(withKey("vox:classes", entry(R"({"id":7,"name":"w","color":[1,2,3],"top":[1,1,1],"bottom":[1,1,1],"side":"x"})")),
                      {where, "\"side\""}));
}

TEST(ClassTableJson, StoredFormRoundTrips) {
  const ClassTable t = fullHeader().classes;
  EXPECT_EQ(classTableFromJson(classTableToJson(t), ClassJsonForm::Stored, "t"), t);
  EXPECT_EQ(classTableFromJson(classTableToJson(blockPalette()), ClassJsonForm::Stored, "t"), blockPalette());
  EXPECT_EQ(classTableFromJson(json::array(), ClassJsonForm::Stored, "t"), ClassTable());
  EXPECT_EQ(classTableJson(t), classTableToJson(t).dump());
}

TEST(ClassTableJson, HandWrittenFormFillsDefaultsAndTakesHex) {
  const json arr = json::parse(R"([{"name":"a"}, {"id":9,"name":"b","color":"#0aFf10"},
      {"name":"c","top":"#010203","bottom":[4,5,6],"side":[7,8,9]}])");
  const ClassTable t = classTableFromJson(arr, ClassJsonForm::HandWritten, "rules.json: classes");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(*t.find(1), (ClassInfo{1, "a", {128, 128, 128}, std::nullopt})) << "id = position + 1, grey";
  EXPECT_EQ(t.find(9)->color, (Rgb8{10, 255, 16}));
  EXPECT_EQ(*t.find(3), (ClassInfo{3, "c", {128, 128, 128}, FacePalette{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}}));
  for (const char* bad : {"#01020", "#0102034", "010203", "#01020g", "#-10203"})
    EXPECT_TRUE(throwsVoxError([&] { classInfoFromJson(json{{"name", "x"}, {"color", bad}}, 0, ClassJsonForm::HandWritten, "r"); },
                               ErrorKind::BadInput, {"r[0] \"color\"", "#rrggbb"}))
        << bad;
  EXPECT_TRUE(throwsVoxError(
      [&] { classInfoFromJson(json{{"name", "x"}, {"top", "#010203"}}, 4, ClassJsonForm::HandWritten, "r"); },
      ErrorKind::BadInput, {"r[4]", "or none"}))
      << "the partial-palette rule is the same in both forms";
}

TEST(SceneMeta, PyramidLevelPrefixIsMipDigitsDot) {
  for (size_t level : {1u, 2u, 12u}) EXPECT_TRUE(vox::hasPyramidLevelPrefix(vox::pyramidGridPrefix(level) + "occupancy"));
  for (const char* name : {"occupancy", "votes.3", "color", "free", "mip", "mip.occupancy", "mipmap.x", "mip3", "xmip1.a"})
    EXPECT_FALSE(vox::hasPyramidLevelPrefix(name)) << name;
}
