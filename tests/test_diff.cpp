// vox diff's comparisons (docs/diff.md): scenes kind by kind with tolerances at
// their boundaries, images against hand-computed metrics, JSON pointers and
// the relative tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "formats/core/json_diff.h"
#include "formats/image/image_diff.h"
#include "libvox/scene/scene_diff.h"

using namespace vox;

namespace {

SceneHeader header() {
  SceneHeader h;
  h.dims = {20, 10, 30};
  h.voxelSize = 0.5;
  h.origin = {-1, 2, 3};
  h.classes.add({1, "grass", {10, 200, 10}, std::nullopt});
  h.classes.add({3, "stone", {128, 128, 128}, std::nullopt});
  return h;
}

// A base scene with a few hundred voxels over several leaves, plus `edit`.
Scene scene(const std::function<void(SceneBuilder&)>& edit = {}, SceneHeader h = header()) {
  SceneBuilder b(h);
  for (int w = 0; w < 30; w += 3)
    for (int v = 0; v < 10; v += 2)
      for (int u = 0; u < 20; u += 1) {
        b.addVotes({u, v, w}, 1, 100 + u, (u + v) % 2 == 0);
        if (u % 5 == 0) b.addVotes({u, v, w}, 3, 7, false);
        b.setColor({u, v, w}, {0.25f, 0.5f, float(u) / 32.f});
      }
  if (edit) edit(b);
  return std::move(b).build();
}

}  // namespace

TEST(SceneDiff, EqualScenesAtAnyThreadCount) {
  const Scene a = scene(), b = scene();
  for (unsigned t : {1u, 2u, 4u}) {
    SceneDiffOptions o;
    o.threads = t;
    const SceneDiff d = diffScenes(a, b, o);
    EXPECT_TRUE(d.same());
    EXPECT_EQ(d.voxelsCompared, a.occupiedCount());
    EXPECT_EQ(d.voxelsDiffering, 0u);
  }
}

TEST(SceneDiff, OneVoteIsAVoteDifferenceOnly) {
  const Scene a = scene();
  const Scene b = scene([](SceneBuilder& s) { s.addVotes({7, 4, 9}, 1, 5, false); });
  const SceneDiff d = diffScenes(a, b);
  EXPECT_TRUE(d.header.empty());
  EXPECT_EQ(d.voxelsDiffering, 1u);
  EXPECT_EQ(d.kind(VoxelDiffKind::Votes).count, 1u);
  EXPECT_EQ(d.kind(VoxelDiffKind::Occupancy).count, 0u);
  EXPECT_EQ(d.kind(VoxelDiffKind::Color).count, 0u);
  EXPECT_EQ(d.kind(VoxelDiffKind::Surface).count, 0u);
  ASSERT_TRUE(d.first);
  EXPECT_EQ(d.first->at, (Coord3{7, 4, 9}));
  EXPECT_EQ(d.kind(VoxelDiffKind::Votes).worst->magnitude, 5.0);
  EXPECT_EQ(d.first->a.votes[0].votes, 107u);
  EXPECT_EQ(d.first->b.votes[0].votes, 112u);
  // The world position of the voxel's centre.
  EXPECT_EQ(voxelCentreWorld(a.header(), d.first->at), (std::array<double, 3>{-1 + 7.5 * 0.5, 2 + 4.5 * 0.5, 3 + 9.5 * 0.5}));
}

TEST(SceneDiff, VotesToleranceBoundary) {
  const Scene a = scene();
  const Scene b = scene([](SceneBuilder& s) {
    s.addVotes({7, 4, 9}, 1, 5, false);
    s.addVotes({8, 4, 9}, 3, 2, false);  // a class the voxel had none of: 0 -> 2
  });
  SceneDiffOptions o;
  o.votesTolerance = 4;
  EXPECT_EQ(diffScenes(a, b, o).voxelsDiffering, 1u);  // 5 > 4; 2 <= 4
  o.votesTolerance = 5;
  EXPECT_TRUE(diffScenes(a, b, o).same());  // 5 <= 5
  o.votesTolerance = 1;
  const SceneDiff d = diffScenes(a, b, o);
  EXPECT_EQ(d.kind(VoxelDiffKind::Votes).count, 2u);
  EXPECT_EQ(d.kind(VoxelDiffKind::Votes).first->at, (Coord3{7, 4, 9}));
  EXPECT_EQ(d.kind(VoxelDiffKind::Votes).worst->at, (Coord3{7, 4, 9}));
}

TEST(SceneDiff, ColorToleranceBoundaryAndMissingColour) {
  const Scene a = scene();
  const float delta = 0.125f;  // exact in float and double
  const Scene b = scene([&](SceneBuilder& s) { s.setColor({3, 2, 6}, {0.25f + delta, 0.5f, 3.f / 32.f}); });
  SceneDiffOptions o;
  o.colorTolerance = 0.125;
  EXPECT_TRUE(diffScenes(a, b, o).same());
  o.colorTolerance = std::nextafter(0.125, 0.0);
  const SceneDiff d = diffScenes(a, b, o);
  EXPECT_EQ(d.kind(VoxelDiffKind::Color).count, 1u);
  EXPECT_EQ(d.kind(VoxelDiffKind::Color).first->at, (Coord3{3, 2, 6}));
  EXPECT_EQ(d.kind(VoxelDiffKind::Votes).count, 0u);
}

TEST(SceneDiff, OccupancySurfaceAndHeader) {
  const Scene a = scene();
  SceneHeader h = header();
  h.voxelSize = 0.25;
  h.classes = ClassTable();
  h.classes.add({1, "grass", {10, 200, 10}, std::nullopt});
  h.classes.add({3, "rock", {128, 128, 128}, std::nullopt});
  const Scene b = scene(
      [](SceneBuilder& s) {
        s.addVotes({19, 9, 29}, 3, 40, true);   // new voxel: only in B
        s.addVotes({0, 0, 0}, 1, 0, true);      // no-op
        s.addVotes({1, 0, 0}, 1, 0, false);     // no-op (zero votes)
        s.addVotes({1, 2, 0}, 1, 1, true);      // (1,2,0) was interior: surface flips, votes +1
      },
      h);
  SceneDiffOptions o;
  o.votesTolerance = 1;
  const SceneDiff d = diffScenes(a, b, o);
  ASSERT_EQ(d.header.size(), 1u);
  EXPECT_EQ(d.header[0].field, "voxel_size");
  ASSERT_EQ(d.classes.size(), 1u);
  EXPECT_EQ(d.classes[0].id, 3);
  EXPECT_EQ(d.onlyInB, 1u);
  EXPECT_EQ(d.onlyInA, 0u);
  EXPECT_EQ(d.kind(VoxelDiffKind::Occupancy).first->at, (Coord3{19, 9, 29}));
  EXPECT_EQ(d.kind(VoxelDiffKind::Occupancy).worst->magnitude, 40.0);
  EXPECT_EQ(d.kind(VoxelDiffKind::Surface).count, 1u);
  EXPECT_EQ(d.kind(VoxelDiffKind::Surface).first->at, (Coord3{1, 2, 0}));
  EXPECT_EQ(d.kind(VoxelDiffKind::Votes).count, 0u);  // +1 is within the tolerance
  EXPECT_EQ(d.voxelsDiffering, 2u);
  EXPECT_EQ(d.first->at, (Coord3{1, 2, 0}));  // smallest (w, v, u)
}

TEST(SceneDiff, SourcesByContentNotPath) {
  SceneHeader h1 = header(), h2 = header();
  h1.sources.push_back({"a/m.obj", "mesh", std::string(64, 'c'), 10});
  h2.sources.push_back({"b/m.obj", "mesh", std::string(64, 'c'), 10});
  EXPECT_TRUE(diffScenes(scene({}, h1), scene({}, h2)).same());
  h2.sources[0].sha256 = std::string(64, 'd');
  EXPECT_EQ(diffScenes(scene({}, h1), scene({}, h2)).header.size(), 1u);
  SceneDiffOptions o;
  o.ignoreSources = true;
  EXPECT_TRUE(diffScenes(scene({}, h1), scene({}, h2), o).same());
}

namespace {

Image rgba8(uint32_t w, uint32_t h, uint8_t fill) {
  Image img(w, h, 4, SampleType::U8);
  std::fill(img.pixels.begin(), img.pixels.end(), fill);
  return img;
}

}  // namespace

TEST(ImageDiff, OneTexelHandComputed) {
  Image a = rgba8(16, 12, 100), b = a;
  b.pixels[(5 * 16 + 9) * 4 + 1] = 151;  // pixel (9, 5), G: +51 = 0.2
  const ImageDiff d = diffImages(a, b);
  EXPECT_EQ(d.verdict, ImageVerdict::Fail);
  EXPECT_EQ(d.pixelsDiffering, 1u);
  EXPECT_EQ(d.failPixels, 1u);
  EXPECT_EQ(d.maxX, 9u);
  EXPECT_EQ(d.maxY, 5u);
  EXPECT_EQ(d.maxChannel, 1u);
  EXPECT_DOUBLE_EQ(d.maxError, 0.2);
  const double values = 16.0 * 12 * 4;
  EXPECT_DOUBLE_EQ(d.mse, 0.2 * 0.2 / values);
  EXPECT_DOUBLE_EQ(d.meanError, 0.2 / values);
  EXPECT_NEAR(d.psnr, 10 * std::log10(values / 0.04), 1e-9);
  EXPECT_EQ(d.maskAgree, 16u * 12u);
  ASSERT_TRUE(d.ssim);
  EXPECT_LT(*d.ssim, 1.0);
  // idiff's thresholds: the error is 0.2.
  ImageDiffOptions o;
  o.failThreshold = 0.2;  // strictly greater fails
  o.warnThreshold = 0.1;
  EXPECT_EQ(diffImages(a, b, o).verdict, ImageVerdict::Warn);
  o.warnPercent = 100.0 / (16 * 12);  // one pixel of 192 is allowed
  EXPECT_EQ(diffImages(a, b, o).verdict, ImageVerdict::Pass);
  o.hardWarn = 0.19;
  EXPECT_EQ(diffImages(a, b, o).verdict, ImageVerdict::Warn);
  ImageDiffOptions f;
  f.failPercent = 100.0 / (16 * 12);
  EXPECT_EQ(diffImages(a, b, f).verdict, ImageVerdict::Warn);  // fail allowed, warn (1e-6) not
  f.hardFail = 0.19;
  EXPECT_EQ(diffImages(a, b, f).verdict, ImageVerdict::Fail);
}

TEST(ImageDiff, EqualImagesAndSsimOfConstantShift) {
  const Image a = rgba8(10, 9, 40);
  const ImageDiff same = diffImages(a, a);
  EXPECT_EQ(same.verdict, ImageVerdict::Pass);
  EXPECT_EQ(same.mse, 0.0);
  EXPECT_TRUE(std::isinf(same.psnr));
  EXPECT_EQ(*same.ssim, 1.0);
  // Constant images: SSIM = (2 mx my + C1) / (mx^2 + my^2 + C1) on every window.
  const Image b = rgba8(10, 9, 60);
  const double mx = 40 / 255.0, my = 60 / 255.0, c1 = 1e-4;
  EXPECT_NEAR(*diffImages(a, b).ssim, (2 * mx * my + c1) / (mx * mx + my * my + c1), 1e-12);
  // Under 8x8 there is no window.
  EXPECT_FALSE(diffImages(rgba8(7, 20, 1), rgba8(7, 20, 1)).ssim);
}

TEST(ImageDiff, MaskAlphaBackgroundAndIncompatible) {
  Image a = rgba8(4, 2, 255), b = a;
  b.pixels[3] = 0;  // pixel (0, 0) becomes a miss in B
  EXPECT_EQ(diffImages(a, b).maskAgree, 7u);
  Image rgb(4, 2, 3, SampleType::U8);
  for (size_t i = 0; i < rgb.pixels.size(); i += 3) rgb.pixels[i] = 135, rgb.pixels[i + 1] = 207, rgb.pixels[i + 2] = 235;
  Image rgb2 = rgb;
  rgb2.pixels[0] = 0;  // a hit
  const ImageDiff d = diffImages(rgb, rgb2);
  EXPECT_EQ(d.maskAgree, 7u);
  EXPECT_EQ(d.maskSource, "background");
  EXPECT_FALSE(diffImages(rgba8(4, 2, 0), rgba8(4, 3, 0)).incompatible.empty());
  EXPECT_FALSE(diffImages(rgb, Image(4, 2, 1, SampleType::U8)).incompatible.empty());
  // RGB against RGBA: the colour channels are compared.
  const ImageDiff mixed = diffImages(rgb, [&] {
    Image x(4, 2, 4, SampleType::U8);
    for (size_t p = 0; p < 8; ++p) x.pixels[p * 4] = 135, x.pixels[p * 4 + 1] = 207, x.pixels[p * 4 + 2] = 235, x.pixels[p * 4 + 3] = 255;
    return x;
  }());
  EXPECT_TRUE(mixed.incompatible.empty());
  EXPECT_EQ(mixed.channels, 3u);
  EXPECT_EQ(mixed.pixelsDiffering, 0u);
}

TEST(ImageDiff, DeterministicAtAnyThreadCount) {
  Image a(300, 70, 3, SampleType::U16), b = a;
  for (size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] = uint8_t(i * 7), b.pixels[i] = uint8_t(i * 7 + (i % 13 == 0));
  ImageDiffOptions o;
  o.threads = 1;
  const ImageDiff d1 = diffImages(a, b, o);
  o.threads = 3;
  const ImageDiff d3 = diffImages(a, b, o);
  EXPECT_EQ(d1.mse, d3.mse);
  EXPECT_EQ(*d1.ssim, *d3.ssim);
  EXPECT_EQ(d1.maxX, d3.maxX);
  EXPECT_EQ(d1.maxY, d3.maxY);
}

TEST(ImageDiff, DifferenceImage) {
  Image a = rgba8(3, 2, 10), b = a;
  b.pixels[(1 * 3 + 2) * 4 + 0] = 61;   // (2, 1) R +51
  b.pixels[(0 * 3 + 1) * 4 + 3] = 0;    // (1, 0) alpha -10
  const Image d = differenceImage(a, b, 2.0);
  ASSERT_EQ(d.channels, 3u);
  EXPECT_EQ(d.pixels[(1 * 3 + 2) * 3 + 0], 102);  // 255 * 2 * 0.2
  EXPECT_EQ(d.pixels[(1 * 3 + 2) * 3 + 1], 0);
  EXPECT_EQ(d.pixels[(0 * 3 + 1) * 3 + 0], 20);  // alpha error shown in every channel
  EXPECT_EQ(d.pixels[0], 0);
}

TEST(SceneDiff, ValuesInTheirShortestExactText) {
  VoxelValues v;
  v.occupied = v.surface = true;
  v.votes = {{3, 2}};
  v.color = RgbLinear{0.87499809265136719f, 0.5f, 0.1f};
  EXPECT_EQ(describeVoxel(v), "surface votes{3:2} color(0.8749981,0.5,0.1)") << "a float's digits, not a double's 17";
  SceneHeader ha = header(), hb = header();
  ha.voxelSize = 0.8, hb.voxelSize = 0.4;
  const SceneDiff d = diffScenes(scene({}, ha), scene({}, hb));
  ASSERT_EQ(d.header.size(), 1u);
  EXPECT_EQ(d.header[0].field, "voxel_size");
  EXPECT_EQ(d.header[0].a, "0.8") << "not 0.80000000000000004";
  EXPECT_EQ(d.header[0].b, "0.4");
}

TEST(ImageDiff, FloatDifferenceImageForExr) {
  Image a = rgba8(3, 2, 10), b = a;
  b.pixels[(1 * 3 + 2) * 4 + 0] = 61;  // (2, 1) R +51
  const Image d = differenceImage(a, b, 10.0, SampleType::F32);
  ASSERT_EQ(d.type, SampleType::F32);
  ASSERT_EQ(d.channels, 3u);
  EXPECT_FLOAT_EQ(d.row<float>(1)[2 * 3 + 0], float(10.0 * 51 / 255)) << "neither rounded nor clamped at 1";
  EXPECT_EQ(d.row<float>(1)[2 * 3 + 1], 0.0f);
  EXPECT_EQ(d.row<float>(0)[0], 0.0f);
  // Depth renders: two misses (+inf) are equal, a difference of 0, not NaN.
  Image za(2, 1, 1, SampleType::F32), zb = za;
  za.row<float>(0)[0] = zb.row<float>(0)[0] = std::numeric_limits<float>::infinity();
  za.row<float>(0)[1] = 1.5f, zb.row<float>(0)[1] = 1.0f;
  const Image dz = differenceImage(za, zb, 1.0, SampleType::F32);
  EXPECT_EQ(dz.row<float>(0)[0], 0.0f);
  EXPECT_EQ(dz.row<float>(0)[3], 0.5f);
  EXPECT_EQ(differenceImage(za, zb).row<uint8_t>(0)[0], 0);
}

TEST(JsonDiff, FirstPointerAndRelativeTolerance) {
  const auto a = nlohmann::json::parse(R"({"levels":[{"iou":0.5,"n":10},{"iou":0.75,"n":3}],"name":"x","total_seconds":1.5})");
  const auto b = nlohmann::json::parse(R"({"levels":[{"iou":0.5,"n":10},{"iou":0.7501,"n":3}],"name":"x","total_seconds":9})");
  const JsonDiff d = diffJson(a, b);
  EXPECT_EQ(d.differing, 1u);  // total_seconds is ignored by default
  EXPECT_EQ(d.differences[0].pointer, "/levels/1/iou");
  EXPECT_EQ(d.differences[0].a, "0.75");
  EXPECT_EQ(d.differences[0].b, "0.7501");
  const double rel = 0.0001 / 0.7501;
  JsonDiffOptions o;
  o.relTolerance = rel * 1.000001;
  EXPECT_TRUE(diffJson(a, b, o).same());
  o.relTolerance = rel * 0.999999;
  EXPECT_FALSE(diffJson(a, b, o).same());
  o.ignoreKeys.clear();
  o.relTolerance = 0;
  EXPECT_EQ(diffJson(a, b, o).differing, 2u);
}

TEST(JsonDiff, AbsentKeysTypesAndEscapes) {
  const auto a = nlohmann::json::parse(R"({"a/b":1,"c":[1,2],"d":"1","big":18446744073709551615})");
  const auto b = nlohmann::json::parse(R"({"a/b":1,"c":[1],"d":1,"e~":null,"big":18446744073709551614})");
  const JsonDiff d = diffJson(a, b);
  ASSERT_EQ(d.differing, 4u);
  EXPECT_EQ(d.differences[0].pointer, "/big");
  EXPECT_EQ(d.differences[1].pointer, "/c/1");
  EXPECT_EQ(d.differences[1].b, "(absent)");
  EXPECT_EQ(d.differences[2].pointer, "/d");
  EXPECT_EQ(d.differences[3].pointer, "/e~0");
  EXPECT_TRUE(jsonKeyMatches("*_seconds", "cast_seconds"));
  EXPECT_FALSE(jsonKeyMatches("*_seconds", "seconds"));
  EXPECT_TRUE(jsonKeyMatches("a*b*c", "aXXbYc"));
}
