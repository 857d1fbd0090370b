// The exact voxelizer against independent oracles: analytic shapes with known
// answers, dense point sampling (no voxel a triangle touches is missed), double
// clipping against slightly grown boxes (no voxel is added that the triangle
// does not reach), enclosed volume, and determinism across thread counts.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "libvox/scene/voxelize_scene.h"
#include "libvox/scene/voxelize_check.h"
#include "libvox/scene/voxelize_sdf.h"
#include "test_util.h"
#include "voxelize_test_meshes.h"

using namespace vox;

namespace {

using voxtest::meshOf;

SceneHeader gridHeader(uint32_t n, double voxelSize = 1.0, std::array<double, 3> origin = {0, 0, 0}) {
  return voxtest::twoClassHeader({n, n, n}, voxelSize, origin);
}

std::set<std::tuple<int, int, int>> occupied(const Scene& s) {
  std::set<std::tuple<int, int, int>> out;
  s.forEachVoxel([&](const VoxelView& v) { out.insert({v.at.u, v.at.v, v.at.w}); });
  return out;
}

Scene run(const Mesh& m, const SceneHeader& h, FillMode fill, unsigned threads = 1, uint8_t cls = 1) {
  VoxelizeSettings s;
  s.fill = fill;
  s.threads = threads;
  return voxelizeMesh(m, std::vector<uint8_t>(m.triangles.size(), cls), h, s);
}

/// Axis-aligned box [lo, hi] as 12 outward-facing triangles.
Mesh boxMesh(std::array<double, 3> lo, std::array<double, 3> hi, bool inverted = false) {
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 8; ++i) p.push_back({i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  std::vector<std::array<uint32_t, 3>> t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                            {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  if (inverted)
    for (auto& tri : t) std::swap(tri[1], tri[2]);
  return meshOf(p, t);
}

Mesh sphereMesh(std::array<double, 3> c, double r, int slices, bool inverted = false) {
  std::vector<std::array<double, 3>> p;
  std::vector<std::array<uint32_t, 3>> t;
  const int stacks = slices / 2;
  for (int i = 0; i <= stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const double th = M_PI * i / stacks, ph = 2 * M_PI * j / slices;
      p.push_back({c[0] + r * std::sin(th) * std::cos(ph), c[1] + r * std::sin(th) * std::sin(ph), c[2] + r * std::cos(th)});
    }
  auto id = [&](int i, int j) { return uint32_t(i * slices + (j % slices)); };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      std::array<uint32_t, 3> a{id(i, j), id(i + 1, j), id(i + 1, j + 1)}, b{id(i, j), id(i + 1, j + 1), id(i, j + 1)};
      if (inverted) std::swap(a[1], a[2]), std::swap(b[1], b[2]);
      t.push_back(a), t.push_back(b);
    }
  return meshOf(p, t);
}

}  // namespace

TEST(Voxelize, FaceOnAGridPlaneTouchesBothLayers) {
  // A square on the plane z = 3 covering x, y in [1, 3]: closed boxes of layers
  // w = 2 and w = 3 touch it, for u, v in 0..3 (its edges lie on grid planes too).
  const Mesh m = meshOf({{1, 1, 3}, {3, 1, 3}, {3, 3, 3}, {1, 3, 3}}, {{0, 1, 2}, {0, 2, 3}});
  const auto occ = occupied(run(m, gridHeader(8), FillMode::Surface));
  std::set<std::tuple<int, int, int>> want;
  for (int u = 0; u <= 3; ++u)
    for (int v = 0; v <= 3; ++v)
      for (int w : {2, 3}) want.insert({u, v, w});
  EXPECT_EQ(occ, want);
}

TEST(Voxelize, VertexOnACornerTouchesTheEightVoxelsAroundIt) {
  // A degenerate triangle collapsed to the point (4, 4, 4).
  const Mesh m = meshOf({{4, 4, 4}, {4, 4, 4}, {4, 4, 4}}, {{0, 1, 2}});
  const auto occ = occupied(run(m, gridHeader(8), FillMode::Surface));
  EXPECT_EQ(occ.size(), 8u);
  for (auto [u, v, w] : occ) EXPECT_TRUE(u >= 3 && u <= 4 && v >= 3 && v <= 4 && w >= 3 && w <= 4);
}

TEST(Voxelize, RandomTrianglesMatchOracles) {
  std::mt19937 rng(7);
  const uint32_t n = 10;
  const SceneHeader h = gridHeader(n);
  for (int trial = 0; trial < 300; ++trial) {
    // Mix of lattice-aligned vertices (on faces, edges, corners) and arbitrary ones.
    auto coord = [&]() -> double {
      switch (rng() % 3) {
        case 0: return double(rng() % (n + 1));         // on a grid plane
        case 1: return (rng() % (2 * n + 1)) * 0.5;      // on a plane or a centre
        default: return std::uniform_real_distribution<double>(-0.5, n + 0.5)(rng);
      }
    };
    std::array<std::array<double, 3>, 3> v;
    for (auto& p : v) p = {coord(), coord(), coord()};
    if (trial % 10 == 0) v[2] = v[1];  // degenerate: a segment
    const Mesh m = meshOf({v[0], v[1], v[2]}, {{0, 1, 2}});
    const auto occ = occupied(run(m, h, FillMode::Surface));
    // Snapped vertices, as the voxelizer sees them.
    std::array<double, 3> s[3];
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) s[k][i] = double(snapToLattice(v[k][i])) / 65536.0;
    // No misses: every sample point of the triangle lies in an occupied voxel (all
    // voxels whose closed box holds it).
    const int N = 40;
    for (int a = 0; a <= N; ++a)
      for (int b = 0; a + b <= N; ++b) {
        const double l0 = double(a) / N, l1 = double(b) / N, l2 = 1 - l0 - l1;
        double p[3];
        for (int i = 0; i < 3; ++i) p[i] = l0 * s[0][i] + l1 * s[1][i] + l2 * s[2][i];
        int lo[3], hi[3];
        for (int i = 0; i < 3; ++i) {
          lo[i] = int(std::ceil(p[i])) - 1, hi[i] = int(std::floor(p[i]));
          if (std::abs(p[i] - std::round(p[i])) > 1e-9) lo[i] = hi[i] = int(std::floor(p[i]));
        }
        for (int x = lo[0]; x <= hi[0]; ++x)
          for (int y = lo[1]; y <= hi[1]; ++y)
            for (int z = lo[2]; z <= hi[2]; ++z)
              if (x >= 0 && y >= 0 && z >= 0 && x < int(n) && y < int(n) && z < int(n)) {
                ASSERT_TRUE(occ.count({x, y, z})) << "trial " << trial << " missed voxel " << x << "," << y << "," << z;
              }
      }
    // No extras: every occupied voxel's box grown by 1e-7 still intersects the
    // triangle (double clipping with a margin far above its rounding error).
    for (auto [x, y, z] : occ) {
      std::vector<std::array<double, 3>> poly = {s[0], s[1], s[2]};
      const int c[3] = {x, y, z};
      for (int axis = 0; axis < 3 && !poly.empty(); ++axis)
        for (int side = 0; side < 2 && !poly.empty(); ++side) {
          const double bound = side == 0 ? c[axis] - 1e-7 : c[axis] + 1 + 1e-7;
          std::vector<std::array<double, 3>> out;
          for (size_t i = 0; i < poly.size(); ++i) {
            const auto& A = poly[i];
            const auto& B = poly[(i + 1) % poly.size()];
            const double da = side == 0 ? A[axis] - bound : bound - A[axis];
            const double db = side == 0 ? B[axis] - bound : bound - B[axis];
            if (da >= 0) out.push_back(A);
            if ((da >= 0) != (db >= 0)) {
              std::array<double, 3> q;
              for (int k = 0; k < 3; ++k) q[k] = A[k] + (B[k] - A[k]) * (da / (da - db));
              out.push_back(q);
            }
          }
          poly = out;
        }
      ASSERT_FALSE(poly.empty()) << "trial " << trial << " extra voxel " << x << "," << y << "," << z;
    }
  }
}

TEST(Voxelize, ShellOfAClosedMeshIsWatertight) {
  // Flood fill the complement of the surface from the domain boundary: it must
  // not reach the sphere's centre.
  const uint32_t n = 40;
  const Mesh m = sphereMesh({20.3, 19.7, 20.1}, 14.2, 48);
  const auto occ = occupied(run(m, gridHeader(n), FillMode::Surface, 2));
  std::vector<char> seen(n * n * n, 0);
  std::vector<std::array<int, 3>> stack = {{0, 0, 0}};
  while (!stack.empty()) {
    auto [x, y, z] = stack.back();
    stack.pop_back();
    if (x < 0 || y < 0 || z < 0 || x >= int(n) || y >= int(n) || z >= int(n)) continue;
    char& s = seen[(x * n + y) * n + z];
    if (s || occ.count({x, y, z})) continue;
    s = 1;
    stack.push_back({x + 1, y, z}), stack.push_back({x - 1, y, z}), stack.push_back({x, y + 1, z});
    stack.push_back({x, y - 1, z}), stack.push_back({x, y, z + 1}), stack.push_back({x, y, z - 1});
  }
  EXPECT_FALSE(seen[(20 * n + 20) * n + 20]) << "the shell leaks";
}

TEST(Voxelize, SolidBoxIsExact) {
  // Box [2, 7] x [1, 5] x [3, 9] with faces on grid planes: the closed boxes of
  // voxels 1..7 x 0..5 x 2..9 touch it; every centre strictly inside is interior.
  for (bool inverted : {false, true}) {
    const Scene s = run(boxMesh({2, 1, 3}, {7, 5, 9}, inverted), gridHeader(12), FillMode::Solid, 2);
    EXPECT_EQ(s.occupiedCount(), uint64_t(7 * 6 * 8)) << "inverted " << inverted;
    const SceneStats st = s.stats();
    EXPECT_EQ(st.surface, uint64_t(7 * 6 * 8 - 3 * 2 * 4)) << "inverted " << inverted;
  }
}

TEST(Voxelize, SolidSphereVolumeAndInvertedWinding) {
  const uint32_t n = 48;
  const double r = 17.3;
  const std::array<double, 3> c{24.1, 23.7, 24.4};
  const Scene a = run(sphereMesh(c, r, 96), gridHeader(n), FillMode::Solid, 2);
  const Scene b = run(sphereMesh(c, r, 96, true), gridHeader(n), FillMode::Solid, 1);
  EXPECT_TRUE(compareScenes(a, b).same()) << "inverted winding must give the same solid";
  // Interior voxels: centres inside the polyhedron, whose volume is a bit below the sphere's.
  const SceneStats st = a.stats();
  const double interior = double(st.occupied - st.surface);
  const double sphere = 4.0 / 3.0 * M_PI * r * r * r;
  EXPECT_GT(interior, sphere * 0.80);
  EXPECT_LT(double(st.occupied), sphere * 1.25);
  // Brute force on voxel centres (well inside / well outside the sphere).
  a.forEachVoxel([&](const VoxelView& v) {
    const double d = std::hypot(v.at.u + 0.5 - c[0], v.at.v + 0.5 - c[1], v.at.w + 0.5 - c[2]);
    ASSERT_LT(d, r + 1.0) << "voxel far outside the sphere";
  });
  std::vector<ClassVotes> tmp;
  for (int u = 0; u < int(n); ++u)
    for (int v = 0; v < int(n); ++v)
      for (int w = 0; w < int(n); ++w)
        if (std::hypot(u + 0.5 - c[0], v + 0.5 - c[1], w + 0.5 - c[2]) < r - 1.0) {
          ASSERT_TRUE(a.voxel({u, v, w}, tmp)) << "interior voxel missing";
        }
}

TEST(Voxelize, OpenBoxStillFillsAndNestedCavityStaysHollow) {
  // Drop the top face (+z) of a box: the 2-of-3 vote (--solid-rule parity) fills
  // it anyway. (The winding rule leaves the top layer, whose centres lie on the
  // open face's plane where w = 0.5 exactly; tests/test_winding.cpp.)
  Mesh open = boxMesh({2.5, 2.5, 2.5}, {9.5, 9.5, 9.5});
  open.triangles.erase(open.triangles.begin() + 2, open.triangles.begin() + 4);
  open.triangleMaterial.resize(open.triangles.size());
  open.trianglePart.resize(open.triangles.size());
  VoxelizeSettings parity;
  parity.fill = FillMode::Solid;
  parity.solidRule = SolidRule::Parity;
  const Mesh closedBox = boxMesh({2.5, 2.5, 2.5}, {9.5, 9.5, 9.5});
  const Scene closedS = voxelizeMesh(closedBox, std::vector<uint8_t>(closedBox.triangles.size(), 1), gridHeader(12), parity);
  const Scene openS = voxelizeMesh(open, std::vector<uint8_t>(open.triangles.size(), 1), gridHeader(12), parity);
  // The voxels the missing face would have made surface become interior: the
  // same voxels are occupied.
  EXPECT_EQ(occupied(openS), occupied(closedS));
  // A sphere with an inward-facing sphere inside: a hollow shell.
  Mesh shell = sphereMesh({16, 16, 16}, 12, 64);
  shell.append(sphereMesh({16, 16, 16}, 6, 64, true));
  const Scene hollow = run(shell, gridHeader(32), FillMode::Solid);
  std::vector<ClassVotes> tmp;
  EXPECT_FALSE(hollow.voxel({16, 16, 16}, tmp)) << "the cavity must stay empty";
  EXPECT_TRUE(hollow.voxel({16, 16, 25}, tmp)) << "the shell is filled";
  // Both spheres facing out (nested parts): all filled.
  Mesh nested = sphereMesh({16, 16, 16}, 12, 64);
  nested.append(sphereMesh({16, 16, 16}, 6, 64));
  EXPECT_TRUE(run(nested, gridHeader(32), FillMode::Solid).voxel({16, 16, 16}, tmp));
}

TEST(Voxelize, InteriorTakesTheEnclosingClass) {
  // Both windings: a part with inverted winding is entered where |winding| rises.
  for (bool inverted : {false, true}) {
    Mesh m = boxMesh({1.5, 1.5, 1.5}, {10.5, 10.5, 10.5}, inverted);
    m.append(boxMesh({4.5, 4.5, 4.5}, {7.5, 7.5, 7.5}, inverted));
    std::vector<uint8_t> cls(m.triangles.size(), 1);
    for (size_t i = 12; i < cls.size(); ++i) cls[i] = 2;
    VoxelizeSettings st;
    st.fill = FillMode::Solid;
    const Scene s = voxelizeMesh(m, cls, gridHeader(12), st);
    std::vector<ClassVotes> tmp;
    auto at = [&](int u, int v, int w) { return s.voxel({u, v, w}, tmp)->votes[0].classId; };
    EXPECT_EQ(at(6, 6, 6), 2) << "inside the inner box, inverted " << inverted;
    EXPECT_EQ(at(3, 3, 3), 1) << "inside the outer box only, inverted " << inverted;
    EXPECT_EQ(at(9, 5, 6), 1) << "inside the outer box only, inverted " << inverted;
    EXPECT_EQ(s.voxel({6, 6, 6}, tmp)->votes[0].votes, kInteriorVotes);
  }
}

TEST(Voxelize, VotesAreAreaInSubvoxelUnits) {
  // A unit square in the middle of voxel (2, 2, 2), parallel to the xy plane.
  const Mesh m = meshOf({{2, 2, 2.5}, {3, 2, 2.5}, {3, 3, 2.5}, {2, 3, 2.5}}, {{0, 1, 2}, {0, 2, 3}});
  const Scene s = run(m, gridHeader(6), FillMode::Surface);
  std::vector<ClassVotes> tmp;
  auto v = s.voxel({2, 2, 2}, tmp);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->votes[0].votes, 65536u) << "two half-squares, 32768 each";
  // Its neighbours across the square's edges are touched with zero area: 1 vote per triangle.
  auto e = s.voxel({1, 2, 2}, tmp);
  ASSERT_TRUE(e);
  EXPECT_GE(e->votes[0].votes, 1u);
  EXPECT_LE(e->votes[0].votes, 2u);
}

TEST(Voxelize, DeterministicAcrossThreadsAndFarFromTheOrigin) {
  const double off = 1e6;
  const SceneHeader h = gridHeader(64, 0.001, {off, off, off});
  Mesh m = sphereMesh({off + 0.032, off + 0.0311, off + 0.0323}, 0.025, 80);
  const Scene a = run(m, h, FillMode::Solid, 1), b = run(m, h, FillMode::Solid, 2), c = run(m, h, FillMode::Solid, 5);
  EXPECT_TRUE(compareScenes(a, b).same());
  EXPECT_TRUE(compareScenes(a, c).same());
  EXPECT_GT(a.occupiedCount(), 40000u) << "millimetre features a million units from the origin";
}

TEST(Voxelize, ClipsOrRefusesFarVerticesAndRefusesNonFiniteOnes) {
  // A segment from the grid to 3e6 voxels away: a surface fill clips it near
  // the grid (voxels (0..3, 0, 0)); a solid fill refuses it (test_voxelize_far.cpp).
  const Mesh far = meshOf({{0, 0, 0}, {1, 0, 0}, {3e6, 0, 0}}, {{0, 1, 2}});
  EXPECT_EQ(occupied(run(far, gridHeader(4), FillMode::Surface)),
            (std::set<std::tuple<int, int, int>>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}));
  EXPECT_TRUE(voxtest::throwsVoxError([&] { run(far, gridHeader(4), FillMode::Solid); }, ErrorKind::BadInput,
                                      {"vertex 3 (counted from 1)", "fill only the surface"}));
  EXPECT_EQ(voxtest::settingOfError([&] { run(far, gridHeader(4), FillMode::Solid); }), Setting::FillMode);
  const Mesh nan = meshOf({{0, 0, 0}, {1, 0, NAN}, {0, 1, 0}}, {{0, 1, 2}});
  EXPECT_TRUE(voxtest::throwsVoxError([&] { run(nan, gridHeader(4), FillMode::Surface); }, ErrorKind::BadInput,
                                      {"vertex 2 (counted from 1)", "non-finite"}));
  EXPECT_EQ(voxtest::settingOfError([&] { run(nan, gridHeader(4), FillMode::Surface); }), Setting::DropInvalid);
  const Scene empty = run(meshOf({}, {}), gridHeader(4), FillMode::Solid);
  EXPECT_EQ(empty.occupiedCount(), 0u);
}

TEST(VoxelizeCheck, OracleAgreesAndVolumeIsMeasured) {
  const Mesh m = sphereMesh({16.2, 15.9, 16.1}, 11.3, 64);
  const Scene surf = run(m, gridHeader(32), FillMode::Surface, 2);
  const SurfaceCheck c = checkSurface(m, surf, 1u << 30);
  EXPECT_EQ(c.missed, 0u);
  ASSERT_TRUE(c.extra);
  EXPECT_EQ(*c.extra, 0u);
  EXPECT_EQ(c.oracleVoxels, surf.occupiedCount());
  // A sample cannot attribute extras.
  const SurfaceCheck sampled = checkSurface(m, surf, 100);
  EXPECT_FALSE(sampled.extra);
  EXPECT_EQ(sampled.missed, 0u);
  const Scene solid = run(m, gridHeader(32), FillMode::Solid, 2);
  const SolidCheck s = checkSolid(m, solid, 4000);
  EXPECT_NEAR(s.meshVolume, 4.0 / 3.0 * M_PI * std::pow(11.3, 3), 0.03 * 4.0 / 3.0 * M_PI * std::pow(11.3, 3));
  EXPECT_GT(s.relativeVolumeError, 0.0) << "conservative surface voxels add volume";
  EXPECT_EQ(s.iou, 1.0) << "interior (non-surface) centres agree with the winding number on a closed mesh";
  EXPECT_GT(s.samples, 1500u) << "interior centres only: surface voxels are left out";
  // Winding number: 1 inside, 0 outside, -1 inside an inverted mesh.
  EXPECT_NEAR(windingNumber(m, {16, 16, 16}), 1.0, 1e-9);
  EXPECT_NEAR(windingNumber(m, {40, 16, 16}), 0.0, 1e-9);
  EXPECT_NEAR(windingNumber(sphereMesh({16.2, 15.9, 16.1}, 11.3, 64, true), {16, 16, 16}), -1.0, 1e-9);
}

TEST(Voxelize, CheckReferenceInDoubleIsTheLongDoubleOne) {
  // A sphere with its top cut away: w runs continuously through 0.5 across
  // the hole, so many points sit near the threshold where double and long
  // double could disagree. insideByWinding must answer as the long double sum.
  Mesh m = sphereMesh({16.2, 15.9, 16.1}, 11.3, 48);
  std::vector<std::array<uint32_t, 3>> kept;
  for (const auto& t : m.triangles) {
    double z = 0;
    for (uint32_t v : t) z += m.positions[v][2] / 3;
    if (z < 22.0) kept.push_back(t);
  }
  m.triangles = kept;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> xy(3, 29), zr(10, 32);
  int nearHalf = 0;
  for (int i = 0; i < 4000; ++i) {
    const std::array<double, 3> p{xy(rng), xy(rng), zr(rng)};
    const double w = windingNumber(m, p);
    nearHalf += std::abs(std::abs(w) - 0.5) < 0.05;
    ASSERT_EQ(insideByWinding(m, p), std::abs(w) > 0.5) << p[0] << " " << p[1] << " " << p[2] << " w " << w;
  }
  EXPECT_GT(nearHalf, 20) << "the sample reaches the 0.5 level across the hole";
}

TEST(Voxelize, ColourFromTextureFactorAndVertexColours) {
  // A 2 x 2 unit square at z = 0.5 over voxels (0..1, 0..1, 0), textured with a
  // 2 x 2 nearest-filtered texture: each voxel sees one texel.
  Mesh m = meshOf({{0, 0, 0.5}, {2, 0, 0.5}, {2, 2, 0.5}, {0, 2, 0.5}}, {{0, 1, 2}, {0, 2, 3}});
  m.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};  // glTF: t = 0 is the top row
  m.textures.push_back(voxtest::quadrantTexture());  // top row: red, green; bottom row: blue, sRGB 188 grey
  m.materials[0].texture = 0;
  m.materials[0].baseColorFactor = {1, 1, 0.5f, 1};
  SceneHeader h = gridHeader(2);
  h.dims = {2, 2, 1};
  const Scene s = run(m, h, FillMode::Surface);
  ASSERT_TRUE(s.hasColor());
  std::vector<ClassVotes> tmp;
  auto col = [&](int u, int v) { return *s.voxel({u, v, 0}, tmp)->color; };
  // Voxel (0, 1) is the top-left texel (v grows with t decreasing... uv (0,0) at world y = 2).
  EXPECT_NEAR(col(0, 1).r, 1.0f, 1e-4);
  EXPECT_NEAR(col(0, 1).g, 0.0f, 1e-4);
  EXPECT_NEAR(col(1, 1).g, 1.0f, 1e-4);
  EXPECT_NEAR(col(0, 0).b, 0.5f, 1e-4) << "blue texel x factor 0.5";
  EXPECT_NEAR(col(1, 0).r, 0.50289f, 1e-3) << "sRGB 188 decodes to linear 0.5029";
  EXPECT_NEAR(col(1, 0).b, 0.5f * 0.50289f, 1e-3);
  // A material that places its texture (an MTL map's -o 0.5 0): s' = s + 0.5,
  // so each voxel takes the texel beside its own (the texture repeats).
  Mesh moved = m;
  moved.materials[0].uvTransform = {1, 0, 0.5, 0, 1, 0};
  const Scene sm = run(moved, h, FillMode::Surface);
  auto movedCol = [&](int u, int v) { return *sm.voxel({u, v, 0}, tmp)->color; };
  EXPECT_NEAR(movedCol(0, 1).g, 1.0f, 1e-4) << "the green texel, left of red's place";
  EXPECT_NEAR(movedCol(1, 1).r, 1.0f, 1e-4) << "red, wrapped round";
  EXPECT_NEAR(movedCol(0, 0).r, 0.50289f, 1e-3) << "the grey texel";
  // A texture coordinate that is not a number (a glTF may hold one) samples
  // nothing: the pieces take the base colour alone.
  Mesh nanUv = m;
  nanUv.uv0[2] = {std::numeric_limits<float>::quiet_NaN(), 0};
  const Scene sn = run(nanUv, h, FillMode::Surface);
  const RgbLinear base = *sn.voxel({1, 1, 0}, tmp)->color;  // the piece of triangle 0, 1, 2 there
  EXPECT_NEAR(base.r, 1.0f, 1e-4);
  EXPECT_NEAR(base.g, 1.0f, 1e-4);
  EXPECT_NEAR(base.b, 0.5f, 1e-4) << "the factor alone";
  // Vertex colours alone: interpolated, averaged by area.
  Mesh vc = meshOf({{0, 0, 0.5}, {2, 0, 0.5}, {2, 2, 0.5}, {0, 2, 0.5}}, {{0, 1, 2}, {0, 2, 3}});
  vc.colors = {{0, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}, {0, 0, 0, 1}};
  const Scene sv = run(vc, h, FillMode::Surface);
  std::vector<ClassVotes> t2;
  EXPECT_LT(sv.voxel({0, 0, 0}, t2)->color->r, 0.5f);
  EXPECT_GT(sv.voxel({1, 0, 0}, t2)->color->r, 0.5f);
  // Interior voxels carry no colour.
  Mesh box = boxMesh({0.5, 0.5, 0.5}, {5.5, 5.5, 5.5});
  box.materials[0].baseColorFactor = {0.2f, 0.4f, 0.6f, 1};
  const Scene sb = run(box, gridHeader(6), FillMode::Solid);
  EXPECT_FALSE(sb.voxel({3, 3, 3}, t2)->color.has_value());
  EXPECT_NEAR(sb.voxel({0, 0, 0}, t2)->color->g, 0.4f, 1e-4);
}

TEST(VoxelizeSdf, AgreesWithTheExactMethodUpToAShell) {
  const Mesh m = sphereMesh({16.2, 15.9, 16.1}, 11.3, 64);
  VoxelizeSettings st;
  st.fill = FillMode::Solid;
  const Scene exact = voxelizeMesh(m, std::vector<uint8_t>(m.triangles.size(), 1), gridHeader(32), st);
  const Scene sdf = voxelizeMeshSdf(m, std::vector<uint8_t>(m.triangles.size(), 1), gridHeader(32), st);
  const auto a = occupied(exact), b = occupied(sdf);
  size_t both = 0;
  for (const auto& k : a) both += b.count(k);
  const double iou = double(both) / double(a.size() + b.size() - both);
  EXPECT_GT(iou, 0.9);
  std::vector<ClassVotes> tmp;
  EXPECT_TRUE(sdf.voxel({16, 16, 16}, tmp)) << "the centre is inside";
  EXPECT_FALSE(sdf.voxel({0, 0, 0}, tmp));
}
