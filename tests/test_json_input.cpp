// parseJsonInput (formats/core/json_input.h): every JSON document vox reads
// refuses an object that names a key twice, naming the document, the key and
// the object.
#include <gtest/gtest.h>

#include "formats/core/camera_json.h"
#include "formats/core/json_input.h"
#include "libvox/core/error.h"

namespace {

std::string duplicateMessage(const std::string& text) {
  try {
    vox::parseJsonInput(text, "in.json");
  } catch (const vox::Error& e) {
    EXPECT_EQ(e.kind, vox::ErrorKind::BadInput);
    return e.what();
  }
  return "";
}

}  // namespace

TEST(JsonInput, RefusesDuplicateKeysNamingTheObject) {
  EXPECT_EQ(duplicateMessage(R"({"a": 1, "b": 2, "a": 3})"),
            "in.json: duplicate key \"a\" in the top-level object: JSON keeps only one of the values; remove the other");
  EXPECT_NE(duplicateMessage(R"({"cameras": [{"eye": [0,0,1]}, {"fov": 40, "eye": [1,2,3], "fov": 60}]})")
                .find("duplicate key \"fov\" in cameras[1]:"),
            std::string::npos);
  EXPECT_NE(duplicateMessage(R"({"grid": {"dims": [1,1,1], "origin": {"x": 0, "x": 1}}})")
                .find("duplicate key \"x\" in grid.origin:"),
            std::string::npos);
  EXPECT_NE(duplicateMessage(R"({"v": [1, [2, 3], {"k": 1}, {"k": 1, "k": 2}]})").find("in v[3]:"), std::string::npos)
      << "array positions count primitives, arrays and objects alike";
  EXPECT_NE(duplicateMessage(R"([{"a": 1}, {"a": 1, "a": 1}])").find("in [1]:"), std::string::npos);
}

TEST(JsonInput, AcceptsWhatIsNotADuplicate) {
  // The same key in different objects, keys that differ only in case, nested same names.
  const nlohmann::json j =
      vox::parseJsonInput(R"({"a": {"a": {"a": 1}}, "A": 2, "list": [{"a": 1}, {"a": 2}], "b": []})", "in.json");
  EXPECT_EQ(j["a"]["a"]["a"], 1);
  EXPECT_EQ(j["list"][1]["a"], 2);
  EXPECT_EQ(vox::parseJsonInput("[]", "x"), nlohmann::json::array());
  EXPECT_EQ(vox::parseJsonInput("3", "x"), 3);
}

// Objects with many keys (past the short list the parser searches in order),
// and the same object's key list reused at one depth: a duplicate is found
// wherever it is, and the keys of one object never leak into the next.
TEST(JsonInput, ManyKeysAndSiblingObjects) {
  std::string many = "{";
  for (int i = 0; i < 300; ++i) many += (i ? ",\"k" : "\"k") + std::to_string(i) + "\": " + std::to_string(i);
  EXPECT_EQ(vox::parseJsonInput(many + "}", "m.json").size(), 300u);
  for (int dup : {0, 5, 23, 24, 25, 299}) {
    const std::string text = many + ", \"k" + std::to_string(dup) + "\": 1}";
    EXPECT_EQ(duplicateMessage("{\"outer\": [0, " + text + "]}"),
              "in.json: duplicate key \"k" + std::to_string(dup) +
                  "\" in outer[1]: JSON keeps only one of the values; remove the other");
  }
  const std::string siblings = "[" + many + "}, " + many + "}, {\"k1\": {\"k1\": [" + many + "}]}}]";
  EXPECT_EQ(vox::parseJsonInput(siblings, "s.json").size(), 3u);
}

TEST(JsonInput, SyntaxErrorsStayTheReadersToWord) {
  EXPECT_THROW(vox::parseJsonInput("{\"a\": ", "x"), nlohmann::json::exception);
  EXPECT_TRUE(vox::parseJsonInputOrDiscarded("{\"a\": ", "x").is_discarded());
  EXPECT_THROW(vox::parseJsonInputOrDiscarded(R"({"a": 1, "a": 2})", "x"), vox::Error);
}

TEST(JsonInput, CameraFilesRefuseDuplicateKeys) {
  try {
    vox::parseCameraJson(R"({"eye": [0, 0, 10], "target": [0, 0, 0], "fov": 30, "fov": 90})", "cam.json", std::nullopt);
    FAIL() << "a camera with two fov keys was read";
  } catch (const vox::Error& e) {
    EXPECT_EQ(e.kind, vox::ErrorKind::BadInput);
    EXPECT_NE(std::string(e.what()).find("cam.json: duplicate key \"fov\" in the top-level object"), std::string::npos)
        << e.what();
  }
}
