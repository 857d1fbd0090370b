// Tile bundles (ray_bundle.h) and the casts that start from them: a bundle's
// certified time must precede every occupied voxel any of its rays touches
// (brute force), a ray started there must find exactly what it finds from 0,
// and castView (which casts by tiles) must equal a per-pixel castRay.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "libvox/render/camera.h"
#include "libvox/render/ray_bundle.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/raycast.h"
#include "libvox/render/render.h"

namespace {

using vox::Coord3;
using vox::Ray;
using vox::RayGrid;
using Vec = std::array<double, 3>;

struct SparseScene {
  std::vector<Coord3> voxels;
  std::unique_ptr<RayGrid> grid;
};

// A few small blobs far apart (so the brick distance field has room to
// certify long stretches) and, in some scenes, a thin floor slab.
SparseScene sparseScene(std::mt19937_64& rng, vox::Dims dims, int blobs, bool floor) {
  std::set<std::array<int64_t, 3>> occupied;  // (w, v, u): the brute force's voxels in a fixed order
  std::uniform_real_distribution<double> unit(0, 1);
  auto set = [&](int64_t u, int64_t v, int64_t w) {
    if (u >= 0 && v >= 0 && w >= 0 && u < dims.x && v < dims.y && w < dims.z) occupied.insert({w, v, u});
  };
  for (int b = 0; b < blobs; ++b) {
    const int64_t cu = int64_t(unit(rng) * dims.x), cv = int64_t(unit(rng) * dims.y), cw = int64_t(unit(rng) * dims.z);
    const int r = int(unit(rng) * 3);
    for (int64_t du = -r; du <= r; ++du)
      for (int64_t dv = -r; dv <= r; ++dv)
        for (int64_t dw = -r; dw <= r; ++dw)
          if (unit(rng) < 0.5) set(cu + du, cv + dv, cw + dw);
  }
  if (floor)
    for (int64_t w = 0; w < dims.z; ++w)
      for (int64_t u = 0; u < dims.x; ++u)
        if (unit(rng) < 0.3) set(u, 2, w);
  SparseScene s;
  s.grid = std::make_unique<RayGrid>(dims);
  for (const auto& [w, v, u] : occupied) {
    s.voxels.push_back({int32_t(u), int32_t(v), int32_t(w)});
    s.grid->addVoxel(uint32_t(u), uint32_t(v), uint32_t(w));
  }
  s.grid->finish();
  return s;
}

std::string text(const Ray& r) {
  char b[256];
  std::snprintf(b, sizeof b, "origin (%.17g, %.17g, %.17g) dir (%.17g, %.17g, %.17g)", r.origin[0], r.origin[1],
                r.origin[2], r.dir[0], r.dir[1], r.dir[2]);
  return b;
}

bool sameHit(const vox::RayHit& a, const vox::RayHit& b) {
  return a.hit == b.hit && (!a.hit || (a.voxel == b.voxel && a.t == b.t && a.exit == b.exit &&
                                       a.faceAxis == b.faceAxis && a.faceSign == b.faceSign));
}

TEST(RayBundle, CertifiedStretchPrecedesEveryOccupiedVoxelTheRaysTouch) {
  std::mt19937_64 rng(1411);
  std::uniform_real_distribution<double> unit(0, 1);
  uint64_t bundles = 0, advanced = 0, missedAll = 0, rays = 0;
  for (int sceneIndex = 0; sceneIndex < 16; ++sceneIndex) {
    // Every fourth domain is smaller than a brick or two on some axis: the
    // content box (whole bricks clipped to the domain) then ends inside a brick.
    std::uniform_int_distribution<uint32_t> side(20, 170), small(1, 12);
    const vox::Dims dims = sceneIndex % 4 == 3 ? vox::Dims{small(rng), small(rng), small(rng)}
                                               : vox::Dims{side(rng), side(rng), side(rng)};
    const SparseScene s = sparseScene(rng, dims, 3 + sceneIndex % 5, sceneIndex % 3 == 0);
    const double ext[3] = {double(dims.x), double(dims.y), double(dims.z)};
    RayGrid::Cursor cursor(*s.grid);
    for (int b = 0; b < 150; ++b) {
      // Origin around, inside or far from the grid; corner directions spread
      // like a pixel tile's (tiny) up to a wide cone.
      Vec origin, target;
      const double reach = b % 5 == 0 ? 20.0 : 1.6;
      for (int a = 0; a < 3; ++a) origin[size_t(a)] = (unit(rng) * reach - (reach - 1) / 2) * ext[a];
      if (b % 7 == 0)  // an integer origin on grid planes
        for (double& o : origin) o = std::floor(o);
      for (int a = 0; a < 3; ++a) target[size_t(a)] = unit(rng) * ext[a];
      const double spread = std::pow(10.0, -4 + 3.5 * unit(rng));
      std::array<Vec, 4> corners;
      for (Vec& d : corners)
        for (int a = 0; a < 3; ++a)
          d[size_t(a)] = (target[size_t(a)] - origin[size_t(a)]) * (1 + spread * (unit(rng) * 2 - 1)) +
                         spread * 50 * (unit(rng) * 2 - 1);
      if (b % 11 == 0)  // an axis-parallel bundle (one direction component zero on every corner)
        for (Vec& d : corners) d[1] = 0;
      const double T = vox::bundleEmptyUntil(*s.grid, origin, corners);
      ASSERT_GE(T, 0.0);
      ++bundles;
      advanced += T > 0;
      missedAll += std::isinf(T);
      // The corners and random points of their hull.
      for (int i = 0; i < 12; ++i) {
        Ray r;
        r.origin = origin;
        if (i < 4) {
          r.dir = corners[size_t(i)];
        } else {
          double wgt[4], sum = 0;
          for (double& x : wgt) sum += (x = unit(rng));
          r.dir = {0, 0, 0};
          for (int c = 0; c < 4; ++c)
            for (int a = 0; a < 3; ++a) r.dir[size_t(a)] += wgt[c] / sum * corners[size_t(c)][size_t(a)];
        }
        const vox::RayHit truth = vox::castRayBruteForce(s.voxels, r);
        ++rays;
        if (std::isinf(T)) {
          ASSERT_FALSE(truth.hit) << "scene " << sceneIndex << " bundle " << b << " certified empty, " << text(r);
          continue;
        }
        // Every occupied voxel the ray touches has key >= T, so the first one does.
        ASSERT_TRUE(!truth.hit || truth.t >= T)
            << "scene " << sceneIndex << " bundle " << b << ": hit at " << truth.t << " before " << T << ", " << text(r);
        const vox::RayHit fromT = vox::castRay(*s.grid, r, cursor, T);
        ASSERT_TRUE(sameHit(fromT, truth)) << "scene " << sceneIndex << " bundle " << b << " from " << T << ", " << text(r);
        ASSERT_TRUE(sameHit(fromT, vox::castRay(*s.grid, r, cursor)));
      }
    }
  }
  // The march must actually certify something, and whole misses, for the test to mean anything.
  EXPECT_GT(advanced, bundles / 2);
  EXPECT_GT(missedAll, bundles / 20);
  EXPECT_LT(missedAll, bundles * 3 / 4);
}

// Two voxels in a 2 x 1 x 1 domain seen from z = 10: the content box ends at
// x = 2, inside its only brick; the march must use that brick's distance (0).
TEST(RayBundle, ContentBoxEndingInsideABrick) {
  RayGrid g(vox::Dims{2, 1, 1});
  g.addVoxel(0, 0, 0);
  g.addVoxel(1, 0, 0);
  g.finish();
  const std::array<Vec, 2> dirs{Vec{-1.0 / 18, 0, -1}, Vec{1.0 / 18, 0, -1}};
  const double T = vox::bundleEmptyUntil(g, {1, 0.5, 10}, dirs);
  EXPECT_FALSE(std::isinf(T));
  EXPECT_LE(T, 9.0);  // the rays reach the voxels' +z face at t = 9
  RayGrid::Cursor cursor(g);
  for (const Vec& d : dirs) {
    Ray r;
    r.origin = {1, 0.5, 10};
    r.dir = d;
    const vox::RayHit h = vox::castRay(g, r, cursor, T);
    EXPECT_TRUE(h.hit);
    EXPECT_EQ(h.t, 9.0);
  }
}

// Domains of more than 2^24 bricks have no distance field (every brick reads
// 1, occupied or not): the march must not take an occupied brick for empty.
TEST(RayBundle, DomainsWithoutADistanceFieldStayConservative) {
  RayGrid g(vox::Dims{8192, 8192, 136});  // 1024 x 1024 x 17 bricks
  g.addVoxel(4005, 4004, 60);
  g.finish();
  ASSERT_EQ(g.emptyBricksAround(500, 500, 7), 1u);  // the premise: no field
  const Vec origin{4004.5, 4004.5, 60.5};          // the middle of the occupied voxel's brick
  const std::array<Vec, 1> along{Vec{1, 0, 0}};
  const double T = vox::bundleEmptyUntil(g, origin, along);
  Ray r;
  r.origin = origin;
  r.dir = along[0];
  const std::vector<Coord3> voxels{{4005, 4004, 60}};
  const vox::RayHit truth = vox::castRayBruteForce(voxels, r);
  ASSERT_TRUE(truth.hit);
  EXPECT_LE(T, truth.t);
  RayGrid::Cursor cursor(g);
  EXPECT_TRUE(sameHit(vox::castRay(g, r, cursor, T), truth));
}

TEST(RayBundle, EmptyGridMissesAndDegenerateBundlesCertifyNothing) {
  RayGrid empty(vox::Dims{16, 16, 16});
  empty.finish();
  const std::array<Vec, 1> one{Vec{1, 0, 0}};
  EXPECT_TRUE(std::isinf(vox::bundleEmptyUntil(empty, {-5, 3, 3}, one)));
  RayGrid g(vox::Dims{16, 16, 16});
  g.addVoxel(8, 8, 8);
  g.finish();
  EXPECT_EQ(vox::bundleEmptyUntil(g, {-5, 3, 3}, std::span<const Vec>{}), 0.0);
  // Directions spanning more than a half space: the whole bundle cannot be
  // outrun, and the certified stretch stops short of the grid.
  const std::array<Vec, 2> opposite{Vec{1, 0, 0}, Vec{-1, 0, 0}};
  const double T = vox::bundleEmptyUntil(g, {-5, 8.5, 8.5}, opposite);
  EXPECT_FALSE(std::isinf(T));
  EXPECT_LT(T, 13.0);
}

// castView casts by tiles; every pixel must be what a lone castRay of its ray
// finds, at any thread count, for image sizes that are not multiples of the tile.
TEST(RayBundle, TiledViewEqualsPerPixelCastsAtAnyThreadCount) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> unit(0, 1);
  uint64_t hits = 0, pixels = 0;
  for (int sceneIndex = 0; sceneIndex < 6; ++sceneIndex) {
    const vox::Dims dims{uint32_t(40 + sceneIndex * 23), uint32_t(30 + sceneIndex * 7), uint32_t(90 - sceneIndex * 9)};
    const SparseScene s = sparseScene(rng, dims, 12, sceneIndex % 2 == 0);
    const vox::GridFrame frame{{-1.5, 0.25, 2.0}, 0.1};
    const vox::Vec3d centre{-1.5 + 0.05 * dims.x, 0.25 + 0.05 * dims.y, 2.0 + 0.05 * dims.z};
    for (int c = 0; c < 4; ++c) {
      vox::Vec3d eye;
      const double dist = c == 3 ? 0.2 : 8 + 10 * unit(rng);  // the last camera inside the scene
      for (int a = 0; a < 3; ++a) eye[size_t(a)] = centre[size_t(a)] + dist * (unit(rng) * 2 - 1);
      const uint32_t w = 37 + uint32_t(unit(rng) * 40), h = 21 + uint32_t(unit(rng) * 30);
      const vox::Camera cam = vox::Camera::lookAt(eye, centre, {0, 1, 0}, 30 + 60 * unit(rng), w, h);
      const vox::ViewHits one = vox::castView(*s.grid, frame, cam, 1);
      const vox::ViewHits two = vox::castView(*s.grid, frame, cam, 2);
      const vox::PixelRays rays(cam, frame);
      RayGrid::Cursor cursor(*s.grid);
      for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
          const vox::RayHit ref = vox::castRay(*s.grid, rays.ray(x, y), cursor);
          for (const vox::ViewHits* v : {&one, &two}) {
            const vox::PixelHit& p = v->pixels[size_t(y) * w + x];
            ASSERT_EQ(p.hit, ref.hit) << "scene " << sceneIndex << " camera " << c << " pixel " << x << "," << y;
            if (!ref.hit) continue;
            ASSERT_TRUE(p.u == ref.voxel.u && p.v == ref.voxel.v && p.w == ref.voxel.w && p.faceAxis == ref.faceAxis &&
                        p.faceSign == ref.faceSign && p.depth == float(rays.worldDistance(rays.ray(x, y), ref.t)))
                << "scene " << sceneIndex << " camera " << c << " pixel " << x << "," << y;
          }
          hits += ref.hit;
          ++pixels;
        }
      EXPECT_EQ(one.hitCount, two.hitCount);
      EXPECT_EQ(one.steps, two.steps);
    }
  }
  EXPECT_GT(hits, pixels / 50);
}

}  // namespace
