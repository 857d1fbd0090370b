// Block meshes (libvox/core/block_mesh.h) on hand-made volumes: the culled
// mesh's exact quads and vertices against the block renderer's definitions,
// its order, culling at brick and box borders, colours, determinism across
// thread counts, and the merged mesh's surface against the culled one.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>
#include <tuple>

#include "libvox/core/block_mesh.h"
#include "libvox/core/color.h"
#include "libvox/scene/class_volume_scene.h"
#include "libvox/scene/demo_hamlet.h"
#include "libvox/core/summary_bytes.h"
#include "test_util.h"

namespace {

using vox::BlockFace;
using vox::BlockQuad;
using vox::ClassVolume;
using vox::Coord3;

struct Block {
  Block(Coord3 a, uint8_t c = 1, std::optional<vox::RgbLinear> rgb = std::nullopt) : at(a), cls(c), color(rgb) {}
  Coord3 at;
  uint8_t cls;
  std::optional<vox::RgbLinear> color;
};

ClassVolume volumeOf(const std::vector<Block>& blocks, vox::IndexBox box, bool withColor = false) {
  ClassVolume vol(box, withColor);
  std::map<std::tuple<int, int, int>, ClassVolume::Brick> bricks;
  for (const Block& b : blocks) {
    const Coord3 o{b.at.u & ~7, b.at.v & ~7, b.at.w & ~7};
    auto it = bricks.find({o.u, o.v, o.w});
    if (it == bricks.end()) it = bricks.emplace(std::tuple(o.u, o.v, o.w), vol.makeBrick(o)).first;
    const int i = ClassVolume::voxelIndex(b.at.u - o.u, b.at.v - o.v, b.at.w - o.w);
    it->second.classes[size_t(i)] = b.cls;
    if (b.color && withColor) it->second.setColor(i, *b.color);
  }
  for (auto& [k, b] : bricks) vol.add(std::move(b));
  vol.finish();
  return vol;
}

vox::IndexBox box(int n) { return {{0, 0, 0}, {n - 1, n - 1, n - 1}}; }

// A class with a face palette (Grass's top/bottom/side) and one without.
vox::ClassTable twoClasses() {
  vox::ClassTable t;
  t.add({1, "Grass", {87, 173, 92}, vox::FacePalette{{87, 173, 92}, {102, 77, 41}, {115, 148, 77}}});
  t.add({2, "Rock", {10, 20, 30}, std::nullopt});
  return t;
}

vox::RgbLinear linear(vox::Rgb8 c) { return {vox::srgb8ToLinear(c.r), vox::srgb8ToLinear(c.g), vox::srgb8ToLinear(c.b)}; }

// The renderer's loop, written out directly: every voxel in (v, w, u) order,
// faces in BlockFace order, kept when the neighbour is empty.
std::vector<std::pair<Coord3, BlockFace>> referenceFaces(const ClassVolume& vol) {
  std::vector<std::pair<Coord3, BlockFace>> out;
  const vox::IndexBox& b = vol.box();
  for (int v = b.min.v; v <= b.max.v; ++v)
    for (int w = b.min.w; w <= b.max.w; ++w)
      for (int u = b.min.u; u <= b.max.u; ++u) {
        if (!vol.classAt({u, v, w})) continue;
        for (int f = 0; f < 6; ++f) {
          const auto& n = vox::kBlockFaces[size_t(f)].normal;
          if (!vol.classAt({u + n[0], v + n[1], w + n[2]})) out.push_back({{u, v, w}, BlockFace(f)});
        }
      }
  return out;
}

TEST(BlockMesh, OneBlockHasSixFacesWithTheRenderersCornersUvsAndColours) {
  const ClassVolume vol = volumeOf({{{2, 3, 4}, 1}}, box(8));
  const vox::BlockMesh mesh = vox::meshVisibleFaces(vol, twoClasses(), {});
  ASSERT_EQ(mesh.quads.size(), 6u);
  EXPECT_EQ(mesh.unitFaces, 6u);
  EXPECT_EQ(mesh.triangles(), 12u);
  const vox::GridFrame frame{{-64.0, 0.0, -64.0}, 2.0};
  // The block renderer's face table, written out (corners, uvs), east, west, top, bottom, south, north.
  const int corners[6][4][3] = {{{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},
                                {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},
                                {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}};
  const int uvs[6][4][2] = {{{0, 1}, {0, 0}, {1, 0}, {1, 1}}, {{1, 1}, {0, 1}, {0, 0}, {1, 0}},
                            {{0, 1}, {0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}},
                            {{0, 1}, {1, 1}, {1, 0}, {0, 0}}, {{1, 1}, {1, 0}, {0, 0}, {0, 1}}};
  const int normals[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const vox::RgbLinear top = linear({87, 173, 92}), bottom = linear({102, 77, 41}), side = linear({115, 148, 77});
  const vox::RgbLinear colors[6] = {side, side, top, bottom, side, side};
  for (int f = 0; f < 6; ++f) {
    const BlockQuad& q = mesh.quads[size_t(f)];
    EXPECT_EQ(q.face, BlockFace(f));
    EXPECT_EQ(q.block, (Coord3{2, 3, 4}));
    EXPECT_EQ(q.color, colors[f]) << "face " << f;
    const auto verts = vox::quadVertices(q, frame);
    for (int c = 0; c < 4; ++c) {
      const vox::BlockVertex& v = verts[size_t(c)];
      // (index + corner) * voxel size + origin
      EXPECT_EQ(v.position[0], float((2 + corners[f][c][0]) * 2.0 - 64.0)) << f << " " << c;
      EXPECT_EQ(v.position[1], float((3 + corners[f][c][1]) * 2.0)) << f << " " << c;
      EXPECT_EQ(v.position[2], float((4 + corners[f][c][2]) * 2.0 - 64.0)) << f << " " << c;
      EXPECT_EQ(v.uv[0], float(uvs[f][c][0]));
      EXPECT_EQ(v.uv[1], float(uvs[f][c][1]));
      for (int a = 0; a < 3; ++a) EXPECT_EQ(v.normal[size_t(a)], float(normals[f][a]));
      EXPECT_EQ(v.color[0], colors[f].r);
    }
  }
}

TEST(BlockMesh, TrianglesTurnCounterClockwiseSeenFromOutside) {
  for (int f = 0; f < 6; ++f) {
    BlockQuad q;
    q.face = BlockFace(f);
    const auto v = vox::quadVertices(q, {});
    for (int t = 0; t < 2; ++t) {
      const auto& a = v[vox::kQuadTriangles[size_t(3 * t)]].position;
      const auto& b = v[vox::kQuadTriangles[size_t(3 * t + 1)]].position;
      const auto& c = v[vox::kQuadTriangles[size_t(3 * t + 2)]].position;
      const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const float cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      const auto& n = vox::kBlockFaces[size_t(f)].normal;
      EXPECT_GT(cross[0] * n[0] + cross[1] * n[1] + cross[2] * n[2], 0.f) << "face " << f << " triangle " << t;
    }
  }
}

TEST(BlockMesh, FacesBetweenTwoBlocksAreCulled) {
  const ClassVolume vol = volumeOf({{{0, 0, 0}, 1}, {{1, 0, 0}, 2}}, box(8));
  const vox::BlockMesh mesh = vox::meshVisibleFaces(vol, twoClasses(), {});
  std::vector<std::pair<int, BlockFace>> got;
  for (const BlockQuad& q : mesh.quads) got.push_back({q.block.u, q.face});
  const std::vector<std::pair<int, BlockFace>> want = {
      {0, BlockFace::NegX}, {0, BlockFace::PosY}, {0, BlockFace::NegY}, {0, BlockFace::PosZ}, {0, BlockFace::NegZ},
      {1, BlockFace::PosX}, {1, BlockFace::PosY}, {1, BlockFace::NegY}, {1, BlockFace::PosZ}, {1, BlockFace::NegZ}};
  EXPECT_EQ(got, want);
  // Class 2 has no face palette: its display colour on every face.
  EXPECT_EQ(mesh.quads.back().color, linear({10, 20, 30}));
}

TEST(BlockMesh, AnEmptyVolumeHasNoFaces) {
  // No bricks, so no rows to split: the counting pass still runs one piece,
  // whose offset must exist (it was written one past the array; ASan).
  for (unsigned threads : {1u, 2u}) {
    vox::BlockMeshSettings settings;
    settings.threads = threads;
    const vox::BlockMesh mesh = vox::meshVisibleFaces(volumeOf({}, box(8)), twoClasses(), settings);
    EXPECT_TRUE(mesh.quads.empty());
    EXPECT_EQ(mesh.unitFaces, 0u);
    EXPECT_TRUE(vox::mergeCoplanarFaces(mesh, threads).quads.empty());
  }
}

TEST(BlockMesh, OrderIsTheRenderersLoopAcrossBricks) {
  // y (v) outermost, then z (w), then x (u): (9,0,0) before (0,0,9) before (0,1,0).
  const ClassVolume vol = volumeOf({{{0, 1, 0}}, {{0, 0, 9}}, {{9, 0, 0}}}, box(16));
  const vox::BlockMesh mesh = vox::meshVisibleFaces(vol, twoClasses(), {});
  ASSERT_EQ(mesh.quads.size(), 18u);
  EXPECT_EQ(mesh.quads[0].block, (Coord3{9, 0, 0}));
  EXPECT_EQ(mesh.quads[6].block, (Coord3{0, 0, 9}));
  EXPECT_EQ(mesh.quads[12].block, (Coord3{0, 1, 0}));
}

TEST(BlockMesh, NeighboursInOtherBricksCullAndTheBoxEdgeDoesNot) {
  // (7,0,0) and (8,0,0) sit in two bricks; (7,0,0)-(7,0,1) is cut by the box.
  const ClassVolume all = volumeOf({{{7, 0, 0}}, {{8, 0, 0}}, {{7, 0, 1}}}, box(16));
  EXPECT_EQ(vox::meshVisibleFaces(all, twoClasses(), {}).quads.size(), 14u);
  const ClassVolume cut = volumeOf({{{7, 0, 0}}, {{8, 0, 0}}, {{7, 0, 1}}}, {{0, 0, 0}, {15, 15, 0}});
  EXPECT_EQ(cut.occupiedCount(), 2u);
  const vox::BlockMesh mesh = vox::meshVisibleFaces(cut, twoClasses(), {});
  EXPECT_EQ(mesh.quads.size(), 10u);  // the +z face of (7,0,0) is back: outside the box is empty
  EXPECT_EQ(mesh.quads[3].face, BlockFace::PosZ);  // -x, +y, -y, +z, -z of (7,0,0)
}

TEST(BlockMesh, VoxelColoursAndTheirFallback) {
  const vox::RgbLinear red{1.f, 0.f, 0.f};
  const ClassVolume vol = volumeOf({{{0, 0, 0}, 1, red}, {{3, 0, 0}, 2, std::nullopt}}, box(8), true);
  vox::BlockMeshSettings s;
  s.color = vox::FaceColor::Voxel;
  const vox::BlockMesh mesh = vox::meshVisibleFaces(vol, twoClasses(), s);
  ASSERT_EQ(mesh.quads.size(), 12u);
  EXPECT_EQ(mesh.quads[0].color, red);
  EXPECT_EQ(mesh.quads[6].color, linear({10, 20, 30}));
  EXPECT_EQ(mesh.uncoloredFaces, 6u);
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::meshVisibleFaces(volumeOf({{{0, 0, 0}}}, box(8)), twoClasses(), s); },
                                      vox::ErrorKind::Usage, {"colours"}));
}

TEST(BlockMesh, AClassMissingFromTheTableIsBadInput) {
  const ClassVolume vol = volumeOf({{{1, 2, 3}, 9}}, box(8));
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::meshVisibleFaces(vol, twoClasses(), {}); }, vox::ErrorKind::BadInput,
                                      {"class 9", "(1, 2, 3)", "class table"}));
}

std::vector<Block> randomBlocks(uint32_t seed, int n, int count, int classes, bool colors) {
  std::mt19937 rng(seed);
  std::vector<Block> blocks;
  std::set<std::tuple<int, int, int>> used;
  while (int(blocks.size()) < count) {
    const Coord3 c{int(rng() % n), int(rng() % n), int(rng() % n)};
    if (!used.insert({c.u, c.v, c.w}).second) continue;
    Block b{c, uint8_t(1 + rng() % classes)};
    if (colors && rng() % 4) b.color = vox::RgbLinear{float(rng() % 2), 0.5f, 0.25f};
    blocks.push_back(b);
  }
  return blocks;
}

TEST(BlockMesh, MatchesTheRenderersLoopAtAnyThreadCount) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const ClassVolume vol = volumeOf(randomBlocks(seed, 40, 9000, 2, false), box(40));
    const auto want = referenceFaces(vol);
    vox::BlockMeshSettings s;
    s.threads = 1;
    const vox::BlockMesh one = vox::meshVisibleFaces(vol, twoClasses(), s);
    s.threads = 2;
    const vox::BlockMesh two = vox::meshVisibleFaces(vol, twoClasses(), s);
    EXPECT_EQ(one.quads, two.quads);
    ASSERT_EQ(one.quads.size(), want.size());
    for (size_t i = 0; i < want.size(); ++i) {
      ASSERT_EQ(one.quads[i].block, want[i].first) << i;
      ASSERT_EQ(one.quads[i].face, want[i].second) << i;
    }
  }
}

// The unit faces a mesh covers: (face, cell) -> (class, colour); fails on overlap.
using Surface = std::map<std::tuple<int, int, int, int>, std::tuple<int, float, float, float>>;
Surface rasterize(const vox::BlockMesh& mesh) {
  Surface s;
  for (const BlockQuad& q : mesh.quads) {
    const auto [a, b] = vox::inPlaneAxes(q.face);
    for (uint32_t i = 0; i < q.extent[0]; ++i)
      for (uint32_t j = 0; j < q.extent[1]; ++j) {
        int c[3] = {q.block.u, q.block.v, q.block.w};
        c[a] += int(i);
        c[b] += int(j);
        const bool fresh =
            s.emplace(std::tuple(int(q.face), c[0], c[1], c[2]), std::tuple(int(q.classId), q.color.r, q.color.g, q.color.b))
                .second;
        EXPECT_TRUE(fresh) << "two quads cover one face";
      }
  }
  return s;
}

TEST(GreedyMesh, CoversExactlyTheCulledSurfaceWithFewerQuads) {
  for (uint32_t seed : {4u, 5u}) {
    for (bool colors : {false, true}) {
      const ClassVolume vol = volumeOf(randomBlocks(seed, 24, 9000, 2, colors), box(24), colors);
      vox::BlockMeshSettings s;
      s.color = colors ? vox::FaceColor::Voxel : vox::FaceColor::Palette;
      const vox::BlockMesh culled = vox::meshVisibleFaces(vol, twoClasses(), s);
      const vox::BlockMesh merged1 = vox::mergeCoplanarFaces(culled, 1);
      const vox::BlockMesh merged2 = vox::mergeCoplanarFaces(culled, 2);
      EXPECT_EQ(merged1.quads, merged2.quads);
      EXPECT_EQ(rasterize(merged1), rasterize(culled));
      EXPECT_LT(merged1.quads.size(), culled.quads.size());
      EXPECT_EQ(merged1.unitFaces, culled.unitFaces);
    }
  }
}

TEST(GreedyMesh, ASlabIsSixRectangles) {
  std::vector<Block> slab;
  for (int u = 0; u < 5; ++u)
    for (int w = 0; w < 3; ++w) slab.push_back({{u, 2, w}, 1});
  const vox::BlockMesh culled = vox::meshVisibleFaces(volumeOf(slab, box(8)), twoClasses(), {});
  EXPECT_EQ(culled.quads.size(), 2u * 15 + 2 * 5 + 2 * 3);
  const vox::BlockMesh merged = vox::mergeCoplanarFaces(culled);
  ASSERT_EQ(merged.quads.size(), 6u);
  const BlockQuad& top = merged.quads[2];  // faces in BlockFace order: the top is third
  EXPECT_EQ(top.face, BlockFace::PosY);
  EXPECT_EQ(top.block, (Coord3{0, 2, 0}));
  EXPECT_EQ(top.extent, (std::array<uint32_t, 2>{5, 3}));
  // Corners span the rectangle; texture coordinates count blocks (one tile per block).
  const auto v = vox::quadVertices(top, {});
  EXPECT_EQ(v[0].position, (std::array<float, 3>{0, 3, 0}));
  EXPECT_EQ(v[2].position, (std::array<float, 3>{5, 3, 3}));
  EXPECT_EQ(v[0].uv, (std::array<float, 2>{0, 3}));
  EXPECT_EQ(v[2].uv, (std::array<float, 2>{5, 0}));
}

TEST(BlockMesh, NoTwoQuadsShareAVertex) {
  // Why --dedup keeps four vertices per quad: across quads, a shared corner
  // always has different texture coordinates (or normal, or colour).
  const ClassVolume vol = volumeOf(randomBlocks(6, 12, 800, 1, false), box(12));
  for (bool greedy : {false, true}) {
    vox::BlockMesh mesh = vox::meshVisibleFaces(vol, twoClasses(), {});
    if (greedy) mesh = vox::mergeCoplanarFaces(mesh);
    std::map<std::vector<float>, size_t> seen;
    for (size_t q = 0; q < mesh.quads.size(); ++q)
      for (const vox::BlockVertex& v : vox::quadVertices(mesh.quads[q], {})) {
        std::vector<float> key(v.position.begin(), v.position.end());
        key.insert(key.end(), v.normal.begin(), v.normal.end());
        key.insert(key.end(), v.color.begin(), v.color.end());
        key.insert(key.end(), v.uv.begin(), v.uv.end());
        const auto [it, fresh] = seen.emplace(key, q);
        EXPECT_TRUE(fresh || it->second == q) << "quads " << it->second << " and " << q << " share a vertex";
      }
  }
}

TEST(ClassVolume, SceneVoxelsTakeTheSummarysWinningClass) {
  vox::HamletOptions ho;
  ho.resolution = 32;
  const vox::Scene scene = vox::buildHamlet(ho);
  const vox::ClassVolume vol = vox::classVolumeFromScene(scene, vox::domainBox(scene.header().dims), true, 2);
  EXPECT_EQ(vol.occupiedCount(), scene.occupiedCount());
  uint64_t checked = 0;
  scene.forEachVoxel([&](const vox::VoxelView& v) {
    ASSERT_EQ(vol.classAt(v.at), vox::summarize(v.votes).cls) << vox::toString(v.at);
    ++checked;
  });
  EXPECT_EQ(checked, scene.occupiedCount());
  // A region keeps its voxels only.
  const vox::IndexBox part{{4, 0, 4}, {11, 5, 20}};
  const vox::ClassVolume cut = vox::classVolumeFromScene(scene, part, false, 1);
  uint64_t inside = 0;
  scene.forEachVoxel([&](const vox::VoxelView& v) {
    const bool in = v.at.u >= 4 && v.at.u <= 11 && v.at.v <= 5 && v.at.w >= 4 && v.at.w <= 20;
    inside += in;
    EXPECT_EQ(cut.classAt(v.at) != 0, in);
  });
  EXPECT_EQ(cut.occupiedCount(), inside);
}

}  // namespace
