// The memory guard's pieces: sizes as users write them, the limit, the
// refusal, and the mesh footprint against the blocks a real bake creates.
#include <gtest/gtest.h>

#include <cmath>

#include "libvox/core/error.h"
#include "libvox/core/memory_budget.h"
#include "libvox/core/regions.h"
#include "libvox/mesh/voxelize.h"
#include "libvox/mesh/voxelize_memory.h"

namespace vox {
namespace {

TEST(MemoryBudget, ParsesSizes) {
  EXPECT_EQ(parseByteSize("0", "--max-memory"), 0u);
  EXPECT_EQ(parseByteSize("123456", "--max-memory"), 123456u);
  EXPECT_EQ(parseByteSize("64k", "--max-memory"), 64u << 10);
  EXPECT_EQ(parseByteSize("500M", "--max-memory"), 500ull << 20);
  EXPECT_EQ(parseByteSize("12G", "--max-memory"), 12ull << 30);
  EXPECT_EQ(parseByteSize("12GB", "--max-memory"), 12ull << 30);
  EXPECT_EQ(parseByteSize("1.5GiB", "--max-memory"), 3ull << 29);
  EXPECT_EQ(parseByteSize("2t", "--max-memory"), 2ull << 40);
  for (const char* bad : {"", "G", "12X", "-1", "1.2.3", "12 G", "nan", "1e3", "99999999999T"}) {
    try {
      parseByteSize(bad, "--max-memory");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind, ErrorKind::Usage) << bad;
      EXPECT_NE(std::string(e.what()).find("--max-memory"), std::string::npos) << e.what();
    }
  }
}

TEST(MemoryBudget, FormatsBytes) {
  EXPECT_EQ(formatBytes(12), "12 bytes");
  EXPECT_EQ(formatBytes(1536), "1.50 KiB");
  EXPECT_EQ(formatBytes(uint64_t(7.9 * (1ull << 30))), "7.90 GiB");
  EXPECT_EQ(formatBytes(uint64_t(31.2 * (1ull << 30))), "31.2 GiB");
  EXPECT_EQ(formatBytes(500ull << 20), "500 MiB");
}

TEST(MemoryBudget, LimitsFromOptions) {
  EXPECT_TRUE(memoryLimitFrom("0", "--max-memory").unlimited());
  EXPECT_EQ(memoryLimitFrom("2G", "--max-memory").bytes, 2ull << 30);
  const PhysicalMemory m = physicalMemory();
  ASSERT_GT(m.bytes, 0u) << "no MemTotal in /proc/meminfo";
  const MemoryLimit d = memoryLimitFrom("", "--max-memory");
  EXPECT_NEAR(double(d.bytes), double(m.bytes) * kDefaultMemoryFraction, 1.0);
  EXPECT_NE(d.description.find("80% of"), std::string::npos) << d.description;
}

TEST(MemoryBudget, RefusesOverTheLimitWithTheEstimateAndASuggestion) {
  MemoryEstimate e;
  e.add("vote blocks", uint64_t(6) << 30);
  e.add("bits", uint64_t(2) << 30);
  e.add("tiny", uint64_t(1));
  EXPECT_EQ(e.bytes(), (uint64_t(8) << 30) + 1);
  EXPECT_NO_THROW(checkMemory(e, {uint64_t(9) << 30, "9 GiB"}, "a bake", "", "--max-memory"));
  EXPECT_NO_THROW(checkMemory(e, {0, "none"}, "a bake", "", "--max-memory"));
  try {
    checkMemory(e, {uint64_t(4) << 30, "4.00 GiB (--max-memory)"}, "a bake", "--res 512 would need about 1 GiB",
                "--max-memory");
    FAIL() << "not refused";
  } catch (const Error& err) {
    EXPECT_EQ(err.kind, ErrorKind::Resource);
    const std::string m = err.what();
    EXPECT_NE(m.find("a bake needs about 8.00 GiB (vote blocks 6.00 GiB, bits 2.00 GiB)"), std::string::npos) << m;
    EXPECT_NE(m.find("but the memory limit is 4.00 GiB (--max-memory)"), std::string::npos) << m;
    EXPECT_NE(m.find("--res 512 would need about 1 GiB"), std::string::npos) << m;
    EXPECT_EQ(m.find("tiny"), std::string::npos) << m;  // parts under 1% left out
  }
}

TEST(MemoryBudget, LargestFitting) {
  auto cube = [](uint64_t n) { return n * n * n; };
  EXPECT_EQ(largestFitting(1, 4096, 1000, cube), 10u);
  EXPECT_EQ(largestFitting(1, 4096, 999, cube), 9u);
  EXPECT_EQ(largestFitting(1, 4096, uint64_t(1) << 62, cube), 4096u);
  EXPECT_EQ(largestFitting(2, 4096, 7, cube), 0u);
}

TEST(MemoryBudget, ResidentNow) { EXPECT_GT(residentBytesNow(), 1u << 20); }

// ---------------------------------------------------------------- mesh footprint

Mesh cubeMesh(double lo, double hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.positions.push_back({i & 1 ? hi : lo, i & 2 ? hi : lo, i & 4 ? hi : lo});
  const uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& t : f) m.triangles.push_back({t[0], t[1], t[2]});
  m.triangleMaterial.assign(12, 0);
  m.trianglePart.assign(12, 0);
  m.materials.push_back({});
  m.parts.push_back({});
  return m;
}

/// A UV sphere: many small triangles in every orientation.
Mesh sphereMesh(double radius, int rings, int segments) {
  Mesh m;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double th = M_PI * r / rings, ph = 2 * M_PI * s / segments;
      m.positions.push_back({radius * std::sin(th) * std::cos(ph), radius * std::sin(th) * std::sin(ph), radius * std::cos(th)});
    }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = uint32_t(r * segments + s), b = uint32_t(r * segments + (s + 1) % segments);
      const uint32_t c = a + uint32_t(segments), d = b + uint32_t(segments);
      m.triangles.push_back({a, c, b});
      m.triangles.push_back({b, c, d});
    }
  m.triangleMaterial.assign(m.triangles.size(), 0);
  m.trianglePart.assign(m.triangles.size(), 0);
  m.materials.push_back({});
  m.parts.push_back({});
  return m;
}

SceneHeader placed(double lo, double hi, uint32_t res) {
  SceneHeader h;
  h.voxelSize = (hi - lo) / res;
  h.origin = {lo, lo, lo};
  h.dims = {res, res, res};
  return h;
}

/// The footprint's block count against the blocks a real bake creates.
void expectBlocksNear(const Mesh& mesh, const SceneHeader& h, double tolerance, const char* what) {
  const std::vector<uint8_t> cls(mesh.triangles.size(), 0);
  const SurfaceFootprint f = surfaceFootprint(mesh, cls, h);
  VoxelizeSettings s;
  s.threads = 2;
  const double real = double(voxelizeMeshBlocks(mesh, cls, h, s).blockCount());
  EXPECT_GT(f.blocks, real / tolerance) << what << ": estimated " << f.blocks << " blocks, real " << real;
  EXPECT_LT(f.blocks, real * tolerance) << what << ": estimated " << f.blocks << " blocks, real " << real;
  // Coarser cells (a tight piece budget) stay within 2x too.
  const SurfaceFootprint coarse = surfaceFootprint(mesh, cls, h, 2000);
  EXPECT_GT(coarse.blocks, real / 2) << what << " (coarse): " << coarse.blocks << " vs " << real;
  EXPECT_LT(coarse.blocks, real * 2) << what << " (coarse): " << coarse.blocks << " vs " << real;
}

TEST(MeshFootprint, CubeBlocksAndVolume) {
  const Mesh m = cubeMesh(0, 1);
  for (uint32_t res : {64u, 256u}) {
    const SceneHeader h = placed(0, 1, res);
    const SurfaceFootprint f = surfaceFootprint(m, std::vector<uint8_t>(12, 0), h);
    EXPECT_NEAR(f.enclosedVoxels, double(res) * res * res, 1e-6 * res * res * res);
    EXPECT_NEAR(f.crossings[2], 2.0 * res * res, 1e-6 * res * res);
    expectBlocksNear(m, h, 1.25, "cube");
  }
}

TEST(MeshFootprint, TiltedAndCurvedSurfaces) {
  // A cube inside a larger grid (faces between voxel boundaries) and a sphere
  // of 8000 small triangles in every orientation.
  expectBlocksNear(cubeMesh(0.1, 0.9), placed(0, 1, 200), 1.3, "inner cube");
  expectBlocksNear(sphereMesh(1.0, 40, 100), placed(-1.1, 1.1, 160), 1.5, "sphere 160");
  expectBlocksNear(sphereMesh(1.0, 40, 100), placed(-1.1, 1.1, 24), 1.5, "sphere 24 (triangles smaller than voxels)");
}

TEST(MeshFootprint, SameAtAnyThreadCount) {
  // 40,000 triangles: four pieces counted apart and merged, at the fine cells
  // and with a piece budget that makes the cells coarser.
  const Mesh m = sphereMesh(1.0, 200, 100);
  std::vector<uint8_t> cls(m.triangles.size());
  for (size_t t = 0; t < cls.size(); ++t) cls[t] = uint8_t(t / 997 % 6);  // class borders through cells
  for (uint64_t budget : {uint64_t(1) << 22, uint64_t(5000)}) {
    const SceneHeader h = placed(-1.1, 1.1, 300);
    const SurfaceFootprint one = surfaceFootprint(m, cls, h, budget, 1);
    EXPECT_GT(one.blocks, 0.0);
    EXPECT_GT(one.blockClasses, one.blocks);  // several classes in some blocks
    for (unsigned threads : {2u, 3u, 0u}) {
      const SurfaceFootprint f = surfaceFootprint(m, cls, h, budget, threads);
      EXPECT_EQ(f.blocks, one.blocks) << threads << " threads, budget " << budget;
      EXPECT_EQ(f.blockClasses, one.blockClasses) << threads << " threads";
      EXPECT_EQ(f.area, one.area) << threads << " threads";
      EXPECT_EQ(f.enclosedVoxels, one.enclosedVoxels) << threads << " threads";
      for (int k = 0; k < 3; ++k) EXPECT_EQ(f.crossings[k], one.crossings[k]) << threads << " threads";
    }
  }
}

TEST(MeshFootprint, CellBitsCountAsTheCellTableDoes) {
  // Meshes of at most four classes are counted with a bit per cell and class,
  // others with the table of cells; both must give the same blocks. A fifth
  // class on a triangle outside the grid (it touches no cell) sends the same
  // mesh to the table.
  for (int classes : {1, 2, 4}) {
    for (uint32_t res : {24u, 160u, 300u}) {
      Mesh m = sphereMesh(1.0, 200, 100);
      std::vector<uint8_t> cls(m.triangles.size());
      for (size_t t = 0; t < cls.size(); ++t) cls[t] = uint8_t(t / 997 % size_t(classes));
      const SceneHeader h = placed(-1.1, 1.1, res);
      const SurfaceFootprint bits = surfaceFootprint(m, cls, h, uint64_t(1) << 22, 2);
      const uint32_t far = uint32_t(m.positions.size());
      for (int k = 0; k < 3; ++k) m.positions.push_back({50.0 + k, 50.0, 50.0 + 2 * k});
      m.triangles.push_back({far, far + 1, far + 2});
      m.triangleMaterial.push_back(0);
      m.trianglePart.push_back(0);
      cls.push_back(200);
      const SurfaceFootprint table = surfaceFootprint(m, cls, h, uint64_t(1) << 22, 2);
      EXPECT_EQ(bits.blocks, table.blocks) << classes << " classes at " << res;
      EXPECT_EQ(bits.blockClasses, table.blockClasses) << classes << " classes at " << res;
      if (classes > 1) {
        EXPECT_GT(bits.blockClasses, bits.blocks) << "class borders run through cells";
      }
    }
  }
}

/// The same triangles with three vertices of their own each, as an STL stores them.
Mesh soupOf(const Mesh& m) {
  Mesh s = m;
  s.positions.clear();
  for (auto& t : s.triangles)
    for (uint32_t& v : t) {
      s.positions.push_back(m.positions[v]);
      v = uint32_t(s.positions.size() - 1);
    }
  return s;
}

double partOf(const MemoryEstimate& e, const std::string& name) {
  for (const MemoryPart& p : e.parts)
    if (p.name == name) return double(p.bytes);
  return 0.0;
}

TEST(MeshFootprint, WindingTablesCountWhereTheyExceedTheBake) {
  // The winding rule's weld and boundary tables live before the blocks: a
  // mesh with many vertices in a coarse grid needs them more than its blocks;
  // the parity rule and the surface fill build no such tables.
  const Mesh m = sphereMesh(1.0, 200, 100);  // 40,000 triangles at --res 8
  const std::vector<uint8_t> cls(m.triangles.size(), 0);
  const SceneHeader coarse = placed(-1.1, 1.1, 8);
  const SurfaceFootprint f = surfaceFootprint(m, cls, coarse);
  const uint64_t welded = distinctPositions(m);
  const std::string tables = "winding boundary tables (before the blocks)";
  VoxelizeSettings s;
  s.fill = FillMode::Solid;
  s.solidRule = SolidRule::Winding;
  const MemoryEstimate winding = estimateMeshBake(f, m, s, welded);
  EXPECT_GT(partOf(winding, tables), 0.0);
  // The bake's parts and the tables' excess: the tables' own estimate, with
  // the lattice; at or over what an indexed closed mesh was measured to take
  // (the bunny: 313 bytes a vertex above the lattice) and within 2.5x of it.
  const double perVertex = (double(winding.bytes()) - double(m.positions.size()) * 24) / double(m.positions.size());
  EXPECT_GT(perVertex, 313.0);
  EXPECT_LT(perVertex, 2.5 * 313.0);
  s.solidRule = SolidRule::Parity;
  EXPECT_EQ(partOf(estimateMeshBake(f, m, s, welded), tables), 0.0);
  s.fill = FillMode::Surface;
  EXPECT_EQ(partOf(estimateMeshBake(f, m, s, welded), tables), 0.0);
  // A fine grid's blocks outweigh the tables: nothing added.
  const SceneHeader fine = placed(-1.1, 1.1, 512);
  s.fill = FillMode::Solid;
  s.solidRule = SolidRule::Winding;
  EXPECT_EQ(partOf(estimateMeshBake(surfaceFootprint(m, cls, fine), m, s, welded), tables), 0.0);
}

TEST(MeshFootprint, DistinctPositionsWeldASoup) {
  // The UV sphere's north pole is 100 vertices at one position (the south
  // pole's sin(pi) is not 0 in doubles: 100 positions); the soup of its
  // 40,000 triangles (120,000 vertices) has the same distinct positions.
  const Mesh m = sphereMesh(1.0, 200, 100);
  const uint64_t indexed = distinctPositions(m);
  EXPECT_EQ(indexed, m.positions.size() - 99);
  const Mesh soup = soupOf(m);
  EXPECT_EQ(distinctPositions(soup), indexed);
  // -0 and +0 are one position (the lattice makes them one vertex).
  Mesh signs;
  signs.positions = {{0.0, 0.0, 1.0}, {-0.0, 0.0, 1.0}, {0.0, -0.0, 1.0}, {1.0, 0.0, 1.0}};
  EXPECT_EQ(distinctPositions(signs), 2u);
  EXPECT_EQ(distinctPositions(Mesh{}), 0u);
}

TEST(MeshFootprint, WindingTablesOfASoupFollowItsWeldedPositions) {
  // An STL's soup is welded before the tables grow: its estimate is the
  // indexed mesh's plus the soup's own per-vertex arrays (index and moved
  // copy), far below what its 3 vertices per triangle would give, and it
  // grows with the distinct positions it is told.
  const Mesh m = sphereMesh(1.0, 200, 100);
  const Mesh soup = soupOf(m);
  const std::vector<uint8_t> cls(m.triangles.size(), 0);
  const SceneHeader coarse = placed(-1.1, 1.1, 8);
  VoxelizeSettings s;
  s.fill = FillMode::Solid;
  s.solidRule = SolidRule::Winding;
  const double indexed = double(estimateMeshBake(surfaceFootprint(m, cls, coarse), m, s, distinctPositions(m)).bytes());
  const SurfaceFootprint fs = surfaceFootprint(soup, cls, coarse);
  const double welded = double(estimateMeshBake(fs, soup, s, distinctPositions(soup)).bytes());
  const double unwelded = double(estimateMeshBake(fs, soup, s, soup.positions.size()).bytes());
  EXPECT_GT(welded, indexed);           // the soup's vertices still cost their index and lattice
  EXPECT_LT(welded, 2.0 * indexed);
  EXPECT_GT(unwelded, 2.5 * welded);    // counted unwelded it was ~4x high
  // More distinct positions (fewer welded) never estimate less; beyond the
  // vertex count they count as the vertices.
  double before = 0;
  for (uint64_t p : {uint64_t(10000), uint64_t(20000), uint64_t(60000), uint64_t(120000), uint64_t(500000)}) {
    const double bytes = double(estimateMeshBake(fs, soup, s, p).bytes());
    EXPECT_GE(bytes, before) << p;
    before = bytes;
  }
  EXPECT_EQ(before, unwelded);
}

/// Two triangles: a square across the whole grid at mid-height, facing z.
Mesh worldPlane() {
  Mesh m;
  m.positions = {{0, 0, 0.5}, {1, 0, 0.5}, {1, 1, 0.5}, {0, 1, 0.5}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.triangleMaterial.assign(2, 0);
  m.trianglePart.assign(2, 0);
  m.materials.push_back({});
  m.parts.push_back({});
  return m;
}

TEST(MeshFootprint, WindingCountsTheCappedCopyAndTheCapsCrossings) {
  // The interior pass works on a capped copy of the mesh (13 bytes a
  // triangle, 24 a vertex, 85 a cap, at most one a boundary edge); the caps'
  // +z crossings (32 bytes each) cover at most l^2 / 4pi columns for a
  // boundary of length l, and at most the box's columns twice.
  const std::string copy = "capped copy of the mesh", caps = "caps' ray crossings";
  VoxelizeSettings s;
  s.fill = FillMode::Solid;
  s.solidRule = SolidRule::Winding;
  const SceneHeader h = placed(0, 1, 64);
  // A square across the grid: one loop of 4 edges (6 by Euler's count, B =
  // 2 P - T), its cap the square: the box's 64 x 64 columns, twice.
  const Mesh square = worldPlane();
  const std::vector<uint8_t> two(2, 0);
  const SurfaceFootprint fs = surfaceFootprint(square, two, h);
  EXPECT_EQ(fs.boxColumns, 64.0 * 64.0);
  const MemoryEstimate es = estimateMeshBake(fs, square, s, distinctPositions(square));
  EXPECT_EQ(partOf(es, copy), 2 * 13.0 + 4 * 24.0 + 6 * 85.0);
  EXPECT_EQ(partOf(es, caps), 2 * 64.0 * 64.0 * 32);
  // A small triangle facing z (area A = 81.92 voxel faces): its perimeter's
  // bound, 9 (4 A / sqrt 3) / 4pi = 1.65 A, over its cap's A columns.
  Mesh tri;
  tri.positions = {{0.2, 0.2, 0.5}, {0.4, 0.2, 0.5}, {0.2, 0.4, 0.5}};
  tri.triangles = {{0, 1, 2}};
  tri.triangleMaterial.assign(1, 0);
  tri.trianglePart.assign(1, 0);
  tri.materials.push_back({});
  tri.parts.push_back({});
  const std::vector<uint8_t> one(1, 0);
  const SurfaceFootprint ft = surfaceFootprint(tri, one, h);
  const double area = 0.5 * 12.8 * 12.8;
  EXPECT_NEAR(ft.area, area, 1e-5 * area);  // of the corners on the lattice
  const MemoryEstimate et = estimateMeshBake(ft, tri, s, 3);
  EXPECT_EQ(partOf(et, copy), 13.0 + 3 * 24.0 + 3 * 85.0);
  EXPECT_NEAR(partOf(et, caps), 32 * 9 * (4 / std::sqrt(3.0)) * ft.area / (4 * M_PI), 1.0);
  EXPECT_GT(partOf(et, caps), 32 * area);
  // Neither part without the winding rule.
  s.solidRule = SolidRule::Parity;
  EXPECT_EQ(partOf(estimateMeshBake(fs, square, s, 4), copy), 0.0);
  EXPECT_EQ(partOf(estimateMeshBake(fs, square, s, 4), caps), 0.0);
  s.fill = FillMode::Surface;
  EXPECT_EQ(partOf(estimateMeshBake(fs, square, s, 4), copy), 0.0);
}

TEST(MeshFootprint, RegionsCountTheirBoxOnly) {
  // Large triangles spanning the world meet every region: the footprint of a
  // region counts the blocks and surface in its box, as the voxelizer
  // allocates them, so the largest region's shrinks as 1/N (it was the
  // whole world's at every N), and the regions' sum is the world's.
  for (const Mesh& m : {worldPlane(), sphereMesh(0.45, 40, 100)}) {
    const std::vector<uint8_t> cls(m.triangles.size(), 0);
    for (uint32_t res : {256u, 512u}) {
      const SceneHeader world = m.triangles.size() == 2 ? placed(0, 1, res) : placed(-0.5, 0.5, res);
      const SurfaceFootprint whole = surfaceFootprint(m, cls, world);
      double previousLargest = 2 * whole.blocks;
      for (uint32_t n : {1u, 2u, 4u, 8u}) {
        double blocks = 0, surface = 0, largest = 0;
        for (uint32_t i = 0; i < n; ++i) {
          SceneHeader h = world;
          h.region = SceneRegion{i, n, regionTile(world.dims, i, n), ""};
          const SurfaceFootprint f = surfaceFootprint(m, cls, h);
          blocks += f.blocks, surface += f.surfaceVoxels;
          largest = std::max(largest, f.blocks);
          EXPECT_LE(f.boxVoxels, double(h.region->box.max.u - h.region->box.min.u + 1) * res *
                                     double(h.region->box.max.w - h.region->box.min.w + 1));
          // Against the blocks the region's bake creates.
          VoxelizeSettings s;
          s.threads = 2;
          s.region = h.region->box;
          const double real = double(voxelizeMeshBlocks(m, cls, h, s).blockCount());
          EXPECT_GE(f.blocks, real / 1.25) << res << " region " << i << "/" << n;
          EXPECT_LE(f.blocks, real * 1.5 + 1) << res << " region " << i << "/" << n;
        }
        EXPECT_NEAR(blocks, whole.blocks, 1e-9 * whole.blocks) << res << " N " << n;  // 32-voxel tiles: whole blocks
        EXPECT_NEAR(surface, whole.surfaceVoxels, 1e-6 * whole.surfaceVoxels) << res << " N " << n;
        EXPECT_LT(largest, previousLargest) << res << " N " << n;
        if (m.triangles.size() == 2) {  // uniform
          EXPECT_LT(largest, 1.3 * whole.blocks / n) << res << " N " << n;
        }
        previousLargest = largest;
      }
    }
  }
}

}  // namespace
}  // namespace vox
