// build-atlas --preview images (formats/image/atlas_preview.h), pixel by pixel
// against values computed by hand.
#include <gtest/gtest.h>

#include "formats/image/atlas_preview.h"
#include "libvox/core/bitmap_packing.h"

using namespace vox;

namespace {
std::array<uint8_t, 3> rgbAt(const AtlasPreview& p, uint32_t x, uint32_t y) { return p.rgb(x, y); }
using Rgb = std::array<uint8_t, 3>;
}  // namespace

TEST(InfoPreview, RampEndsAndStopsByHand) {
  EXPECT_EQ(ramp(0), (Rgb{68, 1, 84}));
  EXPECT_EQ(ramp(255), (Rgb{253, 231, 37}));
  EXPECT_EQ(ramp(128), (Rgb{33, 145, 140})) << "a stop is exact";
  // Halfway between the first two stops: (68*16 + 71*16 + 16) / 32 = 70, (16 + 720 + 16) / 32 = 23, (1344 + 1968 + 16) / 32 = 104.
  EXPECT_EQ(ramp(16), (Rgb{70, 23, 104}));
  EXPECT_EQ(grayRamp(0), 48) << "0 stays visible against black";
  EXPECT_EQ(grayRamp(255), 255);
  EXPECT_EQ(grayRamp(64), 100) << "48 + (207 * 64 + 127) / 255 = 48 + 52";
  EXPECT_EQ(previewPath("out/h.summary.png"), "out/h.summary.preview.png");
  EXPECT_EQ(previewPath("out/h.votes.3.exr"), "out/h.votes.3.preview.png");
  EXPECT_EQ(previewPath("a.b/c"), "a.b/c.preview.png");
}

TEST(InfoPreview, SummaryPanelsClassConfidenceObservations) {
  const AtlasLayout L = AtlasLayout::make({2, 1, 2});
  AtlasImageInfo info{L, AtlasContent::Summary, "rgba8", 0, 0, "s.vdb"};
  Image atlas(L.width, L.height, 4, SampleType::U8);
  const TexelAddress a = L.toTexel(0, 0, 0), b = L.toTexel(1, 0, 1);
  const uint8_t va[4] = {1, 255, 16, 255}, vb[4] = {9, 128, 0, 3};
  std::copy_n(va, 4, atlas.pixels.data() + (size_t(a.y) * L.width + a.x) * 4);
  std::copy_n(vb, 4, atlas.pixels.data() + (size_t(b.y) * L.width + b.x) * 4);
  ClassTable classes;
  classes.add({1, "Brick", {200, 0, 0}, std::nullopt});
  const AtlasPreview p = atlasPreview(atlas, info, classes, "s.summary.png");
  ASSERT_EQ(p.image.width, 3 * L.width);
  ASSERT_EQ(p.image.height, L.height);
  ASSERT_EQ(p.image.channels, 1u) << "indexed colour";
  ASSERT_EQ(p.palette.size(), 256u) << "black, 1 class, unknown, 253 ramp levels";
  const uint32_t W = L.width;
  EXPECT_EQ(rgbAt(p, a.x, a.y), (Rgb{200, 0, 0})) << "class colour";
  EXPECT_EQ(rgbAt(p, W + a.x, a.y), (Rgb{253, 231, 37})) << "confidence 255";
  EXPECT_EQ(rgbAt(p, 2 * W + a.x, a.y), (Rgb{70, 23, 104})) << "observations 16";
  EXPECT_EQ(rgbAt(p, b.x, b.y), (Rgb{255, 0, 255})) << "a class missing from the table is magenta";
  EXPECT_EQ(rgbAt(p, W + b.x, b.y), ramp(128));
  EXPECT_EQ(rgbAt(p, 2 * W + b.x, b.y), (Rgb{68, 1, 84})) << "observations 0 is dark violet, not black";
  // Every other texel is black.
  size_t lit = 0;
  for (uint32_t y = 0; y < p.image.height; ++y)
    for (uint32_t x = 0; x < p.image.width; ++x) lit += rgbAt(p, x, y) != Rgb{0, 0, 0};
  EXPECT_EQ(lit, 6u);
  EXPECT_NE(p.image.textValue(kPreviewTextKey).find("s.summary.png"), std::string::npos);
}

TEST(InfoPreview, SummaryOfManyClassesFallsBackToRgb) {
  const AtlasLayout L = AtlasLayout::make({1, 1, 1});
  Image atlas(L.width, L.height, 4, SampleType::U8);
  const uint8_t v[4] = {200, 128, 16, 0};
  std::copy_n(v, 4, atlas.pixels.data());
  ClassTable classes;
  for (int i = 1; i <= 200; ++i) classes.add({uint8_t(i), "c" + std::to_string(i), {uint8_t(i), 1, 2}, std::nullopt});
  const AtlasPreview p = atlasPreview(atlas, {L, AtlasContent::Summary, "rgba8", 0, 0, "s"}, classes, "s.png");
  EXPECT_TRUE(p.palette.empty()) << "200 classes leave 54 ramp levels: RGB instead";
  EXPECT_EQ(p.image.channels, 3u);
  EXPECT_EQ(rgbAt(p, 0, 0), (Rgb{200, 1, 2}));
  EXPECT_EQ(rgbAt(p, 1, 0), ramp(128)) << "the exact ramp";
  EXPECT_EQ(rgbAt(p, 2, 0), ramp(16));
}

TEST(InfoPreview, VotesNormalisedPerLayerInGray) {
  const AtlasLayout L = AtlasLayout::make({3, 1, 1});
  AtlasImageInfo info{L, AtlasContent::Votes, "r16", 0, 4, "s.vdb"};
  Image atlas(L.width, L.height, 1, SampleType::U16);
  uint16_t* v = reinterpret_cast<uint16_t*>(atlas.pixels.data());
  v[0] = 0, v[1] = 100, v[2] = 400;
  ClassTable classes;
  classes.add({4, "Moss", {}, std::nullopt});
  const AtlasPreview p = atlasPreview(atlas, info, classes, "s.votes.4.png");
  ASSERT_EQ(p.image.channels, 1u);
  // 100 / 400: round(255 / 4) = 64 -> gray 100; 400 / 400 -> 255.
  EXPECT_EQ(p.image.pixels, (std::vector<uint8_t>{0, 100, 255}));
  EXPECT_NE(p.image.textValue(kPreviewTextKey).find("Moss"), std::string::npos) << "the preview names its class";
}

TEST(InfoPreview, BitmapsBlackWhiteAndFourGreys) {
  const AtlasLayout L = AtlasLayout::make({4, 1, 1});
  Image one(1, 1, 1, SampleType::U8);
  one.pixels = {0b0010};  // texel 1 occupied
  const AtlasPreview p1 = atlasPreview(one, {L, AtlasContent::Occupancy, "bitmap", 0, 0, "s"}, {}, "o.png");
  EXPECT_EQ(p1.image.pixels, (std::vector<uint8_t>{0, 255, 0, 0}));
  Image two(1, 1, 1, SampleType::U8);
  two.pixels = {0b00100111};  // texel 0 occupied + touched, 1 occupied, 2 touched only, 3 empty
  const AtlasPreview p2 = atlasPreview(two, {L, AtlasContent::Occupancy2, "bitmap", 0, 0, "s"}, {}, "o2.png");
  EXPECT_EQ(p2.image.pixels, (std::vector<uint8_t>{255, 170, 85, 0}));
}

TEST(InfoPreview, IdentityScaledOverTheDims) {
  const AtlasLayout L = AtlasLayout::make({2, 1, 2});
  Image atlas(L.width, L.height, 4, SampleType::U8);
  const TexelAddress t = L.toTexel(1, 0, 1);
  const uint8_t texel[4] = {1, 0, 1, 255};
  std::copy_n(texel, 4, atlas.pixels.data() + (size_t(t.y) * L.width + t.x) * 4);
  const AtlasPreview p = atlasPreview(atlas, {L, AtlasContent::Identity, "rgba8", 0, 0, "s"}, {}, "i.png");
  EXPECT_EQ(rgbAt(p, t.x, t.y), (Rgb{255, 0, 255})) << "u = 1 of 0..1 -> 255; a 1-voxel axis -> 0";
  const TexelAddress e = L.toTexel(0, 0, 0);
  EXPECT_EQ(rgbAt(p, e.x, e.y), (Rgb{0, 0, 0})) << "empty";
}
