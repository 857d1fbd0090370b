// Region bakes end to end in the library: every part (a demo or mesh bake
// restricted to tile I of N) equals the whole bake cropped to the tile, and
// the merge of all parts equals the whole bake; bad sets of parts are refused.
#include <gtest/gtest.h>

#include <cmath>

#include "libvox/core/regions.h"
#include "libvox/scene/demo_hamlet.h"
#include "libvox/scene/scene_parts.h"
#include "libvox/scene/voxelize_scene.h"
#include "test_util.h"

using namespace vox;

namespace {

/// A scene with `region` as its region record (the world key is a stand-in).
Scene withRegion(Scene s, uint32_t index, uint32_t count, const IndexBox& box) {
  s.header().region = SceneRegion{index, count, box, "key"};
  return s;
}

void expectSame(const Scene& a, const Scene& b, const std::string& what) {
  const SceneDifference d = compareScenes(a, b);
  EXPECT_TRUE(d.same()) << what << ": " << d.headerNote << " " << d.voxelsDiffering << " voxels differ, first "
                        << (d.firstDifference ? toString(*d.firstDifference) : "-") << ": " << d.firstNote;
}

/// A lumpy sphere (both classes, vertex colours), optionally with its top cap
/// cut away (an open mesh).
Mesh lumpySphere(double cx, double cy, double cz, double r, bool open) {
  Mesh m;
  const int nu = 41, nv = 23;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
      const double rr = r * (1 + 0.15 * std::sin(3 * ph) * std::sin(2 * th));
      const double x = rr * std::sin(th) * std::cos(ph), y = rr * std::cos(th), z = 1.3 * rr * std::sin(th) * std::sin(ph);
      m.positions.push_back({cx + x, cy + y, cz + z});
      m.colors.push_back({float(0.5 + x / (2.6 * r)), float(0.5 + y / (2.6 * r)), float(0.5 + z / (3.4 * r)), 1.0f});
    }
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      if (open && j < 3) continue;
      const uint32_t a = uint32_t(j * nu + i), b = uint32_t(j * nu + (i + 1) % nu), c = uint32_t((j + 1) * nu + i),
                     d = uint32_t((j + 1) * nu + (i + 1) % nu);
      m.triangles.push_back({a, c, b});
      m.triangles.push_back({b, c, d});
    }
  m.triangleMaterial.assign(m.triangles.size(), 0);
  m.trianglePart.assign(m.triangles.size(), 0);
  m.materials.push_back({});
  m.parts.push_back({"part", "mesh"});
  return m;
}

SceneHeader meshHeader(uint32_t n) {
  SceneHeader h;
  h.dims = {n, n / 2, n};
  h.classes.add({1, "a", {255, 0, 0}, std::nullopt});
  h.classes.add({2, "b", {0, 255, 0}, std::nullopt});
  return h;
}

}  // namespace

TEST(RegionBake, HamletPartsAreTheWorldCropped) {
  HamletOptions o;
  o.resolution = 96;  // 3 x 3 cells of 32 voxels in x-z
  o.threads = 2;
  const Scene world = buildHamlet(o);
  for (uint32_t n : {1u, 2u, 3u, 7u}) {
    std::vector<Scene> parts;
    for (uint32_t i = 0; i < n; ++i) {
      const IndexBox tile = regionTile(world.header().dims, i, n);
      HamletOptions p = o;
      p.box = tile;
      p.threads = 1 + i % 2;
      Scene part = buildHamlet(p);
      expectSame(part, cropScene(world, tile), "hamlet tile " + std::to_string(i) + " of " + std::to_string(n));
      parts.push_back(withRegion(std::move(part), i, n, tile));
    }
    expectSame(mergeSceneParts(std::move(parts)), world, "hamlet merged from " + std::to_string(n));
  }
}

TEST(RegionBake, MeshPartsAreTheWorldCropped) {
  struct Case {
    const char* name;
    bool open;
    FillMode fill;
    SolidRule rule;
  };
  const Case cases[] = {{"surface", false, FillMode::Surface, SolidRule::Winding},
                        {"solid closed", false, FillMode::Solid, SolidRule::Winding},
                        {"solid open", true, FillMode::Solid, SolidRule::Winding},
                        {"parity closed", false, FillMode::Solid, SolidRule::Parity},
                        {"parity open", true, FillMode::Solid, SolidRule::Parity}};
  const SceneHeader h = meshHeader(80);
  for (const Case& c : cases) {
    // Centre off the cell lines, so triangles straddle every cut.
    const Mesh mesh = lumpySphere(41.3, 20.2, 38.7, 17.0, c.open);
    std::vector<uint8_t> cls(mesh.triangles.size());
    for (size_t t = 0; t < cls.size(); ++t) cls[t] = uint8_t(1 + (t / 7) % 2);
    VoxelizeSettings s;
    s.fill = c.fill;
    s.solidRule = c.rule;
    s.threads = 2;
    const Scene world = voxelizeMesh(mesh, cls, h, s);
    ASSERT_GT(world.occupiedCount(), 1000u) << c.name;
    for (uint32_t n : {2u, 3u, 7u}) {
      std::vector<Scene> parts;
      for (uint32_t i = 0; i < n; ++i) {
        const IndexBox tile = regionTile(h.dims, i, n);
        VoxelizeSettings r = s;
        r.region = tile;
        r.threads = 1 + i % 2;
        Scene part = voxelizeMesh(mesh, cls, h, r);
        expectSame(part, cropScene(world, tile),
                   std::string(c.name) + " tile " + std::to_string(i) + " of " + std::to_string(n));
        parts.push_back(withRegion(std::move(part), i, n, tile));
      }
      expectSame(mergeSceneParts(std::move(parts)), world, std::string(c.name) + " merged from " + std::to_string(n));
    }
  }
}

TEST(RegionBake, EmptyTilesAreValidParts) {
  HamletOptions o;
  o.resolution = 64;  // 2 x 2 cells: tiles 4.. of 9 hold nothing
  const Scene world = buildHamlet(o);
  std::vector<Scene> parts;
  size_t empty = 0;
  for (uint32_t i = 0; i < 9; ++i) {
    const IndexBox tile = regionTile(world.header().dims, i, 9);
    HamletOptions p = o;
    p.box = tile;
    Scene part = buildHamlet(p);
    if (tile.empty()) {
      ++empty;
      EXPECT_EQ(part.occupiedCount(), 0u);
    }
    parts.push_back(withRegion(std::move(part), i, 9, tile));
  }
  EXPECT_GT(empty, 0u);
  expectSame(mergeSceneParts(std::move(parts)), world, "hamlet merged from 9 with empty tiles");
}

TEST(RegionBake, MergeRefusesBadSets) {
  HamletOptions o;
  o.resolution = 64;
  auto parts = [&](std::vector<uint32_t> which, uint32_t n) {
    std::vector<Scene> out;
    for (uint32_t i : which) {
      HamletOptions p = o;
      p.box = regionTile({64, 64, 64}, i, n);
      out.push_back(withRegion(buildHamlet(p), i, n, *p.box));
    }
    return out;
  };
  EXPECT_TRUE(voxtest::throwsVoxError([&] { mergeSceneParts(parts({0, 2}, 3), {"a.vdb", "b.vdb"}); },
                                      ErrorKind::BadInput, {"tile 1 of 3", "missing"}));
  EXPECT_TRUE(voxtest::throwsVoxError([&] { mergeSceneParts(parts({0, 1, 1, 2}, 3), {"a", "b", "c", "d"}); },
                                      ErrorKind::BadInput, {"c"}));
  {
    std::vector<Scene> p = parts({0, 1}, 2);
    p[1].header().region.reset();  // a whole scene
    EXPECT_TRUE(voxtest::throwsVoxError([&] { mergeSceneParts(std::move(p), {"a.vdb", "whole.vdb"}); },
                                        ErrorKind::BadInput, {"whole.vdb", "no region record"}));
  }
  {
    std::vector<Scene> p = parts({0, 1}, 2);
    p[1].header().region->worldKey = "other";
    EXPECT_TRUE(voxtest::throwsVoxError([&] { mergeSceneParts(std::move(p), {"a.vdb", "b.vdb"}); },
                                        ErrorKind::BadInput, {"b.vdb"}));
  }
  {
    std::vector<Scene> p = parts({0, 1}, 2);
    p[0].header().mipLevel = 1;
    EXPECT_TRUE(voxtest::throwsVoxError([&] { mergeSceneParts(std::move(p), {"a.vdb", "b.vdb"}); },
                                        ErrorKind::BadInput, {"a.vdb", "pyramid"}));
  }
  {
    // A voxel outside the part's box: not a part as voxelize writes it.
    std::vector<Scene> p = parts({0, 1}, 2);
    p[0].header().region->box = regionTile({64, 64, 64}, 0, 4);
    p[0].header().region->index = 0;
    p[1].header().region->box = regionTile({64, 64, 64}, 1, 2);
    EXPECT_ANY_THROW(mergeSceneParts(std::move(p), {"a.vdb", "b.vdb"}));
  }
}

// Two overlapping solids of different classes whose +z crossings below a cut
// (enter b, enter a, leave b) decide the class of the voxels above it: a
// region keeps the crossings below its box in their order along the ray, so
// the enclosing class there is a's, as in the whole bake.
TEST(RegionBake, CrossingsBelowARegionKeepTheirOrder) {
  Mesh a = lumpySphere(40.2, 20.1, 30.3, 10.0, false), b = lumpySphere(40.2, 20.1, 14.1, 7.0, false);
  const size_t na = a.triangles.size();
  a.append(b);
  std::vector<uint8_t> cls(a.triangles.size(), 2);
  std::fill(cls.begin(), cls.begin() + long(na), uint8_t(1));
  const SceneHeader h = meshHeader(80);
  for (SolidRule rule : {SolidRule::Winding, SolidRule::Parity}) {
    VoxelizeSettings s;
    s.fill = FillMode::Solid;
    s.solidRule = rule;
    const Scene world = voxelizeMesh(a, cls, h, s);
    for (int32_t cut : {32, 64}) {
      for (const IndexBox box : {IndexBox{{0, 0, 0}, {79, 39, cut - 1}}, IndexBox{{0, 0, cut}, {79, 39, 79}}}) {
        VoxelizeSettings r = s;
        r.region = box;
        expectSame(voxelizeMesh(a, cls, h, r), cropScene(world, box),
                   std::string(rule == SolidRule::Winding ? "winding" : "parity") + " box from w " +
                       std::to_string(box.min.w));
      }
    }
  }
}
