// The atlas metadata (formats/image/atlas_meta.h): the `vox:atlas` entry and
// the STEM.atlas.json sidecar read back what was written, through an image
// file too, and every malformed entry is refused naming the file.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "formats/image/atlas_meta.h"
#include "libvox/core/version.h"
#include "test_util.h"

using namespace vox;
using nlohmann::json;
using voxtest::throwsVoxError;

namespace {

std::vector<AtlasImageInfo> everyKind() {
  const AtlasLayout one = AtlasLayout::make({5, 3, 7});
  const AtlasLayout layered = AtlasLayout::make({64, 64, 70}, 0, 256);
  return {{one, AtlasContent::Summary, "rgba8", 0, 0, "s.vdb"},
          {one, AtlasContent::Identity, "rgba16f", 0, 0, "dir/s.vdb"},
          {one, AtlasContent::Color, "rgba8", 0, 0, ""},
          {one, AtlasContent::Votes, "r16", 0, 255, "s.vdb"},
          {layered, AtlasContent::Occupancy, "bitmap", 4, 0, "s.vdb"},
          {layered, AtlasContent::Occupancy2, "bitmap", 0, 0, "s.vdb"}};
}

/// `vox:atlas` of `info` with `key` set to `value` (removed when null).
std::string withKey(const AtlasImageInfo& info, const std::string& key, const json& value) {
  json j = atlasInfoJson(info);
  if (value.is_null()) j.erase(key);
  else j[key] = value;
  return j.dump();
}

}  // namespace

TEST(AtlasMeta, InfoRoundTripsForEveryContent) {
  for (const AtlasImageInfo& info : everyKind()) {
    EXPECT_EQ(atlasInfoFromJson(atlasInfoJson(info).dump(), "a.png"), info) << atlasInfoJson(info).dump();
    const auto text = atlasImageText(info);
    ASSERT_EQ(text.size(), 2u);
    EXPECT_EQ(text[0].first, kAtlasTextKey);
    EXPECT_EQ(text[1], (std::pair<std::string, std::string>{"Software", versionString()}));
  }
}

TEST(AtlasMeta, EntryHasTheDocumentedKeys) {
  const std::vector<AtlasImageInfo> kinds = everyKind();
  EXPECT_EQ(atlasInfoJson(kinds[0]).dump(), R"({"content":"summary","format":"rgba8","layer":0,"layout":)" +
                                                json::parse(kinds[0].layout.toJson()).dump() + R"(,"scene":"s.vdb"})");
  EXPECT_EQ(atlasInfoJson(kinds[3])["class_id"], 255);
  EXPECT_EQ(atlasInfoJson(kinds[4])["bits_per_voxel"], 1);
  EXPECT_EQ(atlasInfoJson(kinds[5])["bits_per_voxel"], 2);
  EXPECT_FALSE(atlasInfoJson(kinds[0]).contains("class_id"));
}

TEST(AtlasMeta, ImageFilesRoundTrip) {
  voxtest::TempDir dir;
  for (const AtlasImageInfo& info : everyKind()) {
    const bool bitmap = info.content == AtlasContent::Occupancy || info.content == AtlasContent::Occupancy2;
    const uint32_t perByte = info.content == AtlasContent::Occupancy ? 8 : 4;
    const uint32_t width = bitmap ? (info.layout.width + perByte - 1) / perByte : info.layout.width;
    Image img(width, info.layout.height, bitmap || info.content == AtlasContent::Votes ? 1 : 4, SampleType::U8);
    img.text = atlasImageText(info);
    const std::string path = dir.file(std::string(atlasContentName(info.content)) + ".png");
    writePng(img, path);
    AtlasImageInfo back;
    readAtlasImage(path, back);
    EXPECT_EQ(back, info) << path;
  }
}

TEST(AtlasMeta, SidecarRoundTrips) {
  const std::vector<AtlasImageInfo> kinds = everyKind();
  std::vector<AtlasSidecarEntry> files;
  for (size_t i = 0; i < 4; ++i) files.push_back({kinds[i], "s.file" + std::to_string(i) + ".png"});
  for (AtlasSidecarEntry& f : files) f.info.scene = "s.vdb";  // one scene per sidecar
  const std::string text = atlasSidecarJson("s.vdb", kinds[0].layout, files);
  EXPECT_EQ(text.back(), '\n');
  const json side = json::parse(text);
  EXPECT_FALSE(side["files"][0].contains("layout")) << "the layout is written once";
  EXPECT_FALSE(side["files"][0].contains("scene"));
  EXPECT_EQ(atlasSidecarFromJson(text, "s.atlas.json"), files);
  EXPECT_TRUE(atlasSidecarFromJson(atlasSidecarJson("s.vdb", kinds[0].layout, {}), "s.atlas.json").empty());
}

TEST(AtlasMeta, RefusesEachMalformedEntry) {
  const AtlasImageInfo votes = everyKind()[3];
  auto refused = [](const std::string& text, std::initializer_list<std::string> needles) {
    return throwsVoxError([&] { atlasInfoFromJson(text, "a.png"); }, ErrorKind::BadInput, needles);
  };
  EXPECT_TRUE(refused("{", {"a.png", "malformed"}));
  EXPECT_TRUE(refused("[]", {"a.png", "malformed"}));
  for (const char* key : {"layout", "content", "format", "layer"})
    EXPECT_TRUE(refused(withKey(votes, key, nullptr), {"a.png", key})) << key;
  EXPECT_TRUE(refused(withKey(votes, "content", "depth"), {"a.png", "unknown atlas content", "depth"}));
  EXPECT_TRUE(refused(withKey(votes, "content", 3), {"a.png", "malformed"}));
  EXPECT_TRUE(refused(withKey(votes, "layer", -1), {"a.png", "\"layer\""}));
  EXPECT_TRUE(refused(withKey(votes, "layer", 0.5), {"a.png", "\"layer\""}));
  EXPECT_TRUE(refused(withKey(votes, "layer", 1), {"a.png", "layer 1", "1 layers"}));
  EXPECT_TRUE(refused(withKey(votes, "class_id", 256), {"a.png", "class_id"}));
  EXPECT_TRUE(refused(withKey(votes, "scene", 5), {"a.png", "malformed"}));
  json layout = atlasInfoJson(votes)["layout"];
  layout["width"] = layout["width"].get<int>() + 1;
  EXPECT_TRUE(refused(withKey(votes, "layout", layout), {"a.png", "inconsistent atlas layout"}));
  layout.erase("width");
  EXPECT_TRUE(refused(withKey(votes, "layout", layout), {"a.png", "width"}));
}

TEST(AtlasMeta, RefusesMalformedSidecarsAndImages) {
  auto refused = [](const std::string& text, std::initializer_list<std::string> needles) {
    return throwsVoxError([&] { atlasSidecarFromJson(text, "s.atlas.json"); }, ErrorKind::BadInput, needles);
  };
  const AtlasImageInfo info = everyKind()[0];
  const json good = json::parse(atlasSidecarJson("s.vdb", info.layout, {{info, "a.png"}}));
  EXPECT_TRUE(refused("nope", {"s.atlas.json"}));
  for (const char* key : {"layout", "files"}) {
    json j = good;
    j.erase(key);
    EXPECT_TRUE(refused(j.dump(), {"s.atlas.json", "\"layout\" and a \"files\" array"})) << key;
  }
  json noFile = good;
  noFile["files"][0].erase("file");
  EXPECT_TRUE(refused(noFile.dump(), {"s.atlas.json: files[0]", "\"file\""}));
  json badContent = good;
  badContent["files"][0]["content"] = "x";
  EXPECT_TRUE(refused(badContent.dump(), {"s.atlas.json: files[0]", "unknown atlas content"}));

  voxtest::TempDir dir;
  Image plain(4, 4, 1, SampleType::U8);
  writePng(plain, dir.file("plain.png"));
  AtlasImageInfo back;
  EXPECT_TRUE(throwsVoxError([&] { readAtlasImage(dir.file("plain.png"), back); }, ErrorKind::BadInput,
                             {"plain.png", "no \"vox:atlas\" metadata"}));
  Image wrongSize(info.layout.width + 1, info.layout.height, 4, SampleType::U8);
  wrongSize.text = atlasImageText(info);
  writePng(wrongSize, dir.file("size.png"));
  const std::string height = " x " + std::to_string(info.layout.height);
  EXPECT_TRUE(throwsVoxError([&] { readAtlasImage(dir.file("size.png"), back); }, ErrorKind::BadInput,
                             {"size.png", "is " + std::to_string(info.layout.width + 1) + height,
                              "layout says " + std::to_string(info.layout.width) + height}));
  voxtest::writeText(dir.file("text.png"), "not an image");
  EXPECT_TRUE(throwsVoxError([&] { readAtlasImage(dir.file("text.png"), back); }, ErrorKind::BadInput,
                             {"text.png", "not a PNG or EXR"}));
}
