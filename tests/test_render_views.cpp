// Seeing a scene: the color mode and shading over voxel colours against
// hand-computed pixels, named views and orbits framed on the occupied box,
// camera files that reproduce a framed camera exactly, the voxel-walk
// reference against the brute force, and progress that never goes backwards.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <set>
#include <tuple>

#include "formats/core/camera_json.h"
#include "formats/image/render_meta.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/raycast.h"
#include "libvox/render/render.h"
#include "libvox/render/render_modes.h"
#include "libvox/render/touched_voxels.h"
#include "libvox/render/view_framing.h"
#include "libvox/render/voxel_walk.h"
#include "libvox/scene/render_scene.h"
#include "libvox/scene/scene.h"

namespace {

using vox::Coord3;
using vox::Ray;

// Two voxels side by side along x: (0, 0, 0) of class 1 with linear colour
// (0.5, 0.25, 1.0), (1, 0, 0) of class 2 without colour.
vox::Scene twoVoxelScene() {
  vox::SceneHeader h;
  h.dims = {2, 1, 1};
  h.classes = vox::blockPalette();
  vox::SceneBuilder b(h);
  b.addVotes({0, 0, 0}, 1, 10, true);
  b.addVotes({1, 0, 0}, 2, 10, true);
  b.setColor({0, 0, 0}, vox::RgbLinear{0.5f, 0.25f, 1.0f});
  return std::move(b).build();
}

// A 2 x 1 image looking down -z at the scene's +z face (z = 1) from z = 10:
// with aspect 2 and f = 1 / tan(fov / 2) = 18 the pixel centres (NDC x = -0.5
// and +0.5) meet the face at x = 0.5 and x = 1.5, the centres of the two voxels.
vox::Camera faceCamera() {
  const double fov = 2 * std::atan(1.0 / 18.0) * 180.0 / 3.14159265358979323846;
  return vox::Camera::lookAt({1, 0.5, 10}, {1, 0.5, 0}, {0, 1, 0}, fov, 2, 1);
}

struct FaceRender {
  vox::ViewHits hits;
  vox::TouchedVoxels touched;
  std::vector<vox::SummaryTexel> summaries;
  std::vector<vox::VoxelColor8> colors;
};

FaceRender renderFace(const vox::Scene& scene, const vox::Camera& camera) {
  const vox::RayGrid grid = vox::rayGridFromScene(scene);
  FaceRender r;
  r.hits = vox::castView(grid, vox::GridFrame{}, camera, 1);
  r.touched = vox::TouchedVoxels(std::vector<vox::ViewHits>{r.hits});
  r.summaries = vox::sceneSummaries(scene, r.touched.voxels());
  r.colors = vox::sceneColors(scene, r.touched.voxels());
  return r;
}

TEST(RenderColor, VoxelColourIsSrgbEncodedAndClassColourFillsIn) {
  const vox::Scene scene = twoVoxelScene();
  const vox::Camera camera = faceCamera();
  const FaceRender r = renderFace(scene, camera);
  ASSERT_TRUE(r.hits.pixels[0].hit && r.hits.pixels[1].hit);
  EXPECT_EQ(r.hits.pixels[0].u, 0);
  EXPECT_EQ(r.hits.pixels[1].u, 1);
  EXPECT_EQ(r.hits.pixels[0].faceAxis, 2);  // entered through +z
  const vox::ModeImage img = vox::colorImage(r.hits, scene.header().classes, {&r.touched, r.summaries},
                                             {&r.touched, r.colors});
  ASSERT_EQ(img.channels, 4u);
  // sRGB of 0.5, 0.25, 1.0: 1.055 c^(1/2.4) - 0.055 = 0.7354, 0.5371, 1 -> x 255 rounded.
  EXPECT_EQ((std::vector<uint8_t>(img.pixels.begin(), img.pixels.begin() + 4)), (std::vector<uint8_t>{188, 137, 255, 255}));
  const vox::Rgb8 dirt = scene.header().classes.find(2)->color;
  EXPECT_EQ((std::vector<uint8_t>(img.pixels.begin() + 4, img.pixels.end())),
            (std::vector<uint8_t>{dirt.r, dirt.g, dirt.b, 255}));
}

TEST(RenderColor, ShadedLitOverTheVoxelColourOrTheClassPalette) {
  const vox::Scene scene = twoVoxelScene();
  const vox::Camera camera = faceCamera();
  const FaceRender r = renderFace(scene, camera);
  const vox::ClassTable& classes = scene.header().classes;
  const vox::ModeImage voxel = vox::shadedImage(r.hits, camera, classes, {&r.touched, r.summaries},
                                                vox::ShadeColor::Voxel, {&r.touched, r.colors});
  // Face +z: diffuse = 0.5 / |(-0.4, -0.85, -0.5)| = 0.469841, sky factor 0.5,
  // ambient = (horizon + sky) / 2 x 0.55; base = (188, 137, 255) / 255:
  // (0.49034, 0.38816, 0.70886) x 255 -> 125, 99, 181.
  EXPECT_EQ((std::vector<uint8_t>(voxel.pixels.begin(), voxel.pixels.begin() + 3)), (std::vector<uint8_t>{125, 99, 181}));
  // The voxel without colour is shaded over its class's side palette, as with --shade-color class.
  const vox::ModeImage byClass =
      vox::shadedImage(r.hits, camera, classes, {&r.touched, r.summaries}, vox::ShadeColor::Class, {&r.touched, r.colors});
  EXPECT_EQ(std::vector<uint8_t>(voxel.pixels.begin() + 3, voxel.pixels.end()),
            std::vector<uint8_t>(byClass.pixels.begin() + 3, byClass.pixels.end()));
  // The class default is the shading of before: the class palette everywhere.
  const vox::ModeImage old = vox::shadedImage(r.hits, camera, classes, {&r.touched, r.summaries});
  EXPECT_EQ(old.pixels, byClass.pixels);
  const std::array<double, 3> side = vox::facePaletteColor(classes.find(1), {0, 0, 1});
  const std::array<double, 3> lit = vox::terrainShade(side, {0, 0, 1});
  EXPECT_EQ(byClass.pixels[0], uint8_t(std::lround(std::clamp(lit[0], 0.0, 1.0) * 255)));
}

TEST(RenderColor, ScenesWithoutColourAndMissesAreClassColouredAndTransparent) {
  vox::SceneHeader h;
  h.dims = {2, 1, 1};
  h.classes = vox::blockPalette();
  vox::SceneBuilder b(h);
  b.addVotes({1, 0, 0}, 3, 5, true);
  const vox::Scene scene = std::move(b).build();
  const FaceRender r = renderFace(scene, faceCamera());
  EXPECT_FALSE(r.hits.pixels[0].hit);
  const vox::ModeImage color = vox::colorImage(r.hits, scene.header().classes, {&r.touched, r.summaries},
                                               {&r.touched, r.colors});
  const vox::ModeImage cls = vox::classImage(r.hits, scene.header().classes, {&r.touched, r.summaries});
  EXPECT_EQ(color.pixels, cls.pixels);
  EXPECT_EQ(color.pixels[3], 0);  // a miss is transparent
}

TEST(ViewFraming, NamesDirectionsAndUpVectors) {
  EXPECT_EQ(vox::namedViewFrom("side"), vox::NamedView::Right);
  EXPECT_FALSE(vox::namedViewFrom("Front"));
  for (vox::NamedView v : vox::kNamedViews) EXPECT_EQ(vox::namedViewFrom(vox::namedViewName(v)), v);
  vox::Vec3d toEye, up;
  vox::namedViewDirection(vox::NamedView::Top, toEye, up);
  EXPECT_EQ(toEye, (vox::Vec3d{0, 1, 0}));
  EXPECT_EQ(up, (vox::Vec3d{0, 0, -1}));
  vox::namedViewDirection(vox::NamedView::Front, toEye, up);
  EXPECT_EQ(toEye, (vox::Vec3d{0, 0, 1}));
  // Orbit view 0 is the iso direction; the elevation is the iso one for every view.
  vox::namedViewDirection(vox::NamedView::Iso, toEye, up);
  const vox::Vec3d o0 = vox::orbitDirection(0, 6), o3 = vox::orbitDirection(3, 6);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(o0[size_t(a)], toEye[size_t(a)], 1e-12);
  EXPECT_NEAR(o3[1], toEye[1], 1e-12);
  EXPECT_NEAR(o3[0], -toEye[0], 1e-12);
}

TEST(ViewFraming, EveryCornerOfTheBoxProjectsWithinPointNineAndTheBoxFillsTheImage) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> unit(0, 1);
  const std::pair<uint32_t, uint32_t> sizes[] = {{512, 512}, {1920, 1080}, {300, 800}, {1, 1}};
  for (int trial = 0; trial < 40; ++trial) {
    vox::WorldBox box;
    for (int a = 0; a < 3; ++a) {
      box.min[size_t(a)] = (unit(rng) - 0.5) * 100;
      box.max[size_t(a)] = box.min[size_t(a)] + 0.01 + unit(rng) * (trial % 4 == 0 ? 0.5 : 60);
    }
    const auto [w, h] = sizes[trial % 4];
    const double fov = 10 + unit(rng) * 100;
    std::vector<std::pair<vox::Vec3d, vox::Vec3d>> dirs;
    for (vox::NamedView v : vox::kNamedViews) {
      vox::Vec3d d, up;
      vox::namedViewDirection(v, d, up);
      dirs.push_back({d, up});
    }
    for (uint32_t i = 0; i < 7; ++i) dirs.push_back({vox::orbitDirection(i, 7), {0, 1, 0}});
    for (const auto& [d, up] : dirs) {
      const vox::LookAtCamera look = vox::frameBox(box, d, up, fov, w, h);
      const std::array<double, 2> e = vox::cornerNdcExtent(look.camera(), box);
      EXPECT_LE(e[0], 0.9) << "trial " << trial;
      EXPECT_LE(e[1], 0.9) << "trial " << trial;
      EXPECT_GT(std::max(e[0], e[1]), 0.9 - 1e-6) << "trial " << trial << ": the box does not fill the image";
    }
  }
}

TEST(ViewFraming, RayGridKnowsTheExactOccupiedBox) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 30; ++trial) {
    std::uniform_int_distribution<uint32_t> side(1, 90);
    const vox::Dims dims{side(rng), side(rng), side(rng)};
    vox::RayGrid grid(dims);
    std::array<int64_t, 3> lo{INT64_MAX, INT64_MAX, INT64_MAX}, hi{0, 0, 0};
    const int n = 1 + int(rng() % 20);
    for (int i = 0; i < n; ++i) {
      const uint32_t p[3] = {uint32_t(rng() % dims.x), uint32_t(rng() % dims.y), uint32_t(rng() % dims.z)};
      grid.addVoxel(p[0], p[1], p[2]);
      for (size_t a = 0; a < 3; ++a) lo[a] = std::min<int64_t>(lo[a], p[a]), hi[a] = std::max<int64_t>(hi[a], p[a] + 1);
    }
    grid.finish();
    EXPECT_EQ(grid.occupiedMin(), lo);
    EXPECT_EQ(grid.occupiedEnd(), hi);
  }
  vox::RayGrid empty(vox::Dims{4, 4, 4});
  empty.finish();
  EXPECT_EQ(empty.occupiedEnd(), (std::array<int64_t, 3>{0, 0, 0}));
}

TEST(CameraFile, AFramedCameraRoundTripsBitForBitThroughTheFileAndTheImageMetadata) {
  vox::WorldBox box{{-3.3, 0, -1.7}, {2.9, 4.1, 5.3}};
  vox::LookAtCamera look = vox::frameBox(box, vox::orbitDirection(2, 7), {0, 1, 0}, 37.5, 640, 360);
  look.view = "orbit 2/7";
  const std::string text = vox::lookAtCameraFileJson({look});
  const std::vector<vox::CameraView> back = vox::parseCameraJson(text, "cam.json", std::nullopt);
  ASSERT_EQ(back.size(), 1u);
  ASSERT_TRUE(back[0].lookAt);
  EXPECT_EQ(*back[0].lookAt, look);
  EXPECT_EQ(back[0].camera.view, look.camera().view);
  EXPECT_EQ(back[0].camera.projection, look.camera().projection);
  EXPECT_EQ(back[0].label, "orbit 2/7");
  // Several cameras: {"cameras": [...]}.
  vox::LookAtCamera other = look;
  other.view.clear();
  const std::vector<vox::CameraView> two =
      vox::parseCameraJson(vox::lookAtCameraFileJson({look, other}), "cams.json", std::nullopt);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(*two[1].lookAt, other);
  // In the render metadata.
  vox::RenderMeta meta;
  meta.dims = {4, 5, 6};
  meta.viewMatrix = look.camera().view;
  meta.projectionMatrix = look.camera().projection;
  meta.width = 640;
  meta.height = 360;
  meta.lookAt = look;
  const std::string entry = vox::renderMetaJson(meta);
  EXPECT_NE(entry.find("\"look_at\""), std::string::npos);
  EXPECT_EQ(vox::parseRenderMeta(entry, "x.png"), meta);
  meta.lookAt.reset();  // cameras given by hand carry no look_at: the entry is as before
  EXPECT_EQ(vox::renderMetaJson(meta).find("look_at"), std::string::npos);
}

// Random clusters and scattered voxels, as the caster's own tests use.
std::vector<Coord3> randomVoxels(std::mt19937_64& rng, const vox::Dims& dims, int clusters) {
  std::vector<Coord3> out;
  std::uniform_real_distribution<double> unit(0, 1);
  for (int c = 0; c < clusters; ++c) {
    const int cu = int(unit(rng) * dims.x), cv = int(unit(rng) * dims.y), cw = int(unit(rng) * dims.z);
    const int r = 1 + int(unit(rng) * 4);
    for (int du = -r; du <= r; ++du)
      for (int dv = -r; dv <= r; ++dv)
        for (int dw = -r; dw <= r; ++dw) {
          const int u = cu + du, v = cv + dv, w = cw + dw;
          if (u < 0 || v < 0 || w < 0 || u >= int(dims.x) || v >= int(dims.y) || w >= int(dims.z)) continue;
          if (unit(rng) < 0.6) out.push_back({u, v, w});
        }
  }
  std::sort(out.begin(), out.end(), [](const Coord3& a, const Coord3& b) {
    return std::tie(a.u, a.v, a.w) < std::tie(b.u, b.v, b.w);
  });
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// Origins on lattice points, planes and edges, axis-parallel rays, rays in a
// grid plane, rays from inside voxels and from 1e6 and 1e16 voxels away.
Ray trickyRay(std::mt19937_64& rng, const vox::Dims& d) {
  std::uniform_real_distribution<double> unit(0, 1);
  const double ext[3] = {double(d.x), double(d.y), double(d.z)};
  auto intIn = [&](int a) { return std::floor(unit(rng) * (ext[a] + 5)) - 2; };
  auto smallInt = [&] { return double(int(unit(rng) * 5) - 2); };
  Ray r;
  switch (rng() % 8) {
    case 0:
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = (unit(rng) * 1.6 - 0.3) * ext[a];
      for (int a = 0; a < 3; ++a) r.dir[size_t(a)] = unit(rng) * 2 - 1;
      break;
    case 1:
    case 2:
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = intIn(a), r.dir[size_t(a)] = smallInt();
      break;
    case 3: {
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = unit(rng) < 0.5 ? intIn(a) : unit(rng) * ext[a];
      r.dir = {0, 0, 0};
      r.dir[rng() % 3] = unit(rng) < 0.5 ? -1 : 1;
      break;
    }
    case 4: {
      const size_t axis = rng() % 3;
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = unit(rng) * ext[a], r.dir[size_t(a)] = unit(rng) * 2 - 1;
      r.origin[axis] = intIn(int(axis));
      r.dir[axis] = 0;
      break;
    }
    case 5: {
      const double far = unit(rng) < 0.6 ? 1e6 : 1e16;
      for (int a = 0; a < 3; ++a) {
        const double target = unit(rng) * ext[a];
        r.origin[size_t(a)] = target + (unit(rng) * 2 - 1) * far;
        r.dir[size_t(a)] = target - r.origin[size_t(a)];
      }
      break;
    }
    case 6:
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = intIn(a);
      for (int a = 0; a < 3; ++a) r.dir[size_t(a)] = intIn(a) - r.origin[size_t(a)];
      break;
    default:
      for (int a = 0; a < 3; ++a) r.origin[size_t(a)] = unit(rng) * ext[a], r.dir[size_t(a)] = unit(rng) * 2 - 1;
      break;
  }
  if (r.dir[0] == 0 && r.dir[1] == 0 && r.dir[2] == 0) r.dir[0] = 1;
  return r;
}

TEST(VoxelWalk, EqualsTheBruteForceOnRandomScenesAndAdversarialRays) {
  std::mt19937_64 rng(20261125);
  uint64_t rays = 0, hits = 0;
  for (int sceneIndex = 0; sceneIndex < 40; ++sceneIndex) {
    std::uniform_int_distribution<uint32_t> side(1, 40);
    vox::Dims dims{side(rng), side(rng), side(rng)};
    if (sceneIndex % 10 == 9) dims = {1, 1, 1};
    const std::vector<Coord3> voxels = randomVoxels(rng, dims, 1 + sceneIndex % 6);
    const vox::VoxelWalk walk(voxels);
    for (int i = 0; i < 1500; ++i) {
      const Ray r = trickyRay(rng, dims);
      const vox::RayHit got = walk.cast(r), want = vox::castRayBruteForce(voxels, r);
      ASSERT_EQ(got.hit, want.hit) << "scene " << sceneIndex << " ray " << i;
      ++rays;
      if (!got.hit) continue;
      ++hits;
      ASSERT_EQ(got.voxel, want.voxel) << "scene " << sceneIndex << " ray " << i;
      ASSERT_EQ(got.t, want.t);
      ASSERT_EQ(got.faceAxis, want.faceAxis);
      ASSERT_EQ(got.faceSign, want.faceSign);
    }
  }
  EXPECT_GT(hits, rays / 10);
  EXPECT_LT(hits, rays * 9 / 10);
}

TEST(VoxelWalk, ChecksAWholeViewLikeTheBruteForce) {
  std::mt19937_64 rng(3);
  const vox::Dims dims{48, 20, 33};
  const std::vector<Coord3> voxels = randomVoxels(rng, dims, 25);
  vox::RayGrid grid(dims);
  for (const Coord3& c : voxels) grid.addVoxel(uint32_t(c.u), uint32_t(c.v), uint32_t(c.w));
  grid.finish();
  const vox::GridFrame frame{{-2, 0, 1}, 0.5};
  const vox::Camera camera = vox::Camera::lookAt({30, 20, 40}, {10, 4, 9}, {0, 1, 0}, 50, 64, 48);
  vox::ViewHits hits = vox::castView(grid, frame, camera, 2);
  const vox::VoxelWalk walk(voxels);
  const vox::ReferenceCaster ref = [&](const Ray& r) { return walk.cast(r); };
  const vox::ViewCheck all = vox::checkView(hits, ref, frame, camera, 1, 2);
  EXPECT_EQ(all.pixelsChecked, 64u * 48);
  EXPECT_EQ(all.pixelsDiffering, 0u);
  // A wrong pixel is found and named.
  size_t wrong = 0;
  while (!hits.pixels[wrong].hit) ++wrong;
  hits.pixels[wrong].u += 1;
  const vox::ViewCheck bad = vox::checkView(hits, ref, frame, camera, 1, 2);
  EXPECT_EQ(bad.pixelsDiffering, 1u);
  ASSERT_EQ(bad.first.size(), 1u);
  EXPECT_EQ(bad.first[0].x, wrong % 64);
}

TEST(CheckSampling, OnePixelInEachRunOfKWithVaryingOffsets) {
  const uint64_t pixels = 400 * 300, stride = 400;  // a stride equal to the width
  const uint64_t n = vox::sampledPixelCount(pixels, stride);
  EXPECT_EQ(n, 300u);
  std::set<uint64_t> columns;
  for (uint64_t s = 0; s < n; ++s) {
    const uint64_t p = vox::sampledPixel(s, pixels, stride);
    EXPECT_GE(p, s * stride);
    EXPECT_LT(p, std::min(pixels, (s + 1) * stride));
    columns.insert(p % 400);
  }
  EXPECT_GT(columns.size(), 100u);  // not one column
  EXPECT_LT(vox::sampledPixel(3, 10, 3), 10u);  // the last, shorter run
  for (uint64_t s = 0; s < 10; ++s) EXPECT_EQ(vox::sampledPixel(s, 10, 1), s);
}

TEST(RenderProgress, FractionsNeverGoBackwardsAndCallsNeverOverlap) {
  std::mt19937_64 rng(9);
  const vox::Dims dims{64, 64, 64};
  vox::RayGrid grid(dims);
  for (const Coord3& c : randomVoxels(rng, dims, 60)) grid.addVoxel(uint32_t(c.u), uint32_t(c.v), uint32_t(c.w));
  grid.finish();
  const vox::Camera camera = vox::Camera::lookAt({90, 70, 80}, {32, 20, 32}, {0, 1, 0}, 60, 64, 1024);
  std::vector<double> seen;
  std::atomic<int> inside{0};
  bool overlapped = false;
  auto record = [&](double f) {
    if (inside.fetch_add(1) != 0) overlapped = true;
    seen.push_back(f);
    inside.fetch_sub(1);
  };
  for (int run = 0; run < 2; ++run) {
    seen.clear();
    vox::castView(grid, vox::GridFrame{}, camera, 4, record);
    ASSERT_FALSE(seen.empty());
    for (size_t i = 1; i < seen.size(); ++i) ASSERT_GT(seen[i], seen[i - 1]) << "run " << run << " call " << i;
    const vox::VoxelWalk walk(grid.occupiedVoxels());
    seen.clear();
    const vox::ViewHits hits = vox::castView(grid, vox::GridFrame{}, camera, 4);
    vox::checkView(hits, [&](const Ray& r) { return walk.cast(r); }, vox::GridFrame{}, camera, 1, 4, record);
    ASSERT_FALSE(seen.empty());
    for (size_t i = 1; i < seen.size(); ++i) ASSERT_GT(seen[i], seen[i - 1]) << "check, run " << run;
  }
  EXPECT_FALSE(overlapped);
}

}  // namespace
