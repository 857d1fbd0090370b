// The atlas metadata (formats/image/atlas_meta.h): the `vox:atlas` entry and
// the STEM.atlas.json sidecar read back what was written, through an image
// file too, and every malformed entry is refused naming the file.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <tuple>

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
    const SampleType type = info.format == "rgba16f" ? SampleType::F16 : info.format == "r16" ? SampleType::U16 : SampleType::U8;
    Image img(width, info.layout.height, bitmap || info.content == AtlasContent::Votes ? 1 : 4, type);
    img.text = atlasImageText(info);
    const AtlasImageShape shape = atlasImageShape(info, "a.png");
    EXPECT_EQ(std::tie(shape.width, shape.height, shape.channels), std::tie(img.width, img.height, img.channels));
    EXPECT_EQ(shape.type, type);
    const bool exr = type == SampleType::F16;
    const std::string path = dir.file(std::string(atlasContentName(info.content)) + (exr ? ".exr" : ".png"));
    if (exr) writeExr(img, path);
    else writePng(img, path);
    AtlasImageInfo back;
    readAtlasImage(path, back);
    EXPECT_EQ(back, info) << path;
  }
}

TEST(AtlasMeta, AnImageMustHaveTheShapeItsEntryGives) {
  // diff compared such images (exit 0) while info and verify-bijection
  // refused them: one reader for all three.
  const AtlasImageInfo summary = everyKind()[0];
  Image img(summary.layout.width, summary.layout.height, 4, SampleType::U8);
  img.text = atlasImageText(summary);
  ASSERT_TRUE(atlasInfoOfImage(img, "a.png"));
  EXPECT_EQ(*atlasInfoOfImage(img, "a.png"), summary);
  EXPECT_FALSE(atlasInfoOfImage(Image(2, 2, 4, SampleType::U8), "plain.png")) << "no entry: not an atlas";
  const std::string want = "says " + std::to_string(summary.layout.width) + " x " +
                           std::to_string(summary.layout.height) + " x 4 uint8";
  Image taller(summary.layout.width, summary.layout.height + 1, 4, SampleType::U8);
  taller.text = img.text;
  EXPECT_TRUE(throwsVoxError([&] { atlasInfoOfImage(taller, "a.png"); }, ErrorKind::BadInput,
                             {"a.png: the image is", "(summary, rgba8) " + want, "changed after vox wrote it"}));
  Image gray(summary.layout.width, summary.layout.height, 1, SampleType::U8);
  gray.text = img.text;
  EXPECT_TRUE(throwsVoxError([&] { atlasInfoOfImage(gray, "a.png"); }, ErrorKind::BadInput, {"x 1 uint8", want}));
  Image wide(summary.layout.width, summary.layout.height, 4, SampleType::U16);
  wide.text = img.text;
  EXPECT_TRUE(throwsVoxError([&] { atlasInfoOfImage(wide, "a.png"); }, ErrorKind::BadInput, {"x 4 uint16", want}));
  AtlasImageInfo oddFormat = summary;
  oddFormat.format = "rgba16";
  img.text = atlasImageText(oddFormat);
  EXPECT_TRUE(throwsVoxError([&] { atlasInfoOfImage(img, "a.png"); }, ErrorKind::BadInput,
                             {"a.png: format \"rgba16\" is not one a summary atlas is written in (rgba8)"}));
  AtlasImageInfo votes = everyKind()[3];
  votes.format = "rgba8";
  EXPECT_TRUE(throwsVoxError([&] { atlasImageShape(votes, "v.png"); }, ErrorKind::BadInput, {"(r8, r16, r32ui)"}));
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
    EXPECT_TRUE(refused(withKey(votes, key, nullptr), {"a.png", "no \"" + std::string(key) + "\" key"})) << key;
  // In words, not the JSON library's exception text.
  for (const std::string& text : {std::string("{"), withKey(votes, "content", nullptr), withKey(votes, "format", 3),
                                  withKey(votes, "class_id", "x")})
    EXPECT_TRUE(refused(text, {"a.png"}) && !throwsVoxError([&] { atlasInfoFromJson(text, "a.png"); },
                                                            ErrorKind::BadInput, {"json.exception"}))
        << text;
  EXPECT_TRUE(refused(withKey(votes, "content", "depth"), {"a.png", "unknown atlas content", "depth"}));
  EXPECT_TRUE(refused(withKey(votes, "content", 3), {"a.png", "malformed"}));
  EXPECT_TRUE(refused(withKey(votes, "layer", -1), {"a.png", "\"layer\""}));
  EXPECT_TRUE(refused(withKey(votes, "layer", 0.5), {"a.png", "\"layer\""}));
  EXPECT_TRUE(refused(withKey(votes, "layer", 1), {"a.png", "layer 1", "the layout's 1 layer"}));
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
                              "says " + std::to_string(info.layout.width) + height}));
  voxtest::writeText(dir.file("text.png"), "not an image");
  EXPECT_TRUE(throwsVoxError([&] { readAtlasImage(dir.file("text.png"), back); }, ErrorKind::BadInput,
                             {"text.png", "not a PNG or EXR"}));
}
