// Atlas mapping, bijection proof, summary bytes, texel formats, bitmaps — each
// against an independent oracle (the UVW atlas layout's own bit formulas, brute-force sets, a
// long double reference, exhaustive round trips).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include <random>
#include <set>

#include "libvox/core/atlas_mapping.h"
#include "libvox/core/bijection_proof.h"
#include "libvox/core/bitmap_packing.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/core/texel_formats.h"
#include "test_util.h"

using namespace vox;

TEST(AtlasMapping, EqualsTheUvwLayoutFormulaForAll256Cubed) {
  const AtlasLayout L = AtlasLayout::make({256, 256, 256});
  EXPECT_EQ(L.tilesPerRow, 16u);
  EXPECT_EQ(L.width, 4096u);
  EXPECT_EQ(L.height, 4096u);
  EXPECT_EQ(L.layers, 1u);
  for (uint32_t w = 0; w < 256; ++w)
    for (uint32_t v = 0; v < 256; ++v)
      for (uint32_t u = 0; u < 256; ++u) {
        const TexelAddress t = L.toTexel(u, v, w);
        ASSERT_EQ(t, uvw256VoxelToAtlas(u, v, w));
        const Coord3 s = uvw256AtlasToVoxel(t.x, t.y);
        ASSERT_EQ(*L.toVoxel(0, t.x, t.y), s);
      }
}

TEST(AtlasMapping, DefaultTilesPerRowIsSmallestThenSquarest) {
  EXPECT_EQ(AtlasLayout::make({3, 5, 7}).tilesPerRow, 7u) << "7 x 1 tiles: 21 x 5 has no padding";
  const AtlasLayout a = AtlasLayout::make({64, 64, 64});
  EXPECT_EQ(a.width, 512u);
  EXPECT_EQ(a.height, 512u);
  const AtlasLayout flat = AtlasLayout::make({1, 1, 65536});
  EXPECT_EQ(flat.width, 256u) << "1 x 1 x 65536 becomes a 256 x 256 square";
  EXPECT_EQ(flat.height, 256u);
  // 2^30 texels cannot fit one 16384^2 layer: four full layers.
  const AtlasLayout big = AtlasLayout::make({1024, 1024, 1024});
  EXPECT_EQ(big.layers, 4u);
  EXPECT_EQ(big.width, 16384u);
  EXPECT_EQ(big.height, 16384u);
}

TEST(AtlasMapping, LayersWhenASideWouldPassTheMaximum) {
  const AtlasLayout L = AtlasLayout::make({10, 10, 50}, 0, 32);
  EXPECT_EQ(L.tilesPerRow, 3u);
  EXPECT_EQ(L.rowsPerLayer, 3u);
  EXPECT_EQ(L.layers, 6u);  // 17 tile rows, 3 per layer
  EXPECT_LE(L.width, 32u);
  EXPECT_LE(L.height, 32u);
  EXPECT_TRUE(proveBijection(L, 2).ok());
  EXPECT_THROW(AtlasLayout::make({40, 10, 5}, 0, 32), Error);
  EXPECT_THROW(AtlasLayout::make({10, 10, 5}, 4, 32), Error) << "forced T too wide";
}

// The default T as ATLAS.md states it, by scanning every T (64-bit, so a T
// range that ends at 2^32 - 1 ends): the reference the direct search must equal.
AtlasLayout referenceDefaultLayout(Dims d, uint32_t maxSide) {
  const uint64_t maxT = std::min<uint64_t>(d.z, maxSide / d.x), maxR = maxSide / d.y;
  uint64_t best = 0, bestArea = 0, bestSkew = 0;
  for (uint64_t T = 1; T <= maxT; ++T) {
    const uint64_t rows = (uint64_t(d.z) + T - 1) / T;
    if (rows > maxR) continue;
    const uint64_t w = T * d.x, h = rows * d.y, area = w * h, skew = w > h ? w - h : h - w;
    if (!best || area < bestArea || (area == bestArea && skew < bestSkew)) best = T, bestArea = area, bestSkew = skew;
  }
  return AtlasLayout::make(d, uint32_t(best ? best : maxT), maxSide);
}

TEST(AtlasMapping, DefaultTilesPerRowEqualsTheScanOfEveryT) {
  std::mt19937 rng(11);
  for (int i = 0; i < 3000; ++i) {
    const Dims d{1 + uint32_t(rng() % 40), 1 + uint32_t(rng() % 40), 1 + uint32_t(rng() % (i % 3 ? 300 : 5000))};
    const uint32_t maxSide = std::max(d.x, d.y) + uint32_t(rng() % (i % 2 ? 200 : 3000));
    ASSERT_EQ(AtlasLayout::make(d, 0, maxSide), referenceDefaultLayout(d, maxSide)) << toString(d) << " " << maxSide;
  }
  for (const Dims& d : {Dims{1, 1, 65536}, Dims{256, 256, 256}, Dims{1, 1, 4097}, Dims{3, 1, 99991}, Dims{7, 300, 1000}})
    EXPECT_EQ(AtlasLayout::make(d), referenceDefaultLayout(d, kDefaultAtlasMaxSide)) << toString(d);
}

TEST(AtlasMapping, HugeMaximumSidesAreQuickOrRefused) {
  // A counter of 32 bits wrapped past T = 2^32 - 1 and divided by zero (SIGFPE).
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(voxtest::throwsVoxError([] { AtlasLayout::make({1, 1, 0xffffffffu}, 0, 0xffffffffu); },
                                      ErrorKind::Usage, {"4294967295", "2147483647"}));
  // 2^32 - 1 = 65535 * 65537: no padding, and the most square such split.
  const AtlasLayout L = AtlasLayout::make({1, 1, 0xffffffffu}, 0, kMaxAtlasSide);
  EXPECT_EQ(L.tilesPerRow, 65535u);
  EXPECT_EQ(L.width, 65535u);
  EXPECT_EQ(L.height, 65537u);
  EXPECT_EQ(L.layers, 1u);
  const AtlasLayout flat = AtlasLayout::make({1, 1, 0x7fffffffu}, 0, kMaxAtlasSide);
  EXPECT_EQ(uint64_t(flat.width) * flat.height, 0x7fffffffull) << "2^31 - 1 is prime: only 1 x (2^31 - 1) has no padding";
  EXPECT_EQ(AtlasLayout::make({1, 1, 1000}, 0, kMaxAtlasSide).width, 25u) << "25 x 40";
  // The same layout in a file's metadata: refused as bad input, at once.
  const std::string huge = R"({"dims":[1,1,4294967295],"tiles_per_row":0,"rows_per_layer":1,"layers":1,)"
                           R"("width":1,"height":1,"max_side":4294967295})";
  EXPECT_TRUE(voxtest::throwsVoxError([&] { AtlasLayout::fromJson(huge, "fpe.png"); }, ErrorKind::BadInput,
                                      {"fpe.png", "tiles_per_row"}));
  std::string hugeT1 = huge;
  hugeT1.replace(hugeT1.find("\"tiles_per_row\":0"), 17, "\"tiles_per_row\":1");
  EXPECT_TRUE(voxtest::throwsVoxError([&] { AtlasLayout::fromJson(hugeT1, "fpe.png"); }, ErrorKind::BadInput,
                                      {"fpe.png", "inconsistent atlas layout", "2147483647"}));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
}

TEST(AtlasMapping, LayoutsNameTheirTilesPerRow) {
  std::string text = AtlasLayout::make({3, 5, 7}).toJson();
  text.replace(text.find("\"tiles_per_row\":7"), 17, "\"tiles_per_row\":0");
  EXPECT_TRUE(voxtest::throwsVoxError([&] { AtlasLayout::fromJson(text, "a.png"); }, ErrorKind::BadInput,
                                      {"a.png", "'tiles_per_row' must be >= 1"}));
}

TEST(AtlasMapping, InverseRejectsPaddingAndOutOfRange) {
  const AtlasLayout L = AtlasLayout::make({3, 5, 7}, 3);  // 3 tiles per row, 3 rows: 2 padding tiles
  EXPECT_FALSE(L.toVoxel(0, 3, 10));  // tile slot 7
  EXPECT_FALSE(L.toVoxel(0, 8, 14));  // tile slot 8
  EXPECT_TRUE(L.toVoxel(0, 2, 14));   // tile slot 6 = w 6
  EXPECT_FALSE(L.toVoxel(0, 9, 0));
  EXPECT_FALSE(L.toVoxel(1, 0, 0));
  EXPECT_EQ(AtlasLayout::fromJson(L.toJson(), "x"), L);
  EXPECT_THROW(AtlasLayout::fromJson("{\"dims\":[3,5,7]}", "x"), Error);
}

TEST(BijectionProof, ExhaustiveForManyOddDims) {
  const Dims cases[] = {{1, 1, 1}, {3, 5, 7}, {1, 1, 4097}, {255, 1, 3}, {17, 1, 1}, {1, 300, 2}, {7, 7, 49}, {2, 3, 1000}};
  for (const Dims& d : cases)
    for (uint32_t maxSide : {16384u, 64u}) {
      if (d.x > maxSide || d.y > maxSide) continue;
      const AtlasLayout L = AtlasLayout::make(d, 0, maxSide);
      const BijectionResult r = proveBijection(L, 2);
      EXPECT_TRUE(r.ok()) << toString(d) << " " << (r.first ? r.first->what : "");
      EXPECT_EQ(r.method, "exhaustive");
      EXPECT_EQ(r.voxelsChecked, d.count());
      // Independent count: texels = voxels + padding.
      EXPECT_EQ(r.texelsChecked, d.count() + r.paddingTexels);
      // Brute force: the set of forward images has d.count() distinct members.
      std::set<std::tuple<uint32_t, uint32_t, uint32_t>> images;
      for (uint32_t w = 0; w < d.z; ++w)
        for (uint32_t v = 0; v < d.y; ++v)
          for (uint32_t u = 0; u < d.x; ++u) {
            const TexelAddress t = L.toTexel(u, v, w);
            images.insert({t.layer, t.x, t.y});
          }
      EXPECT_EQ(images.size(), d.count());
    }
}

TEST(BijectionProof, FindsABrokenLayoutAndWorksByParts) {
  AtlasLayout broken = AtlasLayout::make({4, 4, 8});
  ASSERT_EQ(broken.tilesPerRow, 2u);
  broken.tilesPerRow = 1;  // sizes no longer follow: slices 4.. fall past the last layer
  const BijectionResult r = proveBijection(broken, 2);
  EXPECT_FALSE(r.ok());
  ASSERT_TRUE(r.first);
  EXPECT_EQ(r.first->voxel, (Coord3{0, 0, 4})) << r.first->what;
  EXPECT_EQ(r.first->what, "out of range");
  EXPECT_EQ(r.first->texel, (TexelAddress{1, 0, 0}));
  const AtlasLayout big = AtlasLayout::make({5000, 3000, 2000});
  const BijectionResult p = proveBijection(big, 2, 1000000);
  EXPECT_EQ(p.method, "by-parts");
  EXPECT_TRUE(p.ok());
  EXPECT_FALSE(p.argument.empty());
}

TEST(SummaryBytes, MatchesTheReferenceOnRandomAndExtremeHistograms) {
  std::mt19937_64 rng(3);
  auto check = [](std::vector<ClassVotes> h) {
    const SummaryTexel a = summarize(h), b = summarizeReference(h);
    ASSERT_EQ(a, b) << "cls " << int(a.cls) << "/" << int(b.cls) << " conf " << int(a.conf) << "/" << int(b.conf)
                    << " obs " << int(a.obs) << "/" << int(b.obs) << " mrg " << int(a.mrg) << "/" << int(b.mrg);
  };
  for (int i = 0; i < 20000; ++i) {
    std::vector<ClassVotes> h;
    const int n = 1 + int(rng() % 6);
    std::set<uint8_t> ids;
    for (int k = 0; k < n; ++k) {
      const uint8_t id = uint8_t(1 + rng() % 255);
      if (!ids.insert(id).second) continue;
      const int scale = int(rng() % 4);
      const uint32_t v = scale == 0 ? uint32_t(rng() % 4) : scale == 1 ? uint32_t(rng() % 1000)
                                                          : scale == 2 ? uint32_t(rng() % 100000) : uint32_t(rng());
      h.push_back({id, v});
    }
    check(h);
  }
  check({{7, 1}});
  EXPECT_EQ(summarize(std::vector<ClassVotes>{{7, 1}}), (SummaryTexel{7, 255, 16, 255})) << "one vote: log2(2) * 16";
  EXPECT_EQ(summarize(std::vector<ClassVotes>{{9, 5}, {4, 5}}).cls, 4) << "ties go to the lowest id";
  EXPECT_EQ(summarize(std::vector<ClassVotes>{{9, 5}, {4, 5}}).mrg, 0);
  EXPECT_EQ(summarize(std::vector<ClassVotes>{}), (SummaryTexel{0, 0, 0, 0}));
  EXPECT_EQ(summarize(std::vector<ClassVotes>{{3, 0}}), (SummaryTexel{0, 0, 0, 0}));
  std::vector<ClassVotes> all;
  for (int id = 1; id <= 255; ++id) all.push_back({uint8_t(id), 1000});
  check(all);
  EXPECT_EQ(summarize(all).cls, 1);
  for (int k = 1; k < 32; ++k)
    for (int64_t d : {-1, 0, 1}) check({{2, uint32_t((int64_t(1) << k) + d)}});
  check({{2, 0xffffffffu}});
  check({{2, 0xffffffffu}, {3, 0xffffffffu}, {4, 0xfffffffeu}});
  // log2 exact at powers of two: total + 1 = 2^m gives 16 m.
  for (int m = 0; m < 16; ++m) EXPECT_EQ(observationByte(uint64_t(1) << m), 16 * m);
  // At and below every threshold: the smallest n with 16 log2 n >= k gives at
  // least k, n - 1 less than k (small k share thresholds: 2 gives 16).
  for (int k = 1; k < 256; ++k) {
    const uint64_t n = k % 16 == 0 ? uint64_t(1) << (k / 16) : uint64_t(std::ceil(std::exp2l((long double)k / 16.0L)));
    EXPECT_GE(observationByte(n), k) << n;
    EXPECT_LT(observationByte(n - 1), k) << n - 1;
  }
  EXPECT_EQ(observationByte(0), 0);
  EXPECT_EQ(observationByte(uint64_t(1) << 40), 255);
}

TEST(TexelFormats, MeasuredExactLimits) {
  EXPECT_EQ(maxExactInteger(TexelFormat::Rgba8), 255u);
  EXPECT_EQ(maxExactInteger(TexelFormat::Rgba16), 65535u);
  EXPECT_EQ(maxExactInteger(TexelFormat::Rgba16f), 2048u);
  EXPECT_EQ(maxExactInteger(TexelFormat::Rgba32f), uint64_t(1) << 24);
  EXPECT_EQ(maxExactInteger(TexelFormat::Rgba32ui, 2), 0xffffffffull);
  for (TexelFormat f : {TexelFormat::Rgba8, TexelFormat::Rgba16, TexelFormat::Rgba16f, TexelFormat::Rgba32f})
    EXPECT_EQ(maxExactInteger(f), documentedMaxExact(f));
  EXPECT_EQ(narrowestExactFormat(255), TexelFormat::Rgba8);
  EXPECT_EQ(narrowestExactFormat(256), TexelFormat::Rgba16);
  EXPECT_EQ(narrowestExactFormat(65536), TexelFormat::Rgba32ui);
  // Half conversion: exhaustive round trip of every finite half.
  for (uint32_t h = 0; h < 0x10000; ++h) {
    if (((h >> 10) & 0x1f) == 0x1f) continue;
    ASSERT_EQ(floatToHalf(halfToFloat(uint16_t(h))), uint16_t(h)) << h;
  }
  EXPECT_EQ(halfToFloat(floatToHalf(2049.0f)), 2048.0f) << "ties to even";
  EXPECT_EQ(halfToFloat(floatToHalf(2051.0f)), 2052.0f);
}

TEST(OccupancyBitmap, UvwLayoutPackingAndTwoBitMode) {
  const AtlasLayout L = AtlasLayout::make({20, 3, 2});
  OccupancyBitmap one(L, 1), two(L, 2);
  EXPECT_EQ(one.rowBytes(), (L.width + 7) / 8);
  EXPECT_EQ(two.rowBytes(), (L.width + 3) / 4);
  const TexelAddress t = L.toTexel(13, 2, 1);
  one.setOccupied(t);
  two.setOccupied(t);
  two.setTouched(t);
  EXPECT_EQ(one.layerBytes(0)[t.y * one.rowBytes() + (t.x >> 3)], uint8_t(1u << (t.x & 7)));
  EXPECT_EQ(two.layerBytes(0)[t.y * two.rowBytes() + (t.x >> 2)], uint8_t(3u << (2 * (t.x & 3))));
  EXPECT_TRUE(one.occupied(t));
  EXPECT_TRUE(two.touched(t));
  EXPECT_FALSE(one.occupied(L.toTexel(12, 2, 1)));
  size_t set = 0;
  for (uint8_t b : one.layerBytes(0)) set += __builtin_popcount(b);
  EXPECT_EQ(set, 1u);
}
