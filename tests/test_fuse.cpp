// `vox fuse` (docs/fuse.md) against exact oracles: renders of random scenes
// (castView, render-canonical's caster) fused back give exactly the voxels
// the rays hit with the pixels' classes and vote counts, free counts only on
// empty voxels; the face tie rule by hand; the carve rule and its
// several-runs equivalence; views that miss the grid, cameras inside it, 1x1
// images; the same counts at any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "libvox/render/camera.h"
#include "libvox/render/fuse.h"
#include "libvox/render/intrinsics.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/render.h"
#include "libvox/core/error.h"
#include "libvox/scene/fuse_scene.h"
#include "libvox/scene/scene.h"

namespace {

using vox::Coord3;
using vox::Dims;
using vox::FuseCounts;

uint8_t classOfVoxel(const Coord3& c) { return uint8_t(1 + (c.u * 7 + c.v * 3 + c.w) % 5); }

struct Truth {
  Dims dims;
  std::set<uint64_t> occupied;
  std::unique_ptr<vox::RayGrid> grid;
};

Truth randomTruth(std::mt19937_64& rng, Dims dims, double density) {
  Truth t;
  t.dims = dims;
  t.grid = std::make_unique<vox::RayGrid>(dims);
  std::uniform_real_distribution<double> unit(0, 1);
  // A floor, a few boxes and scattered voxels.
  for (uint32_t w = 0; w < dims.z; ++w)
    for (uint32_t v = 0; v < dims.y; ++v)
      for (uint32_t u = 0; u < dims.x; ++u) {
        bool on = v == 0 || unit(rng) < density;
        if (u >= 3 && u < 7 && w >= 4 && w < 9 && v < 6) on = true;
        if (!on) continue;
        t.grid->addVoxel(u, v, w);
        t.occupied.insert(FuseCounts::voxelKey(Coord3{int32_t(u), int32_t(v), int32_t(w)}));
      }
  t.grid->finish();
  return t;
}

// The view render-canonical would write: depth (float) and class per pixel, the face axis.
vox::FuseView renderView(const Truth& t, const vox::GridFrame& frame, const vox::Camera& cam, bool withFaces,
                         std::vector<vox::PixelHit>* hitsOut = nullptr) {
  const vox::ViewHits hits = vox::castView(*t.grid, frame, cam, 1);
  vox::FuseView v;
  v.camera = cam;
  v.depth.assign(hits.pixels.size(), std::numeric_limits<double>::infinity());
  v.classes.assign(hits.pixels.size(), 0);
  if (withFaces) v.faceAxis.assign(hits.pixels.size(), -1);
  for (size_t i = 0; i < hits.pixels.size(); ++i) {
    const vox::PixelHit& p = hits.pixels[i];
    if (!p.hit) continue;
    v.depth[i] = double(p.depth);
    v.classes[i] = classOfVoxel(Coord3{p.u, p.v, p.w});
    if (withFaces) v.faceAxis[i] = p.faceAxis;
  }
  if (hitsOut) *hitsOut = hits.pixels;
  return v;
}

std::vector<vox::Camera> cameras(std::mt19937_64& rng, const Truth& t, const vox::GridFrame& frame, int n) {
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<vox::Camera> out;
  const double X = t.dims.x * frame.voxelSize, Y = t.dims.y * frame.voxelSize, Z = t.dims.z * frame.voxelSize;
  for (int i = 0; i < n; ++i) {
    vox::Vec3d eye, target;
    if (i % 4 == 3) {  // inside the grid
      eye = {frame.origin[0] + X * (0.2 + 0.6 * unit(rng)), frame.origin[1] + Y * (0.3 + 0.6 * unit(rng)),
             frame.origin[2] + Z * (0.2 + 0.6 * unit(rng))};
    } else {
      const double a = 6.28318 * unit(rng), r = 1.5 * std::max(X, Z);
      eye = {frame.origin[0] + X / 2 + r * std::cos(a), frame.origin[1] + Y * (0.5 + 1.5 * unit(rng)),
             frame.origin[2] + Z / 2 + r * std::sin(a)};
    }
    target = {frame.origin[0] + X * unit(rng), frame.origin[1] + Y * 0.3 * unit(rng), frame.origin[2] + Z * unit(rng)};
    out.push_back(vox::Camera::lookAt(eye, target, {0, 1, 0}, 50 + 30 * unit(rng), 48 + uint32_t(i) * 3, 40));
  }
  return out;
}

TEST(FuseRay, DepthOnAFaceGoesToTheVoxelBehind) {
  vox::Ray r;
  r.origin = {0.5, 0.5, 0.5};
  r.dir = {1, 0, 0};
  const Dims d{8, 1, 1};
  vox::DepthMeasure m;
  FuseCounts free;
  vox::FuseRayResult h = vox::fuseRay(r, 1.0, m, 3.5, d, &free);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.voxel, (Coord3{4, 0, 0}));
  EXPECT_EQ(h.freeCells, 4u);  // cells 0..3
  EXPECT_FALSE(h.ambiguous);
  h = vox::fuseRay(r, 1.0, m, 3.4, d, nullptr);
  EXPECT_EQ(h.voxel, (Coord3{3, 0, 0}));
  h = vox::fuseRay(r, 1.0, m, 0.25, d, nullptr);
  EXPECT_EQ(h.voxel, (Coord3{0, 0, 0}));
  EXPECT_EQ(h.freeCells, 0u);
  // Beyond the grid: no vote, every cell free.
  h = vox::fuseRay(r, 1.0, m, 1e30, d, nullptr);
  EXPECT_FALSE(h.hit);
  EXPECT_EQ(h.freeCells, 0u);  // nullptr sink counts nothing
  FuseCounts f2;
  h = vox::fuseRay(r, 1.0, m, 1e30, d, &f2);
  EXPECT_EQ(h.freeCells, 8u);
  // Voxel size and z depth: the same cells at 2 world units per voxel.
  h = vox::fuseRay(r, 2.0, m, 7.0, d, nullptr);
  EXPECT_EQ(h.voxel, (Coord3{4, 0, 0}));
  vox::DepthMeasure z;
  z.kind = vox::DepthKind::Z;
  h = vox::fuseRay(r, 2.0, z, 3.5, d, nullptr);
  EXPECT_EQ(h.voxel, (Coord3{4, 0, 0}));
}

// A ray clipping the corner of a voxel on the grid's boundary: it enters
// through x = 4 and leaves the grid through y = 0 about 1e-8 later, so both
// crossings round to one float32 depth. render-canonical hits the voxel and
// stores its entry's depth; the voxel behind the exit lies outside the grid,
// so the vote goes to the voxel inside (exact with the face axis, ambiguous
// without). A depth exactly on the exit face from a cell entered below it
// still lies beyond the grid.
TEST(FuseRay, TieGroupLeavingTheGridKeepsTheVoxelInside) {
  vox::Ray r;
  r.origin = {10, 6 + 1e-8, 0.5};
  r.dir = {-1, -1, 0};
  const Dims d{4, 4, 4};
  vox::DepthMeasure m;  // distance, float32
  const double length = std::sqrt(2.0);
  const double entry = double(float(6.0 * length)), exit = double(float((6 + 1e-8) * length));
  ASSERT_EQ(entry, exit);
  FuseCounts free;
  for (FuseCounts* sink : {static_cast<FuseCounts*>(nullptr), &free}) {
    vox::FuseRayResult h = vox::fuseRay(r, 1.0, m, entry, d, sink, 0);
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.voxel, (Coord3{3, 0, 0}));
    EXPECT_FALSE(h.ambiguous);
    h = vox::fuseRay(r, 1.0, m, entry, d, sink);
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.voxel, (Coord3{3, 0, 0}));
    EXPECT_TRUE(h.ambiguous);
  }
  EXPECT_EQ(free.freeBricks(), 0u);  // the ray enters the grid at its hit
  // Along x inside the grid, the depth exactly on the exit face x = 0.
  r.origin = {3.5, 0.5, 0.5};
  r.dir = {-1, 0, 0};
  EXPECT_FALSE(vox::fuseRay(r, 1.0, m, 3.5, d, nullptr).hit);
  FuseCounts free2;
  EXPECT_FALSE(vox::fuseRay(r, 1.0, m, 3.5, d, &free2).hit);
}

// Without free counts the walk starts just before the depth: the same hit,
// for any depth (on faces, inside voxels, before and beyond the grid).
TEST(FuseRay, StartingNearTheDepthGivesTheSameHit) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0, 1);
  const Dims d{32, 20, 28};
  uint64_t hits = 0;
  for (int i = 0; i < 20000; ++i) {
    vox::Ray r;
    const double ext[3] = {double(d.x), double(d.y), double(d.z)};
    for (int a = 0; a < 3; ++a) {
      r.origin[size_t(a)] = -20 + 70 * unit(rng);
      r.dir[size_t(a)] = ext[a] * unit(rng) - r.origin[size_t(a)];  // toward a point of the grid
    }
    if (i % 5 == 0) r.origin[0] = std::floor(r.origin[0]);  // lattice origins
    if (i % 7 == 0) r.dir[1] = 0;                           // rays parallel to a plane
    const double vs = i % 3 == 0 ? 0.25 : 1.0;
    vox::DepthMeasure m;
    m.kind = i % 4 == 0 ? vox::DepthKind::Z : vox::DepthKind::Distance;
    m.float32 = i % 2 == 0;
    const double len = std::sqrt(r.dir[0] * r.dir[0] + r.dir[1] * r.dir[1] + r.dir[2] * r.dir[2]);
    double depth = (m.kind == vox::DepthKind::Z ? 1.0 : len * vs) * 2 * unit(rng);
    if (m.float32) depth = double(float(depth));
    FuseCounts free;
    const vox::FuseRayResult a = vox::fuseRay(r, vs, m, depth, d, &free);
    const vox::FuseRayResult b = vox::fuseRay(r, vs, m, depth, d, nullptr);
    ASSERT_EQ(a.hit, b.hit) << i;
    if (a.hit) {
      ++hits;
      ASSERT_EQ(a.voxel, b.voxel) << i;
      ASSERT_EQ(a.ambiguous, b.ambiguous) << i;
    }
  }
  EXPECT_GT(hits, 2000u);
}

TEST(FuseRay, RaysThatMissTheGridVoteNothing) {
  vox::Ray r;
  r.origin = {-5, 0.5, 10};
  r.dir = {1, 0, 0};
  FuseCounts free;
  const vox::FuseRayResult h = vox::fuseRay(r, 1.0, vox::DepthMeasure{}, 6.0, Dims{4, 4, 4}, &free);
  EXPECT_FALSE(h.hit);
  EXPECT_EQ(h.freeCells, 0u);
  EXPECT_EQ(free.freeBricks(), 0u);
  // A depth before the grid: nothing either.
  r.origin = {-5, 0.5, 0.5};
  EXPECT_FALSE(vox::fuseRay(r, 1.0, vox::DepthMeasure{}, 2.0, Dims{4, 4, 4}, &free).hit);
  EXPECT_EQ(free.freeBricks(), 0u);
  EXPECT_TRUE(vox::fuseRay(r, 1.0, vox::DepthMeasure{}, 5.0, Dims{4, 4, 4}, &free).hit);
}

// Every pixel of every view against the caster: the voted voxels are exactly
// the hit voxels, each with its pixels' class and count; free counts only on
// empty voxels.
void roundTrip(bool withFaces, uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int scene = 0; scene < 6; ++scene) {
    const Dims dims{20 + uint32_t(scene), 14, 18 + 2 * uint32_t(scene)};
    const Truth t = randomTruth(rng, dims, 0.02 + 0.01 * scene);
    vox::GridFrame frame;
    frame.voxelSize = 0.1 * (scene + 1);
    frame.origin = {-1.3 * scene, 0.25, 2.0};
    vox::FuseSettings settings;
    settings.threads = 2;
    vox::Fuser fuser(dims, frame, settings);
    std::map<std::pair<uint64_t, uint8_t>, uint64_t> expected;
    uint64_t ambiguous = 0, mismatched = 0;
    for (const vox::Camera& cam : cameras(rng, t, frame, 8)) {
      std::vector<vox::PixelHit> hits;
      const vox::FuseView view = renderView(t, frame, cam, withFaces, &hits);
      const vox::FuseViewStats s = fuser.add(view);
      ambiguous += s.ambiguous;
      const vox::PixelRays rays(cam, frame);
      for (size_t i = 0; i < hits.size(); ++i) {
        const vox::PixelHit& p = hits[i];
        if (!p.hit || !(p.depth > 0)) continue;
        const Coord3 c{p.u, p.v, p.w};
        expected[{FuseCounts::voxelKey(c), classOfVoxel(c)}] += 1;
        const vox::FuseRayResult r = vox::fuseRay(rays.ray(uint32_t(i % cam.width), uint32_t(i / cam.width)),
                                                  frame.voxelSize, view.measure, view.depth[i], dims, nullptr,
                                                  withFaces ? p.faceAxis : -1);
        if (!r.hit || !(r.voxel == c)) ++mismatched;
      }
    }
    const FuseCounts counts = std::move(fuser).finish();
    std::map<std::pair<uint64_t, uint8_t>, uint64_t> got;
    for (const FuseCounts::Vote& v : counts.votes()) got[{FuseCounts::voxelKey(v.at), v.classId}] += v.votes;
    if (withFaces) {
      EXPECT_EQ(ambiguous, 0u) << "scene " << scene;
      EXPECT_EQ(mismatched, 0u) << "scene " << scene;
      EXPECT_EQ(got, expected) << "scene " << scene;
    } else {
      EXPECT_LE(mismatched, ambiguous) << "scene " << scene;
    }
    for (const auto& [c, n] : counts.freeVoxels())
      ASSERT_EQ(t.occupied.count(FuseCounts::voxelKey(c)), 0u)
          << "scene " << scene << ": free count on occupied voxel " << vox::toString(c);
  }
}

TEST(Fuse, RoundTripWithNormalsIsExact) { roundTrip(true, 17); }
TEST(Fuse, RoundTripDepthOnlyMissesOnlyAmbiguousPixels) { roundTrip(false, 18); }

// Grazing rays: an eye on a grid plane looking along it (the middle row of an
// odd-height image lies inside the plane). Mismatches stay within the pixels
// reported ambiguous, and the in-plane rays are among them.
TEST(Fuse, GrazingRaysAreReportedAmbiguous) {
  std::mt19937_64 rng(11);
  const Dims dims{24, 12, 24};
  const Truth t = randomTruth(rng, dims, 0.04);
  vox::GridFrame frame;
  vox::Fuser fuser(dims, frame, vox::FuseSettings{});
  const vox::Camera cam = vox::Camera::lookAt({-6.3, 3.0, 7.7}, {20, 3.0, 13.1}, {0, 1, 0}, 50, 41, 31);
  std::vector<vox::PixelHit> hits;
  const vox::FuseView view = renderView(t, frame, cam, true, &hits);
  const vox::PixelRays rays(cam, frame);
  uint64_t mismatched = 0, ambiguous = 0, middleRowHits = 0;
  for (size_t i = 0; i < hits.size(); ++i) {
    if (!hits[i].hit || !(hits[i].depth > 0)) continue;
    const uint32_t x = uint32_t(i % cam.width), y = uint32_t(i / cam.width);
    const vox::Ray ray = rays.ray(x, y);
    if (y == 15) {
      ASSERT_EQ(ray.dir[1], 0.0);
      ++middleRowHits;
    }
    const vox::FuseRayResult r = vox::fuseRay(ray, 1.0, view.measure, view.depth[i], dims, nullptr, hits[i].faceAxis);
    ambiguous += r.ambiguous ? 1 : 0;
    if (y == 15) {
      EXPECT_TRUE(r.ambiguous);
    }
    if (!r.hit || !(r.voxel == Coord3{hits[i].u, hits[i].v, hits[i].w})) {
      ++mismatched;
      EXPECT_TRUE(r.ambiguous) << "pixel " << x << ", " << y;
    }
  }
  EXPECT_GT(middleRowHits, 0u);
  EXPECT_LE(mismatched, ambiguous);
  (void)fuser;
}

TEST(Fuse, CountsDoNotDependOnThreads) {
  std::mt19937_64 rng(5);
  const Dims dims{24, 12, 24};
  const Truth t = randomTruth(rng, dims, 0.03);
  vox::GridFrame frame;
  const std::vector<vox::Camera> cams = cameras(rng, t, frame, 4);
  std::vector<std::vector<std::pair<Coord3, uint32_t>>> free;
  std::vector<std::vector<FuseCounts::Vote>> votes;
  for (unsigned threads : {1u, 2u, 3u}) {
    vox::FuseSettings s;
    s.threads = threads;
    vox::Fuser fuser(dims, frame, s);
    for (const vox::Camera& c : cams) fuser.add(renderView(t, frame, c, false));
    const FuseCounts counts = std::move(fuser).finish();
    free.push_back(counts.freeVoxels());
    votes.push_back(counts.votes());
  }
  for (size_t i = 1; i < free.size(); ++i) {
    EXPECT_EQ(free[i], free[0]);
    ASSERT_EQ(votes[i].size(), votes[0].size());
    for (size_t k = 0; k < votes[0].size(); ++k) {
      EXPECT_EQ(votes[i][k].at, votes[0][k].at);
      EXPECT_EQ(votes[i][k].classId, votes[0][k].classId);
      EXPECT_EQ(votes[i][k].votes, votes[0][k].votes);
    }
  }
}

TEST(Fuse, ViewsThatMissTheGridAndTinyImages) {
  std::mt19937_64 rng(9);
  const Dims dims{16, 16, 16};
  const Truth t = randomTruth(rng, dims, 0.05);
  vox::GridFrame frame;
  vox::Fuser fuser(dims, frame, vox::FuseSettings{});
  // Looking away from the grid with made-up depths: every pixel outside.
  vox::FuseView away;
  away.camera = vox::Camera::lookAt({-10, 8, 8}, {-20, 8, 8}, {0, 1, 0}, 40, 8, 6);
  away.depth.assign(48, 5.0);
  away.classes.assign(48, 1);
  vox::FuseViewStats s = fuser.add(away);
  EXPECT_EQ(s.used, 0u);
  EXPECT_EQ(s.outside, 48u);
  EXPECT_EQ(s.freeCounts, 0u);
  // 1x1: the centre ray.
  const vox::Camera one = vox::Camera::lookAt({8.2, 20, 8.3}, {8.2, 0, 8.31}, {0, 0, -1}, 30, 1, 1);
  s = fuser.add(renderView(t, frame, one, true));
  EXPECT_EQ(s.pixels, 1u);
  EXPECT_EQ(s.used, 1u);
  // No depth, no class: skipped and counted.
  vox::FuseView holes = renderView(t, frame, vox::Camera::lookAt({30, 20, 30}, {8, 0, 8}, {0, 1, 0}, 40, 10, 10), false);
  holes.depth[0] = 0;
  holes.depth[1] = std::nan("");
  holes.depth[2] = -1;
  holes.classes[3] = 0;
  holes.depth[3] = 10;
  s = fuser.add(holes);
  EXPECT_GE(s.noDepth, 3u);
  EXPECT_EQ(s.unlabelled, 1u);
  EXPECT_EQ(s.used + s.noDepth + s.unlabelled + s.outside, 100u);
}

// OpenCV intrinsics + pose: each pixel's ray projects back to the pixel's
// integer coordinates by the OpenCV formulas (the independent oracle), and
// equals the ray of the equivalent look-at camera.
TEST(FuseCamera, IntrinsicsPutPixelCentresAtIntegerCoordinates) {
  const uint32_t W = 64, H = 40;
  const vox::Intrinsics k{50.5, 48.25, 30.75, 21.5};
  // A camera-to-world pose: rotation about a tilted axis plus a translation.
  const double a = 0.7, c = std::cos(a), s = std::sin(a);
  vox::Mat4d pose{c, 0, -s, 0, /**/ s * 0.6, 0.8, c * 0.6, 0, /**/ s * 0.8, -0.6, c * 0.8, 0, /**/ 3, -2, 5, 1};
  const vox::Camera cam = vox::intrinsicsCamera(k, pose, W, H, "test");
  const vox::Mat4d toCv = vox::inverse(pose);
  for (uint32_t y = 0; y < H; y += 3)
    for (uint32_t x = 0; x < W; x += 3) {
      vox::Vec3d o, d;
      cam.pixelRay(x, y, o, d);
      double p[3];
      for (int i = 0; i < 3; ++i) p[i] = o[size_t(i)] + 7.0 * d[size_t(i)];
      double q[3];
      for (int r = 0; r < 3; ++r)
        q[r] = toCv[size_t(r)] * p[0] + toCv[size_t(4 + r)] * p[1] + toCv[size_t(8 + r)] * p[2] + toCv[size_t(12 + r)];
      ASSERT_GT(q[2], 0);
      EXPECT_NEAR(k.fx * q[0] / q[2] + k.cx, double(x), 1e-9);
      EXPECT_NEAR(k.fy * q[1] / q[2] + k.cy, double(y), 1e-9);
    }
  // The look-at camera with the same pinhole: the same rays.
  const vox::Camera look = vox::Camera::lookAt({4, 5, 6}, {0, 1, -1}, {0, 1, 0}, 55, W, H);
  const double f = 1 / std::tan(55 * M_PI / 360);
  vox::Mat4d glToWorld = look.cameraToWorld;
  for (size_t i = 4; i < 12; ++i) glToWorld[i] = -glToWorld[i];  // OpenCV's y and z axes
  const vox::Camera same = vox::intrinsicsCamera({f * H / 2, f * H / 2, (W - 1) / 2.0, (H - 1) / 2.0}, glToWorld, W, H, "test");
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      vox::Vec3d o1, d1, o2, d2;
      look.pixelRay(x, y, o1, d1);
      same.pixelRay(x, y, o2, d2);
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(o1[size_t(i)], o2[size_t(i)], 1e-12);
        EXPECT_NEAR(d1[size_t(i)], d2[size_t(i)], 1e-12);
      }
    }
  vox::Mat4d singular{};
  EXPECT_THROW(vox::intrinsicsCamera(k, singular, W, H, "test"), vox::Error);
  EXPECT_THROW(vox::intrinsicsCamera({0, 1, 1, 1}, pose, W, H, "test"), vox::Error);
}

vox::SceneHeader header(Dims d) {
  vox::SceneHeader h;
  h.dims = d;
  h.classes = vox::blockPalette();
  return h;
}

TEST(FuseScene, CarveRuleAndRunsAddUp) {
  const Dims d{8, 8, 8};
  // Voxel a: 2 votes, 3 free -> removed (net free 1). b: 3 votes, 3 free -> kept.
  // c: 1 vote in run 1 (kept), 2 free in run 2 -> removed by the totals.
  auto run1 = [] {
    FuseCounts c;
    c.addVote({1, 1, 1}, 2, 2);
    for (int i = 0; i < 3; ++i) c.addFree(1, 1, 1);
    c.addVote({2, 2, 2}, 3, 3);
    for (int i = 0; i < 3; ++i) c.addFree(2, 2, 2);
    c.addVote({3, 3, 3}, 1, 1);
    c.addFree(4, 4, 4);
    return c;
  };
  auto run2 = [] {
    FuseCounts c;
    c.addFree(3, 3, 3);
    c.addFree(3, 3, 3);
    c.addVote({1, 1, 1}, 2, 1);  // a: 3 votes against 3 free in total: back
    return c;
  };
  vox::FusedScene one = vox::applyFusion(header(d), nullptr, run1(), true);
  EXPECT_EQ(one.totals.occupiedAfter, 2u);  // b, c
  EXPECT_EQ(one.totals.rejected, 1u);       // a
  EXPECT_EQ(one.free.freeAt({1, 1, 1}), 1u);
  EXPECT_EQ(one.free.freeAt({2, 2, 2}), 3u);
  EXPECT_EQ(one.free.freeAt({4, 4, 4}), 1u);
  // Second run on top of the first, through the free list a file would hold.
  FuseCounts second = run2();
  for (const auto& [c, n] : one.free.freeVoxels()) second.addFreeCount(c, n);
  vox::FusedScene two = vox::applyFusion(header(d), &one.scene, std::move(second), true);
  // One run with everything.
  FuseCounts all = run1();
  all.merge(run2());
  vox::FusedScene both = vox::applyFusion(header(d), nullptr, std::move(all), true);
  std::set<uint64_t> occTwo, occBoth;
  two.scene.forEachVoxel([&](const vox::VoxelView& v) { occTwo.insert(FuseCounts::voxelKey(v.at)); });
  both.scene.forEachVoxel([&](const vox::VoxelView& v) { occBoth.insert(FuseCounts::voxelKey(v.at)); });
  EXPECT_EQ(occTwo, occBoth);
  EXPECT_EQ(occBoth, (std::set<uint64_t>{FuseCounts::voxelKey({1, 1, 1}), FuseCounts::voxelKey({2, 2, 2})}));
  EXPECT_EQ(two.totals.removed, 1u);  // c
  EXPECT_EQ(two.totals.created, 1u);  // a again
  // Carving off keeps everything.
  vox::FusedScene off = vox::applyFusion(header(d), nullptr, run1(), false);
  EXPECT_EQ(off.totals.occupiedAfter, 3u);
  EXPECT_EQ(off.free.freeAt({1, 1, 1}), 3u);
}

}  // namespace
