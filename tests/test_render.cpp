// render-canonical's kernels against exact oracles: the hierarchical DDA
// against a brute-force caster on random scenes and adversarial rays, cameras
// against matrices computed by hand, shading against the terrain formula.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "formats/core/camera_json.h"
#include "libvox/render/camera.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/raycast.h"
#include "libvox/render/render.h"
#include "libvox/render/render_modes.h"
#include "formats/pagefile/pagefile_ray_grid.h"
#include "libvox/scene/render_scene.h"
#include "libvox/scene/demo_hamlet.h"
#include "test_util.h"

namespace {

using vox::Coord3;
using vox::Ray;
using vox::RayGrid;

struct TestScene {
  vox::Dims dims;
  std::vector<Coord3> voxels;
  std::unique_ptr<RayGrid> grid;
};

// Random clusters (so that the DDA both skips and steps) plus scattered voxels.
TestScene randomScene(std::mt19937_64& rng, vox::Dims dims, int clusters, double density) {
  TestScene s;
  s.dims = dims;
  s.grid = std::make_unique<RayGrid>(dims);
  std::vector<uint8_t> occ(size_t(dims.count()), 0);
  auto set = [&](int64_t u, int64_t v, int64_t w) {
    if (u < 0 || v < 0 || w < 0 || u >= dims.x || v >= dims.y || w >= dims.z) return;
    occ[size_t((w * dims.y + v) * dims.x + u)] = 1;
  };
  std::uniform_real_distribution<double> unit(0, 1);
  for (int c = 0; c < clusters; ++c) {
    const int64_t cu = int64_t(unit(rng) * dims.x), cv = int64_t(unit(rng) * dims.y), cw = int64_t(unit(rng) * dims.z);
    const int r = 1 + int(unit(rng) * 4);
    for (int64_t du = -r; du <= r; ++du)
      for (int64_t dv = -r; dv <= r; ++dv)
        for (int64_t dw = -r; dw <= r; ++dw)
          if (unit(rng) < 0.6) set(cu + du, cv + dv, cw + dw);
  }
  for (uint64_t i = 0; i < dims.count(); ++i)
    if (unit(rng) < density) occ[size_t(i)] = 1;
  for (uint32_t w = 0; w < dims.z; ++w)
    for (uint32_t v = 0; v < dims.y; ++v)
      for (uint32_t u = 0; u < dims.x; ++u)
        if (occ[size_t((uint64_t(w) * dims.y + v) * dims.x + u)]) {
          s.voxels.push_back({int32_t(u), int32_t(v), int32_t(w)});
          s.grid->addVoxel(u, v, w);
        }
  s.grid->finish();
  return s;
}

::testing::AssertionResult sameHit(const vox::RayHit& a, const vox::RayHit& b) {
  if (a.hit != b.hit) return ::testing::AssertionFailure() << "hit " << a.hit << " vs brute force " << b.hit;
  if (!a.hit) return ::testing::AssertionSuccess();
  if (!(a.voxel == b.voxel))
    return ::testing::AssertionFailure() << "voxel " << vox::toString(a.voxel) << " vs brute force "
                                         << vox::toString(b.voxel) << " (t " << a.t << " vs " << b.t << ")";
  if (a.t != b.t) return ::testing::AssertionFailure() << "t " << a.t << " vs " << b.t;
  if (a.faceAxis != b.faceAxis || a.faceSign != b.faceSign) return ::testing::AssertionFailure() << "face differs";
  return ::testing::AssertionSuccess();
}

std::string rayText(const Ray& r) {
  char b[256];
  std::snprintf(b, sizeof b, "origin (%.17g, %.17g, %.17g) dir (%.17g, %.17g, %.17g)", r.origin[0], r.origin[1],
                r.origin[2], r.dir[0], r.dir[1], r.dir[2]);
  return b;
}

// Rays chosen to hit the corner cases: integer origins (on planes, edges and
// corners), axis-parallel and diagonal directions through lattice points,
// origins inside the grid and inside voxels, far origins.
Ray adversarialRay(std::mt19937_64& rng, const vox::Dims& d) {
  std::uniform_int_distribution<int> pick(0, 9);
  std::uniform_real_distribution<double> unit(0, 1);
  const double ext[3] = {double(d.x), double(d.y), double(d.z)};
  auto intIn = [&](int a) { return std::floor(unit(rng) * (ext[a] + 5)) - 2; };
  auto smallInt = [&] { return double(int(unit(rng) * 5) - 2); };
  Ray r;
  switch (pick(rng)) {
    case 0:  // random origin around the grid, random direction
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = (unit(rng) * 1.6 - 0.3) * ext[a];
      for (int a = 0; a < 3; ++a) r.dir[size_t(a)] = unit(rng) * 2 - 1;
      break;
    case 1:  // lattice origin, lattice direction: passes exactly through edges and corners
    case 2:
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = intIn(a);
      for (int a = 0; a < 3; ++a) r.dir[size_t(a)] = smallInt();
      break;
    case 3: {  // axis-parallel, from a face, edge or corner
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = unit(rng) < 0.5 ? intIn(a) : unit(rng) * ext[a];
      const int axis = int(unit(rng) * 3);
      r.dir = {0, 0, 0};
      r.dir[size_t(axis)] = unit(rng) < 0.5 ? -1 : 1;
      break;
    }
    case 4: {  // in a grid plane (one direction component zero, origin on the plane)
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = unit(rng) * ext[a];
      const int axis = int(unit(rng) * 3);
      r.origin[size_t(axis)] = intIn(axis);
      for (int a = 0; a < 3; ++a) r.dir[size_t(a)] = unit(rng) * 2 - 1;
      r.dir[size_t(axis)] = 0;
      break;
    }
    case 5:  // far away (1e6 voxels; or 1e16, where plane times collide in double), aimed at the grid
    case 6: {
      double target[3];
      const double far = unit(rng) < 0.7 ? 1e6 : 1e16;
      for (int a = 0; a < 3; ++a) target[a] = unit(rng) * ext[a];
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = target[a] + (unit(rng) * 2 - 1) * far;
      for (int a = 0; a < 3; ++a) r.dir[size_t(a)] = target[a] - r.origin[size_t(a)];
      break;
    }
    case 7: {  // from a lattice point towards another lattice point inside
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = intIn(a);
      for (int a = 0; a < 3; ++a) r.dir[size_t(a)] = intIn(a) - r.origin[size_t(a)];
      break;
    }
    default:  // inside the grid, maybe inside an occupied voxel
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = unit(rng) * ext[a];
      for (int a = 0; a < 3; ++a) r.dir[size_t(a)] = unit(rng) * 2 - 1;
      break;
  }
  if (r.dir[0] == 0 && r.dir[1] == 0 && r.dir[2] == 0) r.dir[0] = 1;
  return r;
}

TEST(RayCast, EqualsBruteForceOnRandomScenesAndAdversarialRays) {
  std::mt19937_64 rng(20261122);
  uint64_t rays = 0, hits = 0;
  for (int sceneIndex = 0; sceneIndex < 40; ++sceneIndex) {
    std::uniform_int_distribution<uint32_t> side(1, 40);
    vox::Dims dims{side(rng), side(rng), side(rng)};
    if (sceneIndex % 10 == 9) dims = {1, 1, 1};
    const TestScene s = randomScene(rng, dims, 1 + sceneIndex % 6, sceneIndex % 3 == 0 ? 0.01 : 0.0);
    for (int i = 0; i < 1500; ++i) {
      const Ray r = adversarialRay(rng, dims);
      const vox::RayHit fast = vox::castRay(*s.grid, r);
      const vox::RayHit slow = vox::castRayBruteForce(s.voxels, r);
      ASSERT_TRUE(sameHit(fast, slow)) << "scene " << sceneIndex << " " << vox::toString(dims) << ", ray " << i << ": "
                                       << rayText(r);
      ++rays;
      hits += fast.hit;
    }
  }
  // Both outcomes must be well represented for the comparison to mean something.
  EXPECT_GT(hits, rays / 10);
  EXPECT_LT(hits, rays * 9 / 10);
}

TEST(RayCast, EqualsBruteForceAcrossTheHierarchyLevels) {
  // Large sparse grids: rays cross empty 512^3 supers, 64^3 regions and 8^3 bricks.
  std::mt19937_64 rng(7);
  for (const vox::Dims dims : {vox::Dims{1100, 70, 600}, vox::Dims{64, 64, 64}, vox::Dims{513, 9, 1030}}) {
    const TestScene s = randomScene(rng, dims, 30, 0.0);
    for (int i = 0; i < 400; ++i) {
      const Ray r = adversarialRay(rng, dims);
      ASSERT_TRUE(sameHit(vox::castRay(*s.grid, r), vox::castRayBruteForce(s.voxels, r)))
          << vox::toString(dims) << " ray " << i << ": " << rayText(r);
    }
  }
}

TEST(RayCast, EqualsBruteForceOnDomainsTooLargeForTheFlatBrickTable) {
  // 2048 x 1024 x 2048 is 2^23 bricks, past RayGrid's flat table (2^22): its
  // probes walk the tree. Sparse clusters, rays aimed at them or anywhere.
  std::mt19937_64 rng(29);
  const vox::Dims dims{2048, 1024, 2048};
  RayGrid grid(dims);
  std::vector<Coord3> voxels;
  std::uniform_real_distribution<double> unit(0, 1);
  for (int c = 0; c < 40; ++c) {
    const int32_t cu = int32_t(unit(rng) * 2040), cv = int32_t(unit(rng) * 1016), cw = int32_t(unit(rng) * 2040);
    for (int32_t du = 0; du < 6; ++du)
      for (int32_t dv = 0; dv < 6; ++dv)
        for (int32_t dw = 0; dw < 6; ++dw)
          if (unit(rng) < 0.4) {
            voxels.push_back({cu + du, cv + dv, cw + dw});
            grid.addVoxel(uint32_t(cu + du), uint32_t(cv + dv), uint32_t(cw + dw));
          }
  }
  grid.finish();
  int hits = 0;
  for (int i = 0; i < 600; ++i) {
    Ray r = adversarialRay(rng, dims);
    if (i % 2 == 0) {  // at a voxel of a cluster, from somewhere around the domain
      const Coord3& target = voxels[size_t(unit(rng) * double(voxels.size()))];
      const double t[3] = {target.u + unit(rng), target.v + unit(rng), target.w + unit(rng)};
      for (int a = 0; a < 3; ++a) r.dir[size_t(a)] = t[a] - r.origin[size_t(a)];
      if (r.dir[0] == 0 && r.dir[1] == 0 && r.dir[2] == 0) r.dir[0] = 1;
    }
    const vox::RayHit fast = vox::castRay(grid, r);
    ASSERT_TRUE(sameHit(fast, vox::castRayBruteForce(voxels, r))) << "ray " << i << ": " << rayText(r);
    hits += fast.hit;
  }
  EXPECT_GT(hits, 100);
}

TEST(RayCast, SkipsEmptySpaceInsteadOfSteppingThroughIt) {
  // One voxel at the far end of a 4096-long empty corridor: a per-voxel DDA
  // would take ~4000 steps; the hierarchy takes a few dozen.
  RayGrid g(vox::Dims{4096, 16, 16});
  g.addVoxel(4000, 3, 3);
  g.finish();
  Ray r;
  r.origin = {0.5, 3.5, 3.5};
  r.dir = {1, 1e-4, 0};
  const vox::RayHit h = vox::castRay(g, r);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.voxel, (Coord3{4000, 3, 3}));
  EXPECT_LT(h.steps, 40u);
  EXPECT_EQ(h.faceAxis, 0);
  EXPECT_EQ(h.faceSign, -1);
}

TEST(RayCast, TieBreaksAtEdgesAndCornersAsDocumented) {
  // A ray through the shared corner of 8 voxels, all occupied: every one is
  // touched at the same time; the one the ray goes into wins.
  RayGrid g(vox::Dims{4, 4, 4});
  std::vector<Coord3> all;
  for (int u = 1; u <= 2; ++u)
    for (int v = 1; v <= 2; ++v)
      for (int w = 1; w <= 2; ++w) g.addVoxel(uint32_t(u), uint32_t(v), uint32_t(w)), all.push_back({u, v, w});
  g.finish();
  Ray r;
  r.origin = {0, 0, 0};
  r.dir = {1, 1, 1};
  vox::RayHit h = vox::castRay(g, r);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.voxel, (Coord3{1, 1, 1}));  // entered through its corner at t = 1
  EXPECT_EQ(h.t, 1.0);
  // Along the edge x = 2, y = 2 (direction +z): four voxels share the edge,
  // all with the same exit; the smallest (w, v, u) wins.
  r.origin = {2, 2, -3};
  r.dir = {0, 0, 1};
  h = vox::castRay(g, r);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.voxel, (Coord3{1, 1, 1}));
  EXPECT_TRUE(sameHit(h, vox::castRayBruteForce(all, r)));
  // Starting inside a voxel: it is the hit, at t = 0, with no entry face.
  r.origin = {1.5, 1.5, 1.5};
  r.dir = {0.3, -0.2, 1};
  h = vox::castRay(g, r);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.voxel, (Coord3{1, 1, 1}));
  EXPECT_EQ(h.t, 0.0);
  EXPECT_EQ(h.faceAxis, -1);
}

TEST(RayCast, MissesWhenTheGridIsBehindOrBeside) {
  RayGrid g(vox::Dims{8, 8, 8});
  g.addVoxel(4, 4, 4);
  g.finish();
  Ray r;
  r.origin = {4.5, 4.5, 20};
  r.dir = {0, 0, 1};  // pointing away
  EXPECT_FALSE(vox::castRay(g, r).hit);
  r.dir = {0, 0, -1};
  EXPECT_TRUE(vox::castRay(g, r).hit);
  r.origin = {9, 4.5, 20};  // beside the grid, parallel
  EXPECT_FALSE(vox::castRay(g, r).hit);
  r.origin = {8, 4.5, 20};  // exactly on the grid's face plane: touches voxels x = 7 only
  EXPECT_FALSE(vox::castRay(g, r).hit);
}

TEST(RayGrid, ProbeLevelsAndOccupancy) {
  RayGrid g(vox::Dims{1200, 1200, 30});
  g.addVoxel(0, 0, 0);
  g.addVoxel(700, 600, 20);
  RayGrid::Mask512 m{};
  m[0] = 1;
  g.addBrick(1, 0, 0, m);  // voxel (8, 0, 0)
  g.finish();
  EXPECT_EQ(g.occupiedCount(), 3u);
  const RayGrid::Mask512* b = nullptr;
  EXPECT_EQ(g.probe(0, 0, 0, &b), 0);
  EXPECT_TRUE(g.occupied(8, 0, 0));
  EXPECT_FALSE(g.occupied(9, 0, 0));
  EXPECT_EQ(g.probe(16, 0, 0, &b), 1);     // empty brick in a non-empty region
  EXPECT_EQ(g.probe(64, 0, 0, &b), 2);     // empty region in a non-empty super
  EXPECT_EQ(g.probe(0, 600, 0, &b), 3);    // empty super
  EXPECT_EQ(g.probe(-1, 0, 0, &b), 3);     // outside
  EXPECT_EQ(g.probe(1200, 0, 0, &b), 3);
  std::vector<Coord3> seen;
  g.forEachOccupied([&](uint32_t u, uint32_t v, uint32_t w) { seen.push_back({int32_t(u), int32_t(v), int32_t(w)}); });
  EXPECT_EQ(seen.size(), 3u);
}

TEST(RayGrid, BrickDistanceFieldIsTheExactChebyshevDistance) {
  // Against brute force: the distance from every brick to the nearest
  // non-empty one (the caster jumps over boxes this distance says are empty,
  // so an overestimate would skip voxels).
  std::mt19937_64 rng(99);
  for (int trial = 0; trial < 6; ++trial) {
    std::uniform_int_distribution<uint32_t> side(1, 300);
    const vox::Dims dims{side(rng), side(rng) / 3 + 1, side(rng)};
    RayGrid g(dims);
    std::vector<std::array<int64_t, 3>> full;
    std::uniform_real_distribution<double> unit(0, 1);
    const int n = 1 + int(unit(rng) * 12);
    for (int i = 0; i < n; ++i) {
      const uint32_t u = uint32_t(unit(rng) * dims.x), v = uint32_t(unit(rng) * dims.y), w = uint32_t(unit(rng) * dims.z);
      g.addVoxel(u, v, w);
      full.push_back({u >> 3, v >> 3, w >> 3});
    }
    g.finish();
    const int64_t bx = (dims.x + 7) / 8, by = (dims.y + 7) / 8, bz = (dims.z + 7) / 8;
    for (int64_t x = 0; x < bx; ++x)
      for (int64_t y = 0; y < by; ++y)
        for (int64_t z = 0; z < bz; ++z) {
          int64_t best = 255;
          for (const auto& f : full)
            best = std::min(best, std::max({std::abs(f[0] - x), std::abs(f[1] - y), std::abs(f[2] - z)}));
          ASSERT_EQ(g.emptyBricksAround(x, y, z), uint32_t(best)) << "brick " << x << "," << y << "," << z << " of "
                                                                  << vox::toString(dims);
        }
  }
}

TEST(Camera, LookAtAndPerspectiveEqualHandComputedMatrices) {
  // Eye on +z looking at the origin: the view is a translation by -5 along z.
  const vox::Mat4d v = vox::lookAtMatrix({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
  const vox::Mat4d expectV = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1};
  for (int i = 0; i < 16; ++i) EXPECT_DOUBLE_EQ(v[size_t(i)], expectV[size_t(i)]) << i;
  // Eye on +x looking at the origin: camera x = world -z, camera z = world +x.
  const vox::Mat4d v2 = vox::lookAtMatrix({3, 0, 0}, {0, 0, 0}, {0, 1, 0});
  const vox::Mat4d expectV2 = {0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, -3, 1};
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(v2[size_t(i)], expectV2[size_t(i)], 1e-15) << i;
  // fov 90: f = 1; aspect 2; near 0.1, far 500 (the block-map format's createPerspective).
  const vox::Mat4d p = vox::perspectiveMatrix(3.14159265358979323846 / 2, 2.0, 0.1, 500.0);
  EXPECT_NEAR(p[0], 0.5, 1e-15);
  EXPECT_NEAR(p[5], 1.0, 1e-15);
  EXPECT_NEAR(p[10], (500.0 + 0.1) / (0.1 - 500.0), 1e-15);
  EXPECT_EQ(p[11], -1.0);
  EXPECT_NEAR(p[14], 2 * 500.0 * 0.1 / (0.1 - 500.0), 1e-15);
  EXPECT_EQ(p[15], 0.0);
}

TEST(Camera, PixelRaysGoThroughPixelCentresRowZeroAtTheTop) {
  // 90 degree vertical fov, square image of 2 x 2: the four pixel centres are
  // at NDC (+-0.5, +-0.5), i.e. camera directions (+-0.5, +-0.5, -1).
  const vox::Camera c = vox::Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 2, 2);
  vox::Vec3d o, d;
  c.pixelRay(0, 0, o, d);  // top left
  const double l = std::sqrt(0.25 + 0.25 + 1);
  EXPECT_NEAR(d[0], -0.5 / l, 1e-15);
  EXPECT_NEAR(d[1], 0.5 / l, 1e-15);
  EXPECT_NEAR(d[2], -1 / l, 1e-15);
  c.pixelRay(1, 1, o, d);  // bottom right
  EXPECT_NEAR(d[0], 0.5 / l, 1e-15);
  EXPECT_NEAR(d[1], -0.5 / l, 1e-15);
  EXPECT_EQ(o, (vox::Vec3d{0, 0, 0}));
}

TEST(Camera, MetadataJsonViewsGiveTheSameRaysAsLookAt) {
  // A block-map metadata.json whose matrices are the look-at ones (as float32
  // would store them, printed with full precision).
  const vox::Vec3d eye{10.5, 20, 15.3}, target{0, 2, 0};
  const vox::Mat4d view = vox::lookAtMatrix(eye, target, {0, 1, 0});
  const vox::Mat4d proj = vox::perspectiveMatrix(60 * 3.14159265358979323846 / 180, 640.0 / 480.0, 0.1, 500);
  nlohmann::json views = nlohmann::json::array();
  nlohmann::json vj = {{"id", "view_001"}, {"index", 0}};
  vj["viewMatrix"] = std::vector<double>(view.begin(), view.end());
  vj["projectionMatrix"] = std::vector<double>(proj.begin(), proj.end());
  views.push_back(vj);
  const nlohmann::json doc = {{"formatVersion", "1.0"}, {"imageSize", {{"width", 640}, {"height", 480}}}, {"views", views}};
  const auto cams = vox::parseCameraJson(doc.dump(), "metadata.json", std::nullopt);
  ASSERT_EQ(cams.size(), 1u);
  EXPECT_EQ(cams[0].label, "view 0 (view_001)");
  const vox::Camera ref = vox::Camera::lookAt(eye, target, {0, 1, 0}, 60, 640, 480);
  for (uint32_t y : {0u, 239u, 479u})
    for (uint32_t x : {0u, 320u, 639u}) {
      vox::Vec3d o1, d1, o2, d2;
      cams[0].camera.pixelRay(x, y, o1, d1);
      ref.pixelRay(x, y, o2, d2);
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(o1[size_t(a)], o2[size_t(a)], 1e-12);
        EXPECT_NEAR(d1[size_t(a)], d2[size_t(a)], 1e-14);
      }
    }
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(cams[0].camera.eye[size_t(a)], eye[size_t(a)], 1e-12);
}

TEST(Camera, BadCameraFilesNameTheElement) {
  using voxtest::throwsVoxError;
  const auto bad = vox::ErrorKind::BadInput;
  EXPECT_TRUE(throwsVoxError([] { vox::parseCameraJson("{\"imageSize\":{\"width\":4,\"height\":4},\"views\": [{\"viewMatrix\": [1,2,3]}]}", "m.json", std::nullopt); },
                             bad, {"m.json", "views[0]"}));
  EXPECT_TRUE(throwsVoxError(
      [] {
        vox::parseCameraJson("{\"imageSize\":{\"width\":4,\"height\":4},\"views\":[{\"viewMatrix\":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1],"
                             "\"projectionMatrix\":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]}]}",
                             "m.json", std::nullopt);
      },
      bad, {"m.json", "views[0]", "perspective"}));
  EXPECT_TRUE(throwsVoxError([] { vox::parseCameraJson("{\"eye\": [0,0,\"x\"], \"target\": [0,0,0]}", "c.json", std::nullopt); },
                             bad, {"c.json", "camera.eye[2]"}));
  EXPECT_TRUE(throwsVoxError([] { vox::parseCameraJson("{\"eye\": [0,0,0], \"target\": [0,0,0]}", "c.json", std::nullopt); },
                             bad, {"c.json", "distinct"}));
  EXPECT_TRUE(throwsVoxError([] { vox::parseCameraJson("[1,2]", "c.json", std::nullopt); }, bad, {"c.json", "object"}));
  // A look-at camera's keys are all read: a misspelt one is refused, not left
  // to its default (a "fvo" rendered at 60 degrees).
  EXPECT_TRUE(throwsVoxError(
      [] { vox::parseCameraJson(R"({"cameras": [{"eye": [0,0,9], "target": [0,0,0], "fvo": 20}]})", "c.json", std::nullopt); },
      bad, {"c.json", "cameras[0] has no key \"fvo\"", "eye, target, up, fov, size, view"}));
  // What --camera-out writes reads back; metadata.json views keep their other fields.
  EXPECT_EQ(vox::parseCameraJson(R"({"eye": [0,0,9], "target": [0,0,0], "up": [0,1,0], "fov": 20, "size": [4, 3],
                                    "view": "front"})", "c.json", std::nullopt).size(), 1u);
  EXPECT_EQ(vox::parseCameraJson(R"({"imageSize": {"width": 4, "height": 4}, "views": [{"index": 0, "id": "v0",
                                    "viewMatrix": [1,0,0,0,0,1,0,0,0,0,1,0,0,0,-5,1],
                                    "projectionMatrix": [1,0,0,0,0,1,0,0,0,0,-1,-1,0,0,-0.2,0], "time": 3}]})",
                                 "m.json", std::nullopt).size(), 1u);
}

TEST(Camera, LookAtErrorsNameTheSettingNotAnOption) {
  auto settingOf = [](auto&& fn) {
    try {
      fn();
    } catch (const vox::Error& e) {
      EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
      EXPECT_EQ(e.kind, vox::ErrorKind::Usage) << e.what();
      return e.setting;
    }
    ADD_FAILURE() << "no error";
    return vox::Setting::None;
  };
  EXPECT_EQ(settingOf([] { vox::Camera::lookAt({0, 0, 5}, {0, 0, 0}, {0, 0, 1}, 60, 8, 8); }), vox::Setting::CameraUp);
  EXPECT_EQ(settingOf([] { vox::Camera::lookAt({0, 0, 5}, {0, 0, 5}, {0, 1, 0}, 60, 8, 8); }), vox::Setting::CameraPose);
  EXPECT_EQ(settingOf([] { vox::Camera::lookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 180, 8, 8); }),
            vox::Setting::FieldOfView);
  EXPECT_EQ(settingOf([] { vox::Camera::lookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60, 0, 8); }), vox::Setting::ImageSize);
}

TEST(Render, CheckStrideKeepsTheBruteForceWithinItsBudget) {
  EXPECT_EQ(vox::checkStride(6144, 15512, vox::kDefaultCheckBudget), 1u);  // every pixel
  EXPECT_EQ(vox::checkStride(1000, 1000, 1e5), 10u);
  EXPECT_EQ(vox::checkStride(1000, 1001, 1e5), 11u);                     // rounded up
  EXPECT_EQ(vox::checkStride(1000, 0, 0), 1000u);                        // no voxels still costs a test per ray
}

TEST(Render, CanonicalFormatIsTheNarrowestExactOne) {
  EXPECT_EQ(vox::canonicalBits({1, 1, 1}), 8);
  EXPECT_EQ(vox::canonicalBits({256, 3, 256}), 8);       // coordinates 0..255
  EXPECT_EQ(vox::canonicalBits({4, 257, 4}), 16);        // 256 needs 16 bits
  EXPECT_EQ(vox::canonicalBits({65536, 1, 1}), 16);      // 0..65535
  EXPECT_EQ(vox::canonicalBits({1, 1, 65537}), 32);      // EXR UINT
}

TEST(Shading, TerrainFormulaByHandForEveryFaceDirection) {
  // sunDir = normalize(-0.4, -0.85, -0.5): |s| = sqrt(1.1325).
  const double s = std::sqrt(1.1325);
  const double sky[3] = {0.53, 0.81, 0.92}, horizon[3] = {0.18, 0.16, 0.12}, sun[3] = {1.0, 0.97, 0.9};
  const std::array<double, 3> base{0.5, 0.25, 1.0};
  struct Face {
    std::array<int, 3> n;
    double diffuse;  // max(dot(n, -sunDir), 0)
    double skyFactor;
  };
  const Face faces[] = {{{1, 0, 0}, 0.4 / s, 0.5},  {{-1, 0, 0}, 0.0, 0.5}, {{0, 1, 0}, 0.85 / s, 1.0},
                        {{0, -1, 0}, 0.0, 0.0},     {{0, 0, 1}, 0.5 / s, 0.5}, {{0, 0, -1}, 0.0, 0.5}};
  for (const Face& f : faces) {
    const auto got = vox::terrainShade(base, f.n);
    for (int c = 0; c < 3; ++c) {
      const double ambient = (horizon[c] * (1 - f.skyFactor) + sky[c] * f.skyFactor) * 0.55;
      EXPECT_NEAR(got[size_t(c)], base[size_t(c)] * (ambient + f.diffuse * sun[c]), 1e-12)
          << "normal " << f.n[0] << "," << f.n[1] << "," << f.n[2] << " channel " << c;
    }
  }
  // Palette slots: +y top, -y bottom, every horizontal face side.
  vox::ClassInfo grass;
  grass.id = 1;
  grass.name = "Grass";
  grass.color = {1, 2, 3};
  grass.faces = vox::FacePalette{{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
  EXPECT_EQ(vox::facePaletteColor(&grass, {0, 1, 0}), (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(vox::facePaletteColor(&grass, {0, -1, 0}), (std::array<double, 3>{0, 1, 0}));
  EXPECT_EQ(vox::facePaletteColor(&grass, {0, 0, -1}), (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(vox::facePaletteColor(&grass, {1, 0, 0}), (std::array<double, 3>{0, 0, 1}));
}

TEST(Render, DemoViewEqualsBruteForceAndIsThreadIndependent) {
  vox::HamletOptions ho;
  ho.resolution = 64;
  const vox::Scene scene = vox::buildHamlet(ho);
  const RayGrid grid = vox::rayGridFromScene(scene);
  EXPECT_EQ(grid.occupiedCount(), scene.occupiedCount());
  const vox::GridFrame frame{scene.header().origin, scene.header().voxelSize};
  const std::vector<Coord3> occupied = grid.occupiedVoxels();
  // A general view, an axis-aligned one from straight above (rays in grid
  // planes), and one from inside the scene.
  const std::vector<vox::Camera> cams = {
      vox::Camera::lookAt({20, 15, 20}, {0, 2, 0}, {0, 1, 0}, 50, 48, 36),
      vox::Camera::lookAt({0, 40, 0}, {0, 0, 0}, {0, 0, -1}, 40, 33, 33),
      vox::Camera::lookAt({0.05, 1.0, 0.05}, {5, 1, 3}, {0, 1, 0}, 90, 40, 30)};
  for (size_t i = 0; i < cams.size(); ++i) {
    const vox::ViewHits one = vox::castView(grid, frame, cams[i], 1);
    const vox::ViewHits two = vox::castView(grid, frame, cams[i], 2);
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    for (size_t p = 0; p < one.pixels.size(); ++p)
      ASSERT_TRUE(one.pixels[p].hit == two.pixels[p].hit && one.pixels[p].u == two.pixels[p].u &&
                  one.pixels[p].v == two.pixels[p].v && one.pixels[p].w == two.pixels[p].w && one.pixels[p].depth == two.pixels[p].depth);
    const vox::ViewCheck c = vox::checkView(one, occupied, frame, cams[i], 1, 2);
    EXPECT_EQ(c.pixelsChecked, one.pixels.size());
    EXPECT_EQ(c.pixelsDiffering, 0u) << "camera " << i;
    EXPECT_GT(one.hitCount, 0u) << "camera " << i;
  }
}

}  // namespace
