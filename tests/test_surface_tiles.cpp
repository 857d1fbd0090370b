// The surface pass's tiles (libvox/mesh/voxelize.cpp): the domain is cut
// along x, and along y where a slab holds more than its share, by the work of
// the triangles' candidate voxels, and coloured meshes are tiled on one thread
// too. Where the tiles end must not show: large coloured triangles, textured
// ones, and triangles lying on the block boundaries where tiles may end give
// the same scene (votes, colours, surface flags) at every thread count, and a
// wall whose voxels all sit in one block column (cut along y) keeps the exact
// votes of its area.
#include <gtest/gtest.h>

#include <cmath>

#include "libvox/scene/scene_diff.h"
#include "libvox/scene/voxelize_scene.h"
#include "test_util.h"
#include "voxelize_test_meshes.h"

using namespace vox;

namespace {

/// `meshOf` with a colour per vertex (rgb from the position).
Mesh colouredMesh(const std::vector<std::array<double, 3>>& pos, const std::vector<std::array<uint32_t, 3>>& tris) {
  Mesh m = voxtest::meshOf(pos, tris);
  for (const auto& p : pos)
    m.colors.push_back({float(std::fmod(p[0] * 0.37, 1.0)), float(std::fmod(p[1] * 0.23, 1.0)),
                        float(std::fmod(p[2] * 0.11, 1.0)), 1.0f});
  return m;
}

/// The 12 triangles of the box [lo, hi].
void addBox(std::vector<std::array<double, 3>>& p, std::vector<std::array<uint32_t, 3>>& t, std::array<double, 3> lo,
            std::array<double, 3> hi) {
  const uint32_t b = uint32_t(p.size());
  for (int i = 0; i < 8; ++i) p.push_back({i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  for (const auto& tri : std::vector<std::array<uint32_t, 3>>{{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4},
                                                              {1, 5, 4}, {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6},
                                                              {1, 3, 5}, {3, 7, 5}})
    t.push_back({b + tri[0], b + tri[1], b + tri[2]});
}

Scene bake(const Mesh& m, const std::vector<uint8_t>& cls, const SceneHeader& h, unsigned threads) {
  VoxelizeSettings s;
  s.threads = threads;
  return voxelizeMesh(m, cls, h, s);
}

void expectSame(const Scene& a, const Scene& b, const std::string& what) {
  const SceneDifference d = compareScenes(a, b);
  EXPECT_TRUE(d.same()) << what << ": " << d.headerNote << " " << d.voxelsDiffering << " voxels differ, first "
                        << (d.firstDifference ? toString(*d.firstDifference) : "-") << ": " << d.firstNote;
}

/// Bakes `m` at threads 1, 2, 3, 4 and 7, expecting the same scene each time.
void expectSameAtAnyThreadCount(const Mesh& m, const std::vector<uint8_t>& cls, const SceneHeader& h,
                                const std::string& what) {
  const Scene one = bake(m, cls, h, 1);
  ASSERT_GT(one.occupiedCount(), 0u) << what;
  for (unsigned threads : {2u, 3u, 4u, 7u}) expectSame(one, bake(m, cls, h, threads), what + ", threads " + std::to_string(threads));
}

}  // namespace

TEST(SurfaceTiles, LargeColouredTrianglesAtAnyThreadCount) {
  // A 12-triangle box over most of an odd-sized domain: each face is two
  // triangles spanning every tile along its plane.
  std::vector<std::array<double, 3>> p;
  std::vector<std::array<uint32_t, 3>> t;
  addBox(p, t, {1.3, 0.7, 2.1}, {58.6, 44.2, 51.9});
  const Mesh m = colouredMesh(p, t);
  std::vector<uint8_t> cls(t.size(), 1);
  for (size_t i = 0; i < cls.size(); i += 3) cls[i] = 2;  // two classes, sharing voxels along edges
  expectSameAtAnyThreadCount(m, cls, voxtest::twoClassHeader({61, 47, 55}), "coloured box");
}

TEST(SurfaceTiles, TrianglesOnBlockBoundariesAtAnyThreadCount) {
  // Tiles end between 8^3 blocks; these triangles lie in the planes x = 16,
  // y = 24 and z = 8 (touching the voxels on both sides, in different blocks),
  // or have vertices on them, among large ones facing each axis.
  std::vector<std::array<double, 3>> p;
  std::vector<std::array<uint32_t, 3>> t;
  auto tri = [&](std::array<double, 3> a, std::array<double, 3> b, std::array<double, 3> c) {
    const uint32_t k = uint32_t(p.size());
    p.push_back(a), p.push_back(b), p.push_back(c);
    t.push_back({k, k + 1, k + 2});
  };
  tri({16, 1, 1}, {16, 40, 3}, {16, 5, 38});      // in the plane x = 16
  tri({2, 24, 2}, {39, 24, 6}, {9, 24, 37});      // in the plane y = 24
  tri({3, 3, 8}, {38, 9, 8}, {12, 37, 8});        // in the plane z = 8
  tri({8, 8, 8}, {32, 16, 24}, {16, 32, 40});     // vertices on block corners
  tri({7.5, 0.5, 20}, {40.5, 0.5, 20}, {7.5, 40.5, 21});  // spans every tile along x and y
  tri({15.999, 3, 3}, {16.001, 38, 5}, {16, 6, 37});      // a sliver straddling x = 16
  for (int i = 0; i < 40; ++i) {  // small ones around the block boundaries
    const double x = 8 * (1 + i % 4) + 0.25 * (i % 3) - 0.25, y = 8 * (1 + (i / 4) % 4) - 0.5 + 0.125 * (i % 5),
                 z = 4 + i * 0.8;
    tri({x, y, z}, {x + 1.5, y + 0.25, z + 0.5}, {x - 0.25, y + 1.75, z + 1.0});
  }
  const Mesh m = colouredMesh(p, t);
  std::vector<uint8_t> cls(t.size(), 1);
  for (size_t i = 0; i < cls.size(); i += 2) cls[i] = 2;
  expectSameAtAnyThreadCount(m, cls, voxtest::twoClassHeader({44, 42, 45}), "triangles on block boundaries");
  // Without colour (one tile on one thread, tiles on more).
  Mesh plain = m;
  plain.colors.clear();
  expectSameAtAnyThreadCount(plain, cls, voxtest::twoClassHeader({44, 42, 45}), "uncoloured, on block boundaries");
}

TEST(SurfaceTiles, TexturedTrianglesAtAnyThreadCount) {
  // Two large textured triangles (a 4x3 texture repeated, bilinear) facing y,
  // and a small one facing x, so the slabs along x differ in work.
  Mesh m = colouredMesh({{1.5, 10.25, 1.5}, {60.5, 10.25, 1.5}, {60.5, 12.75, 50.5}, {1.5, 11.5, 50.5},
                         {30.2, 2.0, 2.0}, {30.2, 30.0, 4.0}, {30.2, 6.0, 40.0}},
                        {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}});
  m.colors.clear();
  MeshTexture tex;
  tex.width = 4, tex.height = 3;
  for (uint32_t i = 0; i < tex.width * tex.height; ++i)
    tex.rgba.insert(tex.rgba.end(), {uint8_t(40 * i), uint8_t(255 - 20 * i), uint8_t(97 * i), 255});
  m.textures.push_back(tex);
  m.materials[0].texture = 0;
  m.uv0 = {{0, 0}, {3.5, 0}, {3.5, 2.5}, {0, 2.5}, {0.1, 0.1}, {0.9, 0.2}, {0.4, 0.8}};
  expectSameAtAnyThreadCount(m, std::vector<uint8_t>(m.triangles.size(), 1), voxtest::twoClassHeader({62, 40, 52}), "textured");
}

TEST(SurfaceTiles, WallInOneBlockColumnKeepsItsArea) {
  // A wall in the plane x = 20.5 from y, z = 0.5 to 40.5: all its voxels lie
  // in one block column, so with several threads that slab is cut along y.
  // Each voxel's votes are its area exactly (a voxel counted by two tiles
  // would show twice the votes): 65536 inside, half on the sides, a quarter
  // at the corners, plus the one vote of a triangle touching only a corner.
  const Mesh m = colouredMesh({{20.5, 0.5, 0.5}, {20.5, 40.5, 0.5}, {20.5, 40.5, 40.5}, {20.5, 0.5, 40.5}},
                              {{0, 1, 2}, {0, 2, 3}});
  const std::vector<uint8_t> cls(2, 1);
  const SceneHeader h = voxtest::twoClassHeader({64, 48, 48});
  for (unsigned threads : {1u, 2u, 3u}) {
    const Scene s = bake(m, cls, h, threads);
    EXPECT_EQ(s.occupiedCount(), 41u * 41u) << "threads " << threads;
    std::vector<ClassVotes> storage;
    for (int v = 0; v <= 40; ++v)
      for (int w = 0; w <= 40; ++w) {
        const std::optional<VoxelView> voxel = s.voxel({20, v, w}, storage);
        ASSERT_TRUE(voxel.has_value()) << v << " " << w;
        const int edges = (v == 0 || v == 40) + (w == 0 || w == 40);
        // The voxels beside the diagonal the two triangles share touch the
        // other triangle at a corner: one vote more from it.
        const uint32_t expected = (edges == 0 ? 65536u : edges == 1 ? 32768u : 16384u) + (std::abs(v - w) == 1 ? 1u : 0u);
        ASSERT_EQ(voxel->votes.size(), 1u);
        EXPECT_EQ(voxel->votes[0].votes, expected) << "threads " << threads << " at (20, " << v << ", " << w << ")";
      }
  }
}
