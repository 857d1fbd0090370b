// The render module's outputs as data and as files: the per-mode pixels, the
// touched set, the `vox:canonical` entry and the touched-set JSON
// (formats/image/RENDER.md), each written and read back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "formats/image/render_meta.h"
#include "formats/image/touched_json.h"
#include "libvox/core/morton.h"
#include "libvox/render/render_modes.h"
#include "libvox/render/touched_voxels.h"
#include "test_util.h"

namespace {

using voxtest::throwsVoxError;

// A 3 x 2 view: two hits on voxel (1, 2, 3) (one entered through -y, one
// started inside), one on (300, 0, 5) through +x, three misses.
vox::ViewHits smallView() {
  vox::ViewHits h;
  h.width = 3;
  h.height = 2;
  h.pixels.resize(6);
  h.pixels[0] = {1, 2, 3, 4.5f, 1, -1, true};
  h.pixels[2] = {300, 0, 5, 7.25f, 0, 1, true};
  h.pixels[4] = {1, 2, 3, 0.0f, -1, 0, true};
  h.hitCount = 3;
  return h;
}

TEST(RenderModes, NamesRoundTripAndUnknownNamesAreRefused) {
  for (vox::RenderMode m : vox::kRenderModes) EXPECT_EQ(vox::renderModeNamed(vox::renderModeName(m)), m);
  EXPECT_FALSE(vox::renderModeNamed("sketch"));
  EXPECT_FALSE(vox::renderModeNamed("Canonical"));
  EXPECT_TRUE(vox::modeNeedsClasses(vox::RenderMode::Shaded));
  EXPECT_FALSE(vox::modeNeedsClasses(vox::RenderMode::Depth));
}

TEST(RenderModes, CanonicalPixelsAreTheCoordinatesInTheNarrowestSample) {
  const vox::ViewHits h = smallView();
  const vox::ModeImage img = vox::canonicalImage(h, 16);
  ASSERT_EQ(img.sample, vox::PixelSample::U16);
  ASSERT_EQ(img.channels, 4u);
  ASSERT_EQ(img.pixels.size(), 6u * 4 * 2);
  const uint16_t* px = reinterpret_cast<const uint16_t*>(img.pixels.data());
  EXPECT_EQ((std::vector<uint16_t>(px, px + 4)), (std::vector<uint16_t>{1, 2, 3, 65535}));
  EXPECT_EQ((std::vector<uint16_t>(px + 4, px + 8)), (std::vector<uint16_t>{0, 0, 0, 0}));  // a miss
  EXPECT_EQ((std::vector<uint16_t>(px + 8, px + 12)), (std::vector<uint16_t>{300, 0, 5, 65535}));
  EXPECT_EQ(vox::canonicalImage(h, 8).pixels.size(), 6u * 4);
  const vox::ModeImage wide = vox::canonicalImage(h, 32);
  EXPECT_EQ(wide.sample, vox::PixelSample::U32);
  EXPECT_EQ(reinterpret_cast<const uint32_t*>(wide.pixels.data())[3], 0xffffffffu);
}

TEST(RenderModes, DepthNormalAndClassPixels) {
  const vox::ViewHits h = smallView();
  const vox::ModeImage depth = vox::depthImage(h);
  ASSERT_EQ(depth.sample, vox::PixelSample::F32);
  const float* d = reinterpret_cast<const float*>(depth.pixels.data());
  EXPECT_EQ(d[0], 4.5f);
  EXPECT_EQ(d[1], std::numeric_limits<float>::infinity());
  EXPECT_EQ(d[2], 7.25f);

  // Pixel 4 started inside its voxel: its normal faces the ray's dominant axis.
  const vox::Camera cam = vox::Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 3, 2);
  const vox::ModeImage normal = vox::normalImage(h, cam);
  const uint8_t* n = normal.pixels.data();
  EXPECT_EQ((std::vector<uint8_t>(n, n + 4)), (std::vector<uint8_t>{128, 0, 128, 255}));       // -y
  EXPECT_EQ((std::vector<uint8_t>(n + 8, n + 12)), (std::vector<uint8_t>{255, 128, 128, 255}));  // +x
  EXPECT_EQ((std::vector<uint8_t>(n + 16, n + 20)), (std::vector<uint8_t>{128, 128, 255, 255}));  // ray along -z
  EXPECT_EQ(n[7], 0);  // a miss is transparent

  const std::vector<vox::ViewHits> views{h};
  const vox::TouchedVoxels touched(views);
  ASSERT_EQ(touched.size(), 2u);
  std::vector<vox::SummaryTexel> summaries(2);
  summaries[touched.indexOf(h.pixels[0])].cls = 1;
  summaries[touched.indexOf(h.pixels[2])].cls = 9;  // not in the table: grey
  const vox::ClassTable classes = vox::blockPalette();
  const vox::ModeImage cls = vox::classImage(h, classes, vox::HitSummaries{&touched, summaries});
  const vox::Rgb8 grass = classes.find(1)->color;
  EXPECT_EQ((std::vector<uint8_t>(cls.pixels.begin(), cls.pixels.begin() + 4)),
            (std::vector<uint8_t>{grass.r, grass.g, grass.b, 255}));
  EXPECT_EQ((std::vector<uint8_t>(cls.pixels.begin() + 8, cls.pixels.begin() + 12)),
            (std::vector<uint8_t>{128, 128, 128, 255}));
}

TEST(TouchedVoxels, DistinctVoxelsAndTheirChunksInMortonOrder) {
  const std::vector<vox::ViewHits> views{smallView(), smallView()};
  const vox::TouchedVoxels touched(views);
  ASSERT_EQ(touched.size(), 2u);
  EXPECT_EQ(touched.voxel(0), (vox::Coord3{1, 2, 3}));  // (w, v, u) order
  EXPECT_EQ(touched.voxel(1), (vox::Coord3{300, 0, 5}));
  const std::vector<vox::TouchedChunk> chunks = vox::touchedChunks(touched, 16);
  ASSERT_EQ(chunks.size(), 2u);
  EXPECT_EQ(chunks[0], (vox::TouchedChunk{{0, 0, 0}, 0, 1}));
  EXPECT_EQ(chunks[1], (vox::TouchedChunk{{18, 0, 0}, vox::mortonEncode(18, 0, 0), 1}));
  // One chunk of 512 holds both.
  EXPECT_EQ(vox::touchedChunks(touched, 512), (std::vector<vox::TouchedChunk>{{{0, 0, 0}, 0, 2}}));
}

vox::RenderMeta sampleMeta() {
  vox::RenderMeta m;
  m.mode = vox::RenderMode::Canonical;
  m.scene = "h.vdb";
  m.dims = {64, 48, 64};
  m.origin = {-32, 0.0, -0.1};
  m.voxelSize = 0.5;
  m.view = 2;
  m.viewMatrix = vox::lookAtMatrix({20, 15, 20}, {0, 2, 0}, {0, 1, 0});
  m.projectionMatrix = vox::perspectiveMatrix(1.0471975511965976, 1.5, 0.1, 500);
  m.width = 96;
  m.height = 64;
  m.bits = 8;
  return m;
}

TEST(RenderMeta, WritesSortedCompactJsonAndReadsItBack) {
  vox::RenderMeta m = sampleMeta();
  const std::string text = vox::renderMetaJson(m);
  EXPECT_EQ(text.rfind("{\"bits\":8,\"camera\":{\"imageSize\":{\"height\":64,\"width\":96},\"projectionMatrix\":[", 0), 0u)
      << text;
  EXPECT_NE(text.find("\"dims\":[64,48,64],\"mode\":\"canonical\",\"origin\":[-32.0,0.0,-0.1],\"scene\":\"h.vdb\","
                      "\"view\":2,\"voxel_size\":0.5}"),
            std::string::npos)
      << text;
  EXPECT_EQ(vox::parseRenderMeta(text, "r.png"), m);
  m.mode = vox::RenderMode::Depth;
  m.bits.reset();
  m.level = 1;
  EXPECT_EQ(vox::parseRenderMeta(vox::renderMetaJson(m), "r.exr"), m);
}

TEST(RenderMeta, ReaderNamesTheElementItRefuses) {
  const auto bad = vox::ErrorKind::BadInput;
  EXPECT_TRUE(throwsVoxError([] { vox::parseRenderMeta("{", "r.png"); }, bad, {"r.png", "vox:canonical", "JSON"}));
  std::string text = vox::renderMetaJson(sampleMeta());
  auto without = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  EXPECT_TRUE(throwsVoxError([&] { vox::parseRenderMeta(without("\"mode\":\"canonical\"", "\"mode\":\"sketch\""), "r.png"); },
                             bad, {"r.png", "mode"}));
  EXPECT_TRUE(throwsVoxError([&] { vox::parseRenderMeta(without("\"dims\":[64,48,64]", "\"dims\":[64,48]"), "r.png"); },
                             bad, {"dims"}));
  EXPECT_TRUE(throwsVoxError([&] { vox::parseRenderMeta(without("\"viewMatrix\":[", "\"viewMatrix\":[\"x\","), "r.png"); },
                             bad, {"camera.viewMatrix"}));
  EXPECT_TRUE(throwsVoxError([&] { vox::parseRenderMeta(without("\"bits\":8", "\"bits\":12"), "r.png"); }, bad, {"bits"}));
  EXPECT_TRUE(throwsVoxError([&] { vox::parseRenderMeta(without("\"voxel_size\"", "\"size\""), "r.png"); }, bad,
                             {"voxel_size"}));
}

TEST(RenderMeta, ImagesCarryItAndCanonicalSamplesDecode) {
  vox::Image img(2, 1, 4, vox::SampleType::U16);
  reinterpret_cast<uint16_t*>(img.pixels.data())[4] = 700;
  reinterpret_cast<uint16_t*>(img.pixels.data())[7] = 65535;
  EXPECT_FALSE(vox::readRenderMeta(img, "r.png"));
  img.text = {{vox::kRenderMetaKey, vox::renderMetaJson(sampleMeta())}};
  EXPECT_EQ(vox::readRenderMeta(img, "r.png"), sampleMeta());
  EXPECT_EQ(vox::canonicalFullScale(img), 65535u);
  EXPECT_EQ(vox::canonicalSamples(img, 1), (std::array<uint64_t, 4>{700, 0, 0, 65535}));
  // The entry's camera is for the 96x64 image it was written with: a crop
  // (this 2x1 image) is refused rather than cast through the wrong rays.
  EXPECT_TRUE(throwsVoxError([&] { vox::renderCamera(sampleMeta(), img, "r.png", "give a camera"); },
                             vox::ErrorKind::BadInput,
                             {"r.png is 2x1 but its vox:canonical camera was made for 96x64", "; give a camera"}));
  const vox::Camera cam = vox::renderCamera(sampleMeta(), vox::Image(96, 64, 4, vox::SampleType::U16), "r.png", "");
  EXPECT_EQ(cam.width, 96u);
  EXPECT_EQ(cam.view, sampleMeta().viewMatrix);
  vox::requireCanonicalImage(img, "r.png");
  EXPECT_TRUE(throwsVoxError([] { vox::requireCanonicalImage(vox::Image(1, 1, 1, vox::SampleType::F32), "d.exr"); },
                             vox::ErrorKind::BadInput, {"d.exr", "RGBA", "float"}));
}

vox::TouchedSet sampleTouchedSet() {
  vox::TouchedSet set;
  set.scene = "h.vpk";
  set.dims = {64, 64, 64};
  set.chunkSide = 16;
  set.views = 2;
  set.rays = 12288;
  set.hits = 9000;
  set.chunks = {{{0, 0, 0}, 0, 5}, {{1, 0, 0}, vox::mortonEncode(1, 0, 0), 7}, {{0, 3, 2}, vox::mortonEncode(0, 3, 2), 1}};
  set.voxelsTouched = 13;
  return set;
}

TEST(TouchedSetFile, WritesTheDocumentedShapeAndReadsItBack) {
  const vox::TouchedSet set = sampleTouchedSet();
  const std::string text = vox::touchedSetJson(set);
  EXPECT_EQ(text.rfind("{\n \"chunk_size\": 16,\n \"chunks\": [\n  {\n   \"chunk\": [\n    0,\n", 0), 0u) << text;
  EXPECT_NE(text.find("\"chunks_touched\": 3,\n \"dims\": [\n  64,\n  64,\n  64\n ],\n \"format\": \"voxbake-touched\""),
            std::string::npos)
      << text;
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(vox::parseTouchedSet(text, "t.json"), set);
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("t.json"), text);
  EXPECT_EQ(vox::readTouchedSet(dir.file("t.json")), set);
}

TEST(TouchedSetFile, ReaderRefusesWhatTheFormatRulesOut) {
  const auto bad = vox::ErrorKind::BadInput;
  EXPECT_TRUE(throwsVoxError([] { vox::parseTouchedSet("{\"format\": \"voxbake-atlas\"}", "t.json"); }, bad,
                             {"t.json", "voxbake-touched"}));
  vox::TouchedSet unordered = sampleTouchedSet();
  std::swap(unordered.chunks[0], unordered.chunks[1]);
  EXPECT_TRUE(throwsVoxError([&] { vox::parseTouchedSet(vox::touchedSetJson(unordered), "t.json"); }, bad,
                             {"chunks[1]", "Morton order"}));
  vox::TouchedSet wrongKey = sampleTouchedSet();
  wrongKey.chunks[2].morton += 1;
  EXPECT_TRUE(throwsVoxError([&] { vox::parseTouchedSet(vox::touchedSetJson(wrongKey), "t.json"); }, bad,
                             {"chunks[2].morton"}));
  vox::TouchedSet wrongSum = sampleTouchedSet();
  wrongSum.voxelsTouched = 12;
  EXPECT_TRUE(throwsVoxError([&] { vox::parseTouchedSet(vox::touchedSetJson(wrongSum), "t.json"); }, bad,
                             {"voxels_touched"}));
}

}  // namespace
