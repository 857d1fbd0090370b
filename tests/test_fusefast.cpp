// The tracked free-space walk of `vox fuse --free voted` (docs/fuse.md, "Free
// space") against the full walk as the oracle: per ray, the tracked walk adds
// exactly the full walk's free counts at the tracked voxels (and none
// elsewhere) with the same hit; per fusion, FreeScope::Voted gives the same
// votes, the same free counts at every voxel with votes or tracked, and the
// same scene as FreeScope::All, at any thread count.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "libvox/core/error.h"
#include "libvox/render/camera.h"
#include "libvox/render/fuse.h"
#include "libvox/render/ray_bundle.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/render.h"
#include "libvox/scene/fuse_scene.h"
#include "libvox/scene/scene.h"

namespace {

using vox::Coord3;
using vox::Dims;
using vox::FuseCounts;

std::map<uint64_t, uint32_t> freeMap(const FuseCounts& c) {
  std::map<uint64_t, uint32_t> m;
  for (const auto& [at, n] : c.freeVoxels()) m[FuseCounts::voxelKey(at)] = n;
  return m;
}

TEST(FuseRayTracked, SameCountsAtTrackedVoxelsAndSameHit) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  const Dims d{150, 70, 140};
  // Tracked voxels: a few clusters (surfaces) and scattered voxels; most bricks empty.
  vox::RayGrid tracked(d);
  std::set<uint64_t> trackedKeys;
  auto track = [&](int64_t u, int64_t v, int64_t w) {
    if (u < 0 || v < 0 || w < 0 || u >= d.x || v >= d.y || w >= d.z) return;
    tracked.addVoxel(uint32_t(u), uint32_t(v), uint32_t(w));
    trackedKeys.insert(FuseCounts::voxelKey(Coord3{int32_t(u), int32_t(v), int32_t(w)}));
  };
  for (int k = 0; k < 12; ++k) {
    const int64_t cu = int64_t(unit(rng) * d.x), cv = int64_t(unit(rng) * d.y), cw = int64_t(unit(rng) * d.z);
    for (int64_t u = cu - 6; u < cu + 6; ++u)
      for (int64_t w = cw - 6; w < cw + 6; ++w) track(u, cv, w);
  }
  for (int k = 0; k < 200; ++k) track(int64_t(unit(rng) * d.x), int64_t(unit(rng) * d.y), int64_t(unit(rng) * d.z));
  for (int64_t u = 0; u < d.x; ++u) track(u, 0, 0);  // a line along the grid's edge
  tracked.finish();

  FuseCounts full, fast, bundled;
  uint64_t hits = 0, fullSteps = 0, fastSteps = 0, certified = 0;
  vox::RayGrid::Cursor cursor(tracked);
  for (int i = 0; i < 20000; ++i) {
    vox::Ray r;
    const double ext[3] = {double(d.x), double(d.y), double(d.z)};
    for (int a = 0; a < 3; ++a) {
      r.origin[size_t(a)] = -40 + (ext[a] + 80) * unit(rng);
      r.dir[size_t(a)] = ext[a] * unit(rng) - r.origin[size_t(a)];
    }
    if (i % 5 == 0) r.origin[0] = std::floor(r.origin[0]);  // lattice origins
    if (i % 7 == 0) r.dir[1] = 0;                           // rays parallel to a plane
    if (i % 11 == 0) r.origin[2] = 8 * std::floor(r.origin[2] / 8);  // on brick planes
    if (i % 13 == 0) r.dir[0] = r.dir[2];                   // diagonal: edge crossings
    const double vs = i % 3 == 0 ? 0.25 : 1.0;
    vox::DepthMeasure m;
    m.kind = i % 4 == 0 ? vox::DepthKind::Z : vox::DepthKind::Distance;
    m.float32 = i % 2 == 0;
    const double len = std::sqrt(r.dir[0] * r.dir[0] + r.dir[1] * r.dir[1] + r.dir[2] * r.dir[2]);
    double depth = (m.kind == vox::DepthKind::Z ? 1.0 : len * vs) * 2 * unit(rng);
    if (m.float32) depth = double(float(depth));
    const int face = i % 3 - 1 + (i % 9 == 0 ? 1 : 0);
    const vox::FuseRayResult a = vox::fuseRay(r, vs, m, depth, d, &full, face);
    const vox::FuseRayResult b = vox::fuseRay(r, vs, m, depth, d, &fast, face, &tracked, &cursor);
    // Starting at a tile march's certificate (the second pass of addFree):
    // a bundle of this ray and three neighbours within 2% of it.
    std::array<std::array<double, 3>, 4> cone;
    for (size_t k = 0; k < 4; ++k)
      for (size_t a = 0; a < 3; ++a) cone[k][a] = r.dir[a] * (1 + (k == a ? 0.02 : 0.0));
    const double tEmpty = vox::bundleEmptyUntil(tracked, r.origin, cone);
    certified += tEmpty > 0 ? 1 : 0;
    const vox::FuseRayResult c =
        tEmpty == std::numeric_limits<double>::infinity()
            ? b  // addFree skips such a tile (no tracked voxel to count): only the counts must agree
            : vox::fuseRay(r, vs, m, depth, d, &bundled, face, &tracked, &cursor, tEmpty);
    fullSteps += a.steps;
    fastSteps += b.steps;
    ASSERT_EQ(a.hit, b.hit) << i;
    ASSERT_EQ(a.hit, c.hit) << i;
    if (a.hit) {
      ++hits;
      ASSERT_EQ(a.voxel, b.voxel) << i;
      ASSERT_EQ(a.ambiguous, b.ambiguous) << i;
      ASSERT_EQ(a.voxel, c.voxel) << i;
      ASSERT_EQ(a.ambiguous, c.ambiguous) << i;
    }
  }
  EXPECT_GT(hits, 2000u);
  std::map<uint64_t, uint32_t> want;
  for (const auto& [k, n] : freeMap(full))
    if (trackedKeys.count(k)) want[k] = n;
  const std::map<uint64_t, uint32_t> got = freeMap(fast);
  EXPECT_GT(want.size(), 300u);
  EXPECT_EQ(got, want);
  EXPECT_EQ(freeMap(bundled), want);  // from the march's end: the same counts
  EXPECT_GT(certified, 1000u);
  EXPECT_LT(fastSteps * 4, fullSteps);  // the jumps do skip most of the walk
}

// Renders of a scene whose voxels are removed for some views: the other
// views' votes sit where these views' rays pass, so voted voxels get free counts.
struct Scenes {
  std::unique_ptr<vox::RayGrid> a, b;
  std::set<uint64_t> occupied;
};

Scenes scenes(std::mt19937_64& rng, Dims dims) {
  Scenes s;
  s.a = std::make_unique<vox::RayGrid>(dims);
  s.b = std::make_unique<vox::RayGrid>(dims);
  std::uniform_real_distribution<double> unit(0, 1);
  for (uint32_t w = 0; w < dims.z; ++w)
    for (uint32_t v = 0; v < dims.y; ++v)
      for (uint32_t u = 0; u < dims.x; ++u) {
        const bool box = u >= 10 && u < 20 && w >= 12 && w < 22 && v < 9;
        if (!(v == 0 || box || unit(rng) < 0.004)) continue;
        s.a->addVoxel(u, v, w);
        if (!(box && (u + w) % 3 != 0) && unit(rng) < 0.9) s.b->addVoxel(u, v, w);
      }
  s.a->finish();
  s.b->finish();
  return s;
}

vox::FuseView view(const vox::RayGrid& g, const vox::GridFrame& frame, const vox::Camera& cam) {
  const vox::ViewHits hits = vox::castView(g, frame, cam, 1);
  vox::FuseView v;
  v.camera = cam;
  v.depth.assign(hits.pixels.size(), std::numeric_limits<double>::infinity());
  v.classes.assign(hits.pixels.size(), 0);
  v.faceAxis.assign(hits.pixels.size(), -1);
  for (size_t i = 0; i < hits.pixels.size(); ++i) {
    const vox::PixelHit& p = hits.pixels[i];
    if (!p.hit) continue;
    v.depth[i] = double(p.depth);
    v.classes[i] = uint8_t(1 + (p.u + p.w) % 4);
    v.faceAxis[i] = p.faceAxis;
  }
  return v;
}

TEST(FuseTracked, VotedScopeEqualsAllScopeWhereItCounts) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> unit(0, 1);
  const Dims dims{40, 24, 40};
  const Scenes s = scenes(rng, dims);
  vox::GridFrame frame;
  std::vector<vox::FuseView> views;
  for (int i = 0; i < 8; ++i) {
    const double a = 6.28318 * unit(rng);
    const vox::Vec3d eye = i % 4 == 3 ? vox::Vec3d{30, 15, 8} : vox::Vec3d{20 + 60 * std::cos(a), 12 + 30 * unit(rng), 20 + 60 * std::sin(a)};
    const vox::Vec3d target{40 * unit(rng), 6 * unit(rng), 40 * unit(rng)};
    const vox::Camera cam = vox::Camera::lookAt(eye, target, {0, 1, 0}, 60, 64 + uint32_t(i), 48);
    views.push_back(view(i % 2 ? *s.a : *s.b, frame, cam));
  }
  // Extra tracked voxels (an input scene's): a floating slab the views see through.
  std::vector<Coord3> extra;
  for (int32_t u = 25; u < 35; ++u)
    for (int32_t w = 25; w < 35; ++w) extra.push_back({u, 14, w});

  vox::FuseSettings all;
  all.threads = 1;
  vox::Fuser ref(dims, frame, all);
  for (const vox::FuseView& v : views) ref.add(v);
  FuseCounts refCounts = std::move(ref).finish();
  const std::map<uint64_t, uint32_t> refFree = freeMap(refCounts);
  std::set<uint64_t> keep;
  for (const FuseCounts::Vote& v : refCounts.votes()) keep.insert(FuseCounts::voxelKey(v.at));
  for (const Coord3& c : extra) keep.insert(FuseCounts::voxelKey(c));
  std::map<uint64_t, uint32_t> want;
  for (const auto& [k, n] : refFree)
    if (keep.count(k)) want[k] = n;
  uint64_t votedWithFree = 0;
  for (const FuseCounts::Vote& v : refCounts.votes()) votedWithFree += refFree.count(FuseCounts::voxelKey(v.at));
  EXPECT_GT(votedWithFree, 20u);  // the test sees voted voxels that rays also cross
  EXPECT_GT(want.size(), votedWithFree);  // and the floating slab
  const vox::FusedScene refScene = vox::applyFusion([&] {
    vox::SceneHeader h;
    h.dims = dims;
    h.classes = vox::blockPalette();
    return h;
  }(), nullptr, std::move(refCounts), true);

  for (unsigned threads : {1u, 2u, 3u}) {
    vox::FuseSettings voted;
    voted.threads = threads;
    voted.freeScope = vox::FreeScope::Voted;
    vox::Fuser fuser(dims, frame, voted);
    // Half the views kept as their walked pixels between the passes, as
    // `vox fuse` keeps them (made before track(), as there).
    std::vector<vox::FuseWalks> kept;
    for (const vox::FuseView& v : views) {
      fuser.add(v);
      kept.push_back(fuser.walksOf(v));
    }
    fuser.track(extra);
    for (size_t i = views.size(); i-- > 0;) {  // any order
      if (i % 2) {
        fuser.addFree(views[i]);
      } else {
        fuser.addFree(kept[i]);
      }
    }
    FuseCounts counts = std::move(fuser).finish();
    EXPECT_EQ(freeMap(counts), want) << threads;
    vox::SceneHeader h;
    h.dims = dims;
    h.classes = vox::blockPalette();
    const vox::FusedScene scene = vox::applyFusion(h, nullptr, std::move(counts), true);
    EXPECT_EQ(scene.totals.occupiedAfter, refScene.totals.occupiedAfter);
    EXPECT_EQ(scene.totals.rejected, refScene.totals.rejected);
    // Occupied voxels with their votes per class.
    using Votes = std::vector<std::pair<int, uint64_t>>;
    auto votesOf = [](const vox::VoxelView& v) {
      Votes out;
      for (const vox::ClassVotes& c : v.votes) out.push_back({int(c.classId), uint64_t(c.votes)});
      return out;
    };
    std::map<uint64_t, Votes> occ, refOcc;
    scene.scene.forEachVoxel([&](const vox::VoxelView& v) { occ[FuseCounts::voxelKey(v.at)] = votesOf(v); });
    refScene.scene.forEachVoxel([&](const vox::VoxelView& v) { refOcc[FuseCounts::voxelKey(v.at)] = votesOf(v); });
    EXPECT_EQ(occ, refOcc) << threads;
  }
}

// The walked pixels the second pass keeps between the passes: exactly the
// pixels with a depth, a class and a non-zero weight, each once, in the walk's
// order (16 x 16 tiles row by row, their four 8 x 8 bundles row by row, pixels
// row by row), with their depth and face axis; images whose sides are not
// multiples of the tile leave the bundles past their edge empty.
TEST(FuseWalks, HoldTheWalkedPixelsInBundleOrder) {
  std::mt19937_64 rng(41);
  std::uniform_int_distribution<int> pick(0, 9);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::array<std::array<uint32_t, 2>, 5> sizes{{{1, 1}, {16, 16}, {37, 21}, {8, 40}, {65, 17}}};
  for (const auto& [w, h] : sizes)
    for (int variant = 0; variant < 4; ++variant) {
      vox::FuseView v;
      v.camera = vox::Camera::lookAt({10, 10, -30}, {10, 10, 10}, {0, 1, 0}, 50, w, h);
      v.far = variant == 3 ? 5.0 : 0.0;
      const size_t n = size_t(w) * h;
      for (size_t i = 0; i < n; ++i) {
        const int k = pick(rng);
        v.depth.push_back(k == 0 ? 0.0 : k == 1 ? nan : k == 2 ? inf : k == 3 ? -1.0 : 0.25 + 0.5 * double(i % 13));
        v.classes.push_back(uint8_t(pick(rng) == 0 ? 0 : 1 + pick(rng) % 3));
        if (variant != 1) v.faceAxis.push_back(int8_t(pick(rng) % 4 - 1));
        if (variant >= 2) v.weight.push_back(uint16_t(pick(rng) < 2 ? 0 : 1 + pick(rng)));
      }
      vox::FuseSettings settings;
      settings.threads = variant == 0 ? 1 : 3;
      settings.freeScope = vox::FreeScope::Voted;
      const vox::Fuser fuser({16, 16, 16}, vox::GridFrame{}, settings);
      struct Want {
        uint32_t x, y;
        double depth;
        int face;
      };
      std::vector<Want> want;
      std::vector<size_t> perBundle;
      for (uint32_t ty = 0; ty < h; ty += 16)
        for (uint32_t tx = 0; tx < w; tx += 16)
          for (uint32_t b = 0; b < 4; ++b) {
            size_t count = 0;
            const uint32_t by = ty + (b >> 1) * 8, bx = tx + (b & 1) * 8;
            for (uint32_t y = by; y < std::min(h, by + 8); ++y)
              for (uint32_t x = bx; x < std::min(w, bx + 8); ++x) {
                const size_t i = size_t(y) * w + x;
                const bool walked = v.hasDepth(i) && v.classes[i] != 0 && (v.weight.empty() || v.weight[i] != 0);
                if (!walked) continue;
                want.push_back({x, y, v.depth[i], v.faceAxis.empty() ? -1 : v.faceAxis[i]});
                ++count;
              }
            perBundle.push_back(count);
          }
      const vox::FuseWalks walks = fuser.walksOf(v);
      const std::string what = std::to_string(w) + "x" + std::to_string(h) + " variant " + std::to_string(variant);
      ASSERT_EQ(walks.rays(), want.size()) << what;
      EXPECT_EQ(fuser.walkedPixels(v), want.size()) << what;
      EXPECT_EQ(walks.pixels, uint64_t(n));
      EXPECT_EQ(walks.faceAxis.empty(), v.faceAxis.empty() || want.empty());
      ASSERT_EQ(walks.bundleStart.size(), perBundle.size() + 1) << what;
      EXPECT_EQ(walks.bytes(), (perBundle.size() + 1) * 8 + want.size() * (v.faceAxis.empty() ? 9 : 10)) << what;
      size_t r = 0;
      for (size_t bundle = 0; bundle < perBundle.size(); ++bundle) {
        ASSERT_EQ(walks.bundleStart[bundle], r) << what;
        ASSERT_EQ(walks.bundleStart[bundle + 1] - walks.bundleStart[bundle], perBundle[bundle]) << what << " bundle " << bundle;
        const size_t tile = bundle / 4, b = bundle % 4, tilesX = (w + 15) / 16;
        const uint32_t bx = uint32_t(tile % tilesX * 16 + (b & 1) * 8), by = uint32_t(tile / tilesX * 16 + (b >> 1) * 8);
        for (; r < walks.bundleStart[bundle + 1]; ++r) {
          EXPECT_EQ(bx + walks.at[r] % 8, want[r].x) << what << " ray " << r;
          EXPECT_EQ(by + walks.at[r] / 8, want[r].y) << what << " ray " << r;
          EXPECT_EQ(walks.depth[r], want[r].depth) << what << " ray " << r;
          if (!walks.faceAxis.empty()) {
            EXPECT_EQ(int(walks.faceAxis[r]), want[r].face) << what << " ray " << r;
          }
        }
      }
      EXPECT_EQ(r, want.size());
    }
  // Arrays of the wrong length are the caller's error, named.
  vox::FuseView bad;
  bad.camera = vox::Camera::lookAt({0, 0, -5}, {0, 0, 0}, {0, 1, 0}, 50, 4, 4);
  bad.depth.assign(16, 1.0);
  bad.classes.assign(15, 1);
  const vox::Fuser fuser({4, 4, 4}, vox::GridFrame{}, vox::FuseSettings{});
  EXPECT_THROW(fuser.walksOf(bad), vox::Error);
}

}  // namespace
