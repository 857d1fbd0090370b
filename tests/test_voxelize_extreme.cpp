// Extreme but valid inputs: each has a stated expectation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "formats/mesh/mesh_input.h"
#include "libvox/core/memory_budget.h"
#include "libvox/mesh/placement.h"
#include "libvox/scene/voxelize_scene.h"
#include "libvox/scene/voxelize_check.h"
#include "test_util.h"

using namespace vox;

namespace {
SceneHeader header(uint32_t n, double vs = 1.0) {
  SceneHeader h;
  h.dims = {n, n, n};
  h.voxelSize = vs;
  h.classes.add({1, "a", {255, 0, 0}, std::nullopt});
  return h;
}
Mesh meshOf(std::vector<std::array<double, 3>> p, std::vector<std::array<uint32_t, 3>> t) {
  Mesh m;
  m.positions = std::move(p);
  m.triangles = std::move(t);
  m.triangleMaterial.assign(m.triangles.size(), 0);
  m.trianglePart.assign(m.triangles.size(), 0);
  m.materials.push_back({});
  m.parts.push_back({"p", "m"});
  return m;
}
Scene run(const Mesh& m, const SceneHeader& h, FillMode f = FillMode::Surface, unsigned threads = 2) {
  VoxelizeSettings s;
  s.fill = f;
  s.threads = threads;
  return voxelizeMesh(m, std::vector<uint8_t>(m.triangles.size(), 1), h, s);
}
}  // namespace

TEST(VoxelizeExtreme, OneHugeTriangleAtResolution4096) {
  // Covers half of the z = 0.5 plane of a 4096^2 x 1 grid: exactly the voxels
  // (u, v, 0) with u + v <= 4095 plus the diagonal's neighbours it touches.
  SceneHeader h = header(4096);
  h.dims.z = 1;
  const Mesh m = meshOf({{0, 0, 0.5}, {4096, 0, 0.5}, {0, 4096, 0.5}}, {{0, 1, 2}});
  const Scene s = run(m, h);
  // Voxel (u, v) touches the closed triangle x + y <= 4096 iff u + v <= 4096 - 0 (its min corner).
  uint64_t want = 0;
  for (uint64_t u = 0; u < 4096; ++u) want += std::min<uint64_t>(4096, 4096 - u + 1);
  EXPECT_EQ(s.occupiedCount(), want);
}

TEST(VoxelizeExtreme, ResolutionOneIsOneVoxel) {
  SceneHeader h;
  PlacementOptions o;
  o.resolution = 1;
  placeGrid({0, 0, 0}, {3, 2, 1}, o, h);
  h.classes.add({1, "a", {1, 2, 3}, std::nullopt});
  const Mesh m = meshOf({{0, 0, 0}, {3, 0, 0}, {0, 2, 1}}, {{0, 1, 2}});
  EXPECT_EQ(run(m, h, FillMode::Solid).occupiedCount(), 1u);
}

TEST(VoxelizeExtreme, AMillionTinyTriangles) {
  // 1M triangles of 1e-3 voxel inside a 64^3 grid: every one lands in the voxel
  // holding it; the result equals the brute-force oracle.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(0.01, 63.99);
  std::vector<std::array<double, 3>> p;
  std::vector<std::array<uint32_t, 3>> t;
  for (uint32_t i = 0; i < 1000000; ++i) {
    const double x = pos(rng), y = pos(rng), z = pos(rng);
    p.push_back({x, y, z}), p.push_back({x + 1e-3, y, z}), p.push_back({x, y + 1e-3, z});
    t.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  const Mesh m = meshOf(std::move(p), std::move(t));
  const Scene s = run(m, header(64));
  const SurfaceCheck c = checkSurface(m, s, 1u << 30);
  EXPECT_EQ(c.missed, 0u);
  EXPECT_EQ(*c.extra, 0u);
  EXPECT_GT(s.occupiedCount(), 200000u);
}

TEST(VoxelizeExtreme, SliversNonManifoldAndSelfIntersecting) {
  // A sliver (1e-9 wide), three triangles sharing one edge (non-manifold), and
  // two boxes interpenetrating: surface matches the oracle; solid fills both boxes.
  Mesh m = meshOf({{1, 1, 1}, {9, 1, 1}, {5, 1 + 1e-9, 1},                     // sliver
                   {2, 2, 2}, {8, 2, 2}, {5, 6, 2}, {5, 2, 6}, {5, 2, -0.0}},  // fan on edge (2,2,2)-(8,2,2)
                  {{0, 1, 2}, {3, 4, 5}, {3, 4, 6}, {3, 4, 7}});
  const Scene s = run(m, header(12));
  const SurfaceCheck c = checkSurface(m, s, 1u << 30);
  EXPECT_EQ(c.missed, 0u);
  EXPECT_EQ(*c.extra, 0u);
  // Self-intersecting: two overlapping boxes as one mesh.
  auto box = [](std::array<double, 3> lo, std::array<double, 3> hi) {
    std::vector<std::array<double, 3>> p;
    for (int i = 0; i < 8; ++i) p.push_back({i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
    return meshOf(p, {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                      {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}});
  };
  Mesh both = box({1.5, 1.5, 1.5}, {7.5, 7.5, 7.5});
  both.append(box({4.5, 4.5, 4.5}, {10.5, 10.5, 10.5}));
  const Scene solid = run(both, header(12), FillMode::Solid);
  std::vector<ClassVotes> tmp;
  EXPECT_TRUE(solid.voxel({5, 5, 5}, tmp)) << "inside both (winding 2)";
  EXPECT_TRUE(solid.voxel({3, 3, 3}, tmp));
  EXPECT_TRUE(solid.voxel({9, 9, 9}, tmp));
  EXPECT_FALSE(solid.voxel({9, 2, 2}, tmp));
}

TEST(VoxelizeExtreme, SolidFillOfAHugeBoxIsRefusedBeforeAnyWork) {
  // A thin diagonal sliver across a 4096^3 grid: its bounding box is 2^36
  // voxels, whose inside flags alone take 8 GiB. Refused up front by the
  // memory guard (here with a 4 GiB limit, as the CLI sets one), naming the
  // fix (fewer voxels), not run.
  const Mesh sliver = meshOf({{0, 0, 0}, {4096, 4096, 4096}, {4096, 4096, 4095}}, {{0, 1, 2}});
  const MemoryLimit before = processMemoryLimit();
  setProcessMemoryLimit({uint64_t(4) << 30, "4.00 GiB (test)"}, "--max-memory");
  EXPECT_TRUE(voxtest::throwsVoxError([&] { run(sliver, header(4096), FillMode::Solid); }, ErrorKind::Resource,
                                      {"68719476736-voxel box", "GiB", "fill only the surface", "4.00 GiB (test)"}));
  setProcessMemoryLimit(before, "--max-memory");
}

// A vertex beyond a solid fill's reach (2^20 voxels from the grid; a surface
// fill clips its triangles, test_voxelize_far.cpp) is named as its file
// numbers it, with the file: OBJ by its "v" number (a "v" used with two "vt" is two mesh vertices,
// made in the order faces use them), PLY from 0 as its faces count, and the
// second of two inputs by its own file.
TEST(VoxelizeExtreme, FarVertexIsNamedAsItsFileNumbersIt) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("far.obj"), "v 40000000 0 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 1\n"
                                          "f 2/1 3/1 4/1\nf 2/2 3/2 1/2\n");
  voxtest::writeText(dir.file("far.ply"), "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                          "end_header\n0 0 0\n1 0 0\n0 1 0\n0 -40000000 0\n3 0 1 3\n");
  voxtest::writeText(dir.file("near.stl"), "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                           "vertex 0 1 0\nendloop\nendfacet\nendsolid a\n");
  std::vector<std::string> warnings;
  auto fails = [&](const Mesh& m, std::initializer_list<std::string> says) {
    return voxtest::throwsVoxError([&] { run(m, header(4), FillMode::Solid); }, ErrorKind::BadInput, says);
  };
  const Mesh obj = readMeshFile(dir.file("far.obj"), {}, warnings);
  ASSERT_EQ(obj.positions.size(), 6u) << "one mesh vertex per (v, vt) pair";
  EXPECT_TRUE(fails(obj, {"far.obj: vertex 1 (as its 'f' lines number them) lies 40000000 voxels from the grid along x",
                          "beyond the 2^20 a solid fill reaches", "at least 39 times larger"}));
  EXPECT_TRUE(fails(readMeshFile(dir.file("far.ply"), {}, warnings), {"far.ply: vertex 3 (counted from 0", "along y"}));
  Mesh both = readMeshFile(dir.file("near.stl"), {}, warnings);
  both.append(readMeshFile(dir.file("far.ply"), {}, warnings));
  EXPECT_TRUE(fails(both, {"far.ply: vertex 3 (counted from 0"})) << "the second input's vertices keep their file";
  EXPECT_EQ(both.describeVertex(2), dir.file("near.stl") + ": vertex 3 (counted from 1 over its facets, 3 a facet)");
  Mesh made = meshOf({{0, 0, 0}, {1, 0, 0}, {0, 9e6, 0}}, {{0, 1, 2}});
  EXPECT_TRUE(fails(made, {"vertex 3 (counted from 1) lies 9000000 voxels"})) << "a mesh made in memory";
}
