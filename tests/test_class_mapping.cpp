#include <gtest/gtest.h>

#include "formats/mesh/classes_json.h"
#include "test_util.h"

using namespace vox;

namespace {
Mesh twoParts() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 1, 2}, {0, 1, 2}};
  m.materials = {{"RoofTiles", {0.5f, 0.1f, 0.1f, 1}}, {"Plaster", {1, 1, 1, 1}}, {"", {0, 0, 0, 1}}};
  m.parts = {{"house/roof", "roofMesh"}, {"house/wall", "wallMesh"}};
  m.triangleMaterial = {0, 1, 2};
  m.trianglePart = {0, 1, 1};
  return m;
}
}  // namespace

TEST(ClassMapping, OneClassPerMaterialByDefault) {
  const Mesh m = twoParts();
  const ClassMapping c = classPerMaterial(m, "m.glb");
  EXPECT_EQ(c.table.size(), 3u);
  EXPECT_EQ(c.table.find(1)->name, "RoofTiles");
  EXPECT_EQ(c.table.find(3)->name, "material 2");
  EXPECT_EQ(c.table.find(2)->color, (Rgb8{255, 255, 255}));
  EXPECT_EQ(c.table.find(1)->color, (Rgb8{188, 89, 89})) << "linear 0.5 / 0.1 encoded as sRGB";
  EXPECT_EQ(assignClasses(m, c), (std::vector<uint8_t>{1, 2, 3}));
}

TEST(ClassMapping, RulesInOrderWithFieldsAndDefault) {
  const Mesh m = twoParts();
  const ClassMapping c = parseClassMapping(R"({"classes": [
      {"id": 5, "name": "roof", "color": "#b43c32", "match": ["material:Roof*"]},
      {"id": 9, "name": "wall", "color": [200, 200, 200], "match": ["node:house/*", "nothing"]},
      {"name": "other"}], "default": "other"})", "c.json");
  EXPECT_EQ(c.table.find(5)->color, (Rgb8{0xb4, 0x3c, 0x32}));
  EXPECT_EQ(c.table.find(3)->name, "other") << "id defaults to the position + 1";
  EXPECT_EQ(assignClasses(m, c), (std::vector<uint8_t>{5, 9, 9}));
  const ClassMapping strict = parseClassMapping(R"({"classes": [{"name": "roof", "match": ["mesh:roofMesh"]}]})", "c.json");
  EXPECT_TRUE(voxtest::throwsVoxError([&] { assignClasses(m, strict); }, ErrorKind::BadInput,
                                      {"triangle 1", "Plaster", "wallMesh", "house/wall", "default"}));
  EXPECT_EQ(voxtest::settingOfError([&] { assignClasses(m, strict); }), Setting::ClassRules);
}

TEST(ClassMapping, TooManyMaterialsAskForClassRules) {
  // Classes are per material name: 256 distinct names do not fit.
  Mesh m = twoParts();
  m.materials.resize(256);
  for (size_t i = 0; i < m.materials.size(); ++i) m.materials[i].name = "m" + std::to_string(i);
  EXPECT_TRUE(voxtest::throwsVoxError([&] { classPerMaterial(m, "m.glb"); }, ErrorKind::BadInput,
                                      {"m.glb", "256 distinct material names", "at most 255 classes", "class rules"}));
  EXPECT_EQ(voxtest::settingOfError([&] { classPerMaterial(m, "m.glb"); }), Setting::ClassRules);
  m.materials.resize(255);
  EXPECT_EQ(classPerMaterial(m, "m.glb").table.size(), 255u) << "255 materials still fit";
}

TEST(ClassMapping, BadFilesNameTheEntry) {
  auto bad = [](const std::string& text, std::initializer_list<std::string> needles) {
    return voxtest::throwsVoxError([&] { parseClassMapping(text, "c.json"); }, ErrorKind::BadInput, needles);
  };
  EXPECT_TRUE(bad("{", {"c.json", "not valid JSON"}));
  EXPECT_TRUE(bad(R"({"classes": {}})", {"\"classes\" array"}));
  EXPECT_TRUE(bad(R"({"classes": [{"id": 1}]})", {"classes[0]", "name"}));
  EXPECT_TRUE(bad(R"({"classes": [{"name": "a", "id": 300}]})", {"classes[0]", "1..255"}));
  EXPECT_TRUE(bad(R"({"classes": [{"name": "a", "color": "red"}]})", {"classes[0] \"color\""}));
  EXPECT_TRUE(bad(R"({"classes": [{"name": "a"}, {"name": "a"}]})", {"classes[1]", "used twice"}));
  EXPECT_TRUE(bad(R"({"classes": [{"name": "a", "match": "x"}]})", {"\"match\" must be an array"}));
  EXPECT_TRUE(bad(R"({"classes": [{"name": "a"}], "default": "b"})", {"'b'"}));
  EXPECT_TRUE(bad(R"({"classes": []})", {"empty"}));
  // Keys nothing reads are refused by name: a misspelt "match" mapped nothing.
  EXPECT_TRUE(bad(R"({"classes": [{"name": "a", "matches": ["*"]}]})",
                  {"c.json", "classes[0] has no key \"matches\"", "id, name, color, top, bottom, side, match"}));
  EXPECT_TRUE(bad(R"({"classes": [{"name": "a"}], "defualt": "a"})", {"the rules file has no key \"defualt\""}));
}
