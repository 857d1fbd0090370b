// Triangles reaching past the lattice's range (2^20 voxels from the grid):
// a surface fill drops those that miss the grid and clips those that cross
// it (libvox/mesh/lattice_triangles.h), and the grid's voxels are those of
// the whole triangle; a solid fill refuses them.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "libvox/mesh/lattice_triangles.h"
#include "libvox/mesh/voxelize.h"
#include "libvox/mesh/voxelize_memory.h"
#include "libvox/scene/voxelize_scene.h"
#include "test_util.h"
#include "voxelize_test_meshes.h"

using namespace vox;

namespace {

using Key = std::tuple<int, int, int>;
struct Cell {
  uint64_t votes = 0;
  std::optional<RgbLinear> color;
};

std::map<Key, Cell> cells(const Scene& s) {
  std::map<Key, Cell> out;
  s.forEachVoxel([&](const VoxelView& v) { out[{v.at.u, v.at.v, v.at.w}] = {v.totalVotes(), v.color}; });
  return out;
}

Scene bake(const Mesh& m, const SceneHeader& h, unsigned threads = 1, FillMode fill = FillMode::Surface) {
  VoxelizeSettings s;
  s.threads = threads;
  s.fill = fill;
  return voxelizeMesh(m, std::vector<uint8_t>(m.triangles.size(), 1), h, s);
}

/// The voxels of an n^3 grid (voxel size 1 at the origin) whose closed box
/// meets the triangle, decided by the exact integer test on the triangle's
/// own vertices (multiples of 2^-16 voxel, so on the lattice exactly, and
/// within 2^23 voxels, where that test's 128-bit products hold).
std::set<Key> oracle(const std::array<std::array<double, 3>, 3>& tri, int n) {
  std::array<int64_t, 3> q[3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) {
      const double scaled = tri[k][i] * 65536.0;
      EXPECT_EQ(scaled, std::round(scaled)) << "the oracle needs vertices on the lattice";
      EXPECT_LT(std::abs(tri[k][i]), 8388608.0);
      q[k][i] = int64_t(scaled);
    }
  std::set<Key> out;
  for (int u = 0; u < n; ++u)
    for (int v = 0; v < n; ++v)
      for (int w = 0; w < n; ++w)
        if (triangleTouchesVoxel(q, u, v, w)) out.insert({u, v, w});
  return out;
}

std::set<Key> keys(const std::map<Key, Cell>& c) {
  std::set<Key> out;
  for (const auto& [k, cell] : c) out.insert(k);
  return out;
}

/// `tri` clipped to the box [lo, hi]^3 in long double, fanned from its first
/// vertex, with each new vertex's colour interpolated: the clip done by hand.
Mesh clippedByHand(const std::array<std::array<double, 3>, 3>& tri, const std::array<std::array<float, 4>, 3>& rgba,
                   double lo, double hi) {
  struct V {
    long double p[3], c[4];
  };
  std::vector<V> poly(3);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 4; ++i) {
      if (i < 3) poly[k].p[i] = tri[k][i];
      poly[k].c[i] = rgba[k][i];
    }
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      std::vector<V> next;
      auto inside = [&](const V& v) { return side == 0 ? v.p[axis] - lo : hi - v.p[axis]; };
      for (size_t i = 0; i < poly.size(); ++i) {
        const V& a = poly[i];
        const V& b = poly[(i + 1) % poly.size()];
        const long double da = inside(a), db = inside(b);
        if (da >= 0) next.push_back(a);
        if ((da >= 0) != (db >= 0)) {
          const long double t = da / (da - db);
          V q;
          for (int k = 0; k < 3; ++k) q.p[k] = a.p[k] + (b.p[k] - a.p[k]) * t;
          for (int k = 0; k < 4; ++k) q.c[k] = a.c[k] + (b.c[k] - a.c[k]) * t;
          q.p[axis] = side == 0 ? lo : hi;
          next.push_back(q);
        }
      }
      poly = next;
    }
  std::vector<std::array<double, 3>> pos;
  std::vector<std::array<uint32_t, 3>> tris;
  for (const V& v : poly) pos.push_back({double(v.p[0]), double(v.p[1]), double(v.p[2])});
  for (uint32_t i = 1; i + 1 < poly.size(); ++i) tris.push_back({0, i, i + 1});
  Mesh m = voxtest::meshOf(pos, tris);
  for (const V& v : poly) m.colors.push_back({float(v.c[0]), float(v.c[1]), float(v.c[2]), float(v.c[3])});
  return m;
}

// Big triangles through a 16^3 grid, their vertices about 1e7 voxels away:
// P + A, P + B, P - A - B around a point P inside the grid.
std::array<std::array<double, 3>, 3> bigTriangle(std::array<double, 3> P, std::array<double, 3> A, std::array<double, 3> B) {
  return {{{P[0] + A[0], P[1] + A[1], P[2] + A[2]},
           {P[0] + B[0], P[1] + B[1], P[2] + B[2]},
           {P[0] - A[0] - B[0], P[1] - A[1] - B[1], P[2] - A[2] - B[2]}}};
}

const std::array<std::array<double, 3>, 3> kBig[] = {
    bigTriangle({8.25, 7.5, 8.125}, {6000011, 3000017, -4000037}, {-3000011, 5000009, 2500003}),
    bigTriangle({3.0078125, 12.5, 6.75}, {-7000003, 1000033, 2999999}, {2000029, -6000001, -1000003}),
    bigTriangle({10.5, 4.25, 11.0625}, {4000037, -2000003, 7000019}, {-1000001, 6500011, -3000029}),
};

}  // namespace

TEST(VoxelizeFar, BigTriangleGivesExactlyTheVoxelsOfTheWholeTriangle) {
  const SceneHeader h = voxtest::twoClassHeader({16, 16, 16});
  for (const auto& tri : kBig) {
    const Mesh m = voxtest::meshOf({tri[0], tri[1], tri[2]}, {{0, 1, 2}});
    const std::map<Key, Cell> got = cells(bake(m, h));
    const std::set<Key> want = oracle(tri, 16);
    ASSERT_GT(want.size(), 100u) << "the triangle crosses the grid";
    EXPECT_EQ(keys(got), want);
    EXPECT_EQ(cells(bake(m, h, 2)).size(), got.size());
  }
}

TEST(VoxelizeFar, ClippedTriangleMatchesOneClippedByHand) {
  // Voxels, votes and colours against the same triangle clipped to a box of
  // its own (2 voxels around the grid) in the test: the same voxels, votes
  // within one per fan triangle (each rounds its own area), colours as the
  // vertex colours interpolated in the whole triangle.
  const SceneHeader h = voxtest::twoClassHeader({16, 16, 16});
  const std::array<std::array<float, 4>, 3> rgba = {{{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}}};
  for (const auto& tri : kBig) {
    Mesh m = voxtest::meshOf({tri[0], tri[1], tri[2]}, {{0, 1, 2}});
    m.colors = {rgba[0], rgba[1], rgba[2]};
    const Mesh byHand = clippedByHand(tri, rgba, -2, 18);
    ASSERT_GE(byHand.triangles.size(), 1u);
    const std::map<Key, Cell> got = cells(bake(m, h)), want = cells(bake(byHand, h));
    ASSERT_EQ(keys(got), keys(want));
    const uint64_t fans = byHand.triangles.size() + 7;  // both fans: at most 7 triangles each
    double worst = 0;
    for (const auto& [k, cell] : got) {
      const Cell& w = want.at(k);
      EXPECT_LE(std::max(cell.votes, w.votes) - std::min(cell.votes, w.votes), fans);
      ASSERT_TRUE(cell.color && w.color);
      worst = std::max({worst, double(std::abs(cell.color->r - w.color->r)), double(std::abs(cell.color->g - w.color->g)),
                        double(std::abs(cell.color->b - w.color->b))});
    }
    EXPECT_LT(worst, 1e-4) << "colours interpolated in the whole triangle";
    // The thread count changes nothing, bit for bit.
    const std::map<Key, Cell> two = cells(bake(m, h, 2));
    ASSERT_EQ(keys(two), keys(got));
    for (const auto& [k, cell] : got) {
      EXPECT_EQ(two.at(k).votes, cell.votes);
      EXPECT_EQ(two.at(k).color, cell.color);
    }
  }
}

TEST(VoxelizeFar, FanCornersCarryTheirPlaceInTheSourceTriangle) {
  // Each fan corner's barycentric coordinates in the source triangle give
  // back the corner (within the snapping's half step), and the clip's new
  // vertices lie on the clip box, 64 voxels outside the 16^3 grid.
  const SceneHeader h = voxtest::twoClassHeader({16, 16, 16});
  for (const auto& tri : kBig) {
    const Mesh m = voxtest::meshOf({tri[0], tri[1], tri[2]}, {{0, 1, 2}});
    const LatticeTriangles t = latticeTriangles(m, h, FarTriangles::Clip);
    ASSERT_TRUE(t.clipped);
    ASSERT_EQ(t.firstFan, 0u);
    ASSERT_GE(t.size(m), 1u);
    ASSERT_LE(t.size(m), 7u);
    for (size_t f = 0; f < t.size(m); ++f) {
      EXPECT_EQ(t.sourceOf(f), 0u);
      for (int c = 0; c < 3; ++c) {
        double l[3] = {c == 0 ? 1.0 : 0.0, c == 1 ? 1.0 : 0.0, c == 2 ? 1.0 : 0.0};
        t.toSource(f, l[0], l[1], l[2]);
        const auto& q = t.lattice[t.corners(m, f)[size_t(c)]];
        bool onBox = false;
        for (int i = 0; i < 3; ++i) {
          const long double p = (long double)l[0] * tri[0][i] + (long double)l[1] * tri[1][i] + (long double)l[2] * tri[2][i];
          EXPECT_NEAR(double(p), double(q[i]) / 65536.0, 1e-4) << "fan " << f << " corner " << c;
          onBox = onBox || q[i] == -64 * 65536 || q[i] == 80 * 65536;
          EXPECT_GE(q[i], -64 * 65536);
          EXPECT_LE(q[i], 80 * 65536);
        }
        EXPECT_TRUE(onBox);
      }
    }
  }
}

TEST(VoxelizeFar, FarTriangleOutsideTheGridIsIgnored) {
  // A small triangle in the grid, and a stray one 5e6 voxels away (and one
  // whose vertex lies at 1e300): the scene is the small triangle's alone.
  const SceneHeader h = voxtest::twoClassHeader({8, 8, 8});
  const Mesh alone = voxtest::meshOf({{1.5, 1.5, 2.25}, {6.5, 2.5, 2.25}, {3.5, 6.5, 5.75}}, {{0, 1, 2}});
  const Mesh stray = voxtest::meshOf({{1.5, 1.5, 2.25}, {6.5, 2.5, 2.25}, {3.5, 6.5, 5.75}, {5e6, 0, 0}, {5e6, 1, 0},
                                      {5e6, 0, 1}, {-40, 1e300, 3}},
                                     {{0, 1, 2}, {3, 4, 5}, {3, 6, 4}});
  const std::map<Key, Cell> want = cells(bake(alone, h));
  for (unsigned threads : {1u, 2u}) {
    const std::map<Key, Cell> got = cells(bake(stray, h, threads));
    ASSERT_EQ(keys(got), keys(want));
    for (const auto& [k, cell] : got) EXPECT_EQ(cell.votes, want.at(k).votes);
  }
  const LatticeTriangles t = latticeTriangles(stray, h, FarTriangles::Clip);
  EXPECT_EQ(t.dropped, 2u);
  EXPECT_EQ(t.size(stray), 1u);
  // The grid's classes: the stray triangles' class touches nothing.
  std::vector<uint8_t> cls = {1, 2, 2};
  const std::array<bool, 256> used = classesTouchingDomain(stray, cls, h);
  EXPECT_TRUE(used[1]);
  EXPECT_FALSE(used[2]);
}

TEST(VoxelizeFar, MemoryEstimateCountsThePartNearTheGrid) {
  // A ground plane 2e7 voxels wide under a 64^3 grid: estimated as the plane
  // cropped to the grid by hand (it was 2^48 pieces and petabytes of blocks).
  const SceneHeader h = voxtest::twoClassHeader({64, 64, 64});
  const Mesh far = voxtest::meshOf({{-1e7, -1e7, 20.5}, {1e7, -1e7, 20.5}, {1e7, 1e7, 20.5}, {-1e7, 1e7, 20.5}},
                                   {{0, 1, 2}, {0, 2, 3}});
  const Mesh cropped = voxtest::meshOf({{0, 0, 20.5}, {64, 0, 20.5}, {64, 64, 20.5}, {0, 64, 20.5}}, {{0, 1, 2}, {0, 2, 3}});
  const std::vector<uint8_t> cls = {1, 1};
  const SurfaceFootprint f = surfaceFootprint(far, cls, h), c = surfaceFootprint(cropped, cls, h);
  EXPECT_EQ(f.blocks, c.blocks);
  EXPECT_EQ(f.blocks, 64.0) << "one layer of 8 x 8 blocks";
  EXPECT_LT(f.area, 200.0 * 200.0) << "the clipped plane's area, not the whole plane's";
}

TEST(VoxelizeFar, StripToAVertexBeyondDoubleGridRange) {
  // Two near vertices and one far along +x: inside the grid the triangle is
  // the strip y in [3.5, 9.5] at z = 4.25 from x = 2.5 on (the far vertex's
  // pull on y is below 1e-290 voxel). The far vertex at 1e300 voxels, and at
  // 1.7e308 world units with voxels of 0.5 (its grid coordinate overflows a
  // double; the clip converts it in long double).
  for (const auto& [far, voxelSize] : {std::pair{1e300, 1.0}, std::pair{1.7e308, 0.5}}) {
    const SceneHeader h = voxtest::twoClassHeader({16, 16, 16}, voxelSize);
    const double s = voxelSize;
    const Mesh m = voxtest::meshOf({{2.5 * s, 3.5 * s, 4.25 * s}, {2.5 * s, 9.5 * s, 4.25 * s}, {far, 6.5 * s, 4.25 * s}},
                                   {{0, 1, 2}});
    std::set<Key> want;
    for (int u = 2; u < 16; ++u)
      for (int v = 3; v <= 9; ++v) want.insert({u, v, 4});
    EXPECT_EQ(keys(cells(bake(m, h))), want) << far;
  }
}

TEST(VoxelizeFar, SolidFillRefusesAFarVertexNamingTheFixes) {
  const SceneHeader h = voxtest::twoClassHeader({16, 16, 16});
  const auto& tri = kBig[0];
  const Mesh m = voxtest::meshOf({tri[0], tri[1], tri[2]}, {{0, 1, 2}});
  EXPECT_TRUE(voxtest::throwsVoxError([&] { bake(m, h, 1, FillMode::Solid); }, ErrorKind::BadInput,
                                      {"vertex 1 (counted from 1) lies 6000019 voxels from the grid along x",
                                       "beyond the 2^20 a solid fill reaches", "remove the far geometry",
                                       "voxels at least 6 times larger", "fill only the surface"}));
  EXPECT_EQ(voxtest::settingOfError([&] { bake(m, h, 1, FillMode::Solid); }), Setting::FillMode);
  // Non-finite vertices stay refused by either fill.
  const Mesh nan = voxtest::meshOf({{0, 0, 0}, {1, 0, 0}, {0, NAN, 0}}, {{0, 1, 2}});
  EXPECT_TRUE(voxtest::throwsVoxError([&] { bake(nan, h); }, ErrorKind::BadInput,
                                      {"vertex 3 (counted from 1) has a non-finite coordinate"}));
}

TEST(VoxelizeFar, ClassesTouchingTheDomainAsTheVoxelByVoxelTestFindsThem) {
  // Triangles around a 5 x 4 x 3 grid, many straddling its boundary or
  // touching it only at a face, an edge or a corner (vertices on quarter
  // voxels), each its own class: a class is used exactly when the exact test
  // admits one of the grid's voxels.
  const int dims[3] = {5, 4, 3};
  const SceneHeader h = voxtest::twoClassHeader({uint32_t(dims[0]), uint32_t(dims[1]), uint32_t(dims[2])});
  uint64_t state = 12345;
  auto quarter = [&](int lo, int hi) {  // a multiple of 1/4 in [lo, hi]
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + double((state >> 33) % uint64_t((hi - lo) * 4 + 1)) / 4;
  };
  std::vector<std::array<double, 3>> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<uint8_t> cls;
  for (int t = 0; t < 250; ++t) {
    for (int k = 0; k < 3; ++k) {
      std::array<double, 3> p;
      for (int i = 0; i < 3; ++i) p[size_t(i)] = quarter(-3, dims[i] + 3);
      if (t % 5 == 0) p[0] = t % 2 ? double(dims[0]) : 0.0;  // in a face's plane
      positions.push_back(p);
    }
    const uint32_t b = uint32_t(3 * t);
    triangles.push_back({b, b + 1, b + 2});
    cls.push_back(uint8_t(t + 1));
  }
  const Mesh m = voxtest::meshOf(positions, triangles);
  const std::array<bool, 256> used = classesTouchingDomain(m, cls, h);
  int touching = 0;
  for (int t = 0; t < 250; ++t) {
    std::array<int64_t, 3> q[3];
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) q[k][size_t(i)] = int64_t(positions[size_t(3 * t + k)][size_t(i)] * 65536.0);
    bool any = false;
    for (int u = 0; u < dims[0] && !any; ++u)
      for (int v = 0; v < dims[1] && !any; ++v)
        for (int w = 0; w < dims[2] && !any; ++w) any = triangleTouchesVoxel(q, u, v, w);
    EXPECT_EQ(used[size_t(t + 1)], any) << "triangle " << t;
    touching += any;
  }
  EXPECT_GT(touching, 50);
  EXPECT_LT(touching, 225) << "the test needs triangles that miss the grid too";
}

TEST(VoxelizeFar, ALargeTiltedTriangleThatMissesTheGridIsDecidedAtOnce) {
  // The plane x + y + z = -1/2 passes a half voxel from the corner of a
  // 1024^3 grid: its triangle's box covers the grid, the triangle misses it.
  // (Deciding this voxel by voxel took 10^9 exact tests.) Shifted by one
  // voxel, the plane cuts the corner voxel.
  const SceneHeader h = voxtest::twoClassHeader({1024, 1024, 1024});
  const Mesh miss = voxtest::meshOf({{1e5, 1e5, -2e5 - 0.5}, {-2e5 - 0.5, 1e5, 1e5}, {1e5, -2e5 - 0.5, 1e5}}, {{0, 1, 2}});
  const Mesh hit = voxtest::meshOf({{1e5, 1e5, -2e5 + 0.5}, {-2e5 + 0.5, 1e5, 1e5}, {1e5, -2e5 + 0.5, 1e5}}, {{0, 1, 2}});
  EXPECT_FALSE(classesTouchingDomain(miss, {1}, h)[1]);
  EXPECT_TRUE(classesTouchingDomain(hit, {1}, h)[1]);
}
