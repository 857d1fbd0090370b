// The hierarchical winding-number solid fill (libvox/mesh/winding_number.h
// CapField::ballField, libvox/mesh/voxelize.cpp WindingTile) on grids larger
// than one 32^3 tile, with many holes like a scan's: the block bounds decide
// exactly what per-voxel evaluation would (checked against the brute-force
// oracle, long double over every triangle, on a lattice of centres), and the
// result does not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <random>

#include "libvox/mesh/winding_number.h"
#include "libvox/scene/voxelize_check.h"
#include "libvox/scene/voxelize_scene.h"

using namespace vox;

namespace {

SceneHeader header(uint32_t n) {
  SceneHeader h;
  h.dims = {n, n, n};
  h.voxelSize = 1.0;
  h.origin = {0, 0, 0};
  h.classes.add({1, "a", {255, 0, 0}, std::nullopt});
  h.classes.add({2, "b", {0, 255, 0}, std::nullopt});
  return h;
}

Mesh meshOf(std::vector<std::array<double, 3>> pos, std::vector<std::array<uint32_t, 3>> tris) {
  Mesh m;
  m.positions = std::move(pos);
  m.triangles = std::move(tris);
  m.triangleMaterial.assign(m.triangles.size(), 0);
  m.trianglePart.assign(m.triangles.size(), 0);
  m.materials.push_back({});
  m.parts.push_back({"part", "mesh"});
  return m;
}

/// UV sphere, outward normals, without the triangles whose centre (theta, phi) `keep` rejects.
template <class Keep>
Mesh sphere(std::array<double, 3> c, double r, int slices, Keep keep) {
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
      if (!keep(M_PI * (i + 0.5) / stacks, 2 * M_PI * (j + 0.5) / slices)) continue;
      t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return meshOf(p, t);
}

/// A sphere with nine holes of different sizes, like a scan's open patches.
Mesh holeySphere(double r, int slices) {
  return sphere({48.3, 47.9, 48.1}, r, slices, [](double th, double ph) {
    for (int h = 0; h < 9; ++h) {
      const double ht = 0.4 + 0.29 * h, hp = 0.7 * h + 0.3, size = 0.12 + 0.05 * (h % 4);
      if (std::abs(th - ht) < size && std::abs(std::remainder(ph - hp, 2 * M_PI)) < size * 1.5) return false;
    }
    return true;
  });
}

/// Box [lo, hi], outward normals, without its top (+z) face.
Mesh openBox(std::array<double, 3> lo, std::array<double, 3> hi) {
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 8; ++i) p.push_back({i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  return meshOf(p, {{0, 2, 1}, {1, 2, 3}, {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}});
}

Scene solid(const Mesh& m, uint32_t n, unsigned threads) {
  VoxelizeSettings s;
  s.fill = FillMode::Solid;
  s.solidRule = SolidRule::Winding;
  s.threads = threads;
  std::vector<uint8_t> cls(m.triangles.size());
  for (size_t t = 0; t < cls.size(); ++t) cls[t] = uint8_t(1 + t % 2);
  return voxelizeMesh(m, cls, header(n), s);
}

/// Non-surface voxel centres on a lattice of the given stride against the oracle.
void expectExact(const char* name, const Mesh& m, uint32_t n, int stride) {
  const Scene s = solid(m, n, 2);
  uint64_t inside = 0, missed = 0, extra = 0, samples = 0;
  std::vector<ClassVotes> tmp;
  for (int32_t u = 1; u < int32_t(n); u += stride)
    for (int32_t v = 1; v < int32_t(n); v += stride)
      for (int32_t w = 1; w < int32_t(n); w += stride) {
        const auto vox = s.voxel({u, v, w}, tmp);
        if (vox && vox->surface) continue;
        const bool in = std::abs(windingNumber(m, {u + 0.5, v + 0.5, w + 0.5})) > 0.5;
        ++samples;
        inside += in;
        missed += in && !vox;
        extra += !in && vox;
      }
  std::printf("  %-16s %llu samples, %llu inside: missed %llu, extra %llu\n", name, (unsigned long long)samples,
              (unsigned long long)inside, (unsigned long long)missed, (unsigned long long)extra);
  EXPECT_GT(inside, 1000u) << name;
  EXPECT_EQ(missed, 0u) << name;
  EXPECT_EQ(extra, 0u) << name;
}

}  // namespace

TEST(FastWinding, ManyHolesAgreeWithTheOracle) {
  expectExact("nine holes", holeySphere(40.2, 40), 96, 4);
  expectExact("cracked sphere", sphere({48.3, 47.9, 48.1}, 40.2, 40, [](double, double ph) { return ph > 0.2; }), 96, 4);
  expectExact("open-topped box", openBox({10.3, 12.2, 8.7}, {83.6, 80.1, 86.4}), 96, 4);
}

TEST(FastWinding, SameAtAnyThreadCount) {
  const Mesh m = holeySphere(40.2, 48);
  const Scene a = solid(m, 100, 1), b = solid(m, 100, 2), c = solid(m, 100, 3);
  ASSERT_EQ(a.occupiedCount(), b.occupiedCount());
  ASSERT_EQ(a.occupiedCount(), c.occupiedCount());
  ASSERT_GT(a.occupiedCount(), a.surfaceCount() * 5);  // the interior is there
  std::vector<ClassVotes> ta, tb, tc;
  a.forEachVoxel([&](const VoxelView& v) {
    const auto w = b.voxel(v.at, tb), x = c.voxel(v.at, tc);
    ASSERT_TRUE(w.has_value() && x.has_value());
    EXPECT_EQ(w->surface, v.surface);
    EXPECT_EQ(x->surface, v.surface);
    EXPECT_EQ(w->totalVotes(), v.totalVotes());
    EXPECT_EQ(x->totalVotes(), v.totalVotes());
    ASSERT_EQ(v.votes.size(), w->votes.size());
    ASSERT_EQ(v.votes.size(), x->votes.size());
    for (size_t i = 0; i < v.votes.size(); ++i) {
      EXPECT_EQ(v.votes[i], w->votes[i]);
      EXPECT_EQ(v.votes[i], x->votes[i]);
    }
  });
}

namespace {

/// mesh + caps has no boundary: its winding number is an integer off it.
void expectCapsClose(const Mesh& m, const char* name) {
  std::vector<LatticePoint> lattice;
  for (const auto& p : m.positions) lattice.push_back({std::llround(p[0] * 65536), std::llround(p[1] * 65536), std::llround(p[2] * 65536)});
  const std::vector<CapTriangle> caps = capBoundaryLoops(m.triangles, lattice);
  ASSERT_FALSE(caps.empty()) << name;
  const CapField field(caps);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(0, 32);
  for (int i = 0; i < 300; ++i) {
    const double p[3] = {d(rng), d(rng), d(rng)};
    const double w = windingNumber(m, {p[0], p[1], p[2]}) + field.winding(p);
    EXPECT_NEAR(w, std::round(w), 1e-4) << name << " at " << p[0] << " " << p[1] << " " << p[2];
  }
}

/// A 4 x 4 grid of unit-ish cells in the plane z = 15.3 (tilted a little),
/// without the cells `holes` (row-major): a sheet whose holes may share a vertex.
Mesh sheetWithHoles(std::initializer_list<int> holes) {
  std::vector<std::array<double, 3>> p;
  std::vector<std::array<uint32_t, 3>> t;
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) p.push_back({4.1 + 6.0 * i, 3.9 + 6.0 * j, 15.3 + 0.11 * i + 0.07 * j});
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      if (std::find(holes.begin(), holes.end(), j * 4 + i) != holes.end()) continue;
      const uint32_t a = uint32_t(j * 5 + i), b = a + 1, c = a + 5, d = a + 6;
      t.push_back({a, b, d}), t.push_back({a, d, c});
    }
  return meshOf(p, t);
}

}  // namespace

TEST(FastWinding, CapsCloseWalksThroughSharedVertices) {
  // Two holes touching at one vertex (the boundary visits it twice), a
  // doubled open box (every boundary edge twice), and a mesh with many holes.
  expectCapsClose(sheetWithHoles({5, 10}), "holes sharing a vertex");
  Mesh twice = openBox({4.3, 5.2, 3.7}, {27.6, 25.1, 26.4});
  const size_t n = twice.triangles.size();
  for (size_t t = 0; t < n; ++t) twice.triangles.push_back(twice.triangles[t]);
  twice = meshOf(twice.positions, twice.triangles);
  expectCapsClose(twice, "doubled open box");
  expectCapsClose(sphere({16.2, 15.9, 16.1}, 12.3, 40, [](double th, double ph) {
                    return !(std::abs(th - 1.2) < 0.3 && std::abs(ph - 2) < 0.3) && !(std::abs(th - 1.9) < 0.2) && th > 0.3;
                  }),
                  "sphere with a band and holes");
}

TEST(FastWinding, DoubledOpenBoxCountsTwice) {
  // Every triangle twice: w = 2 inside, and the caps' walks cover each
  // boundary edge twice; against the oracle at every centre of a 40^3 grid.
  Mesh twice = openBox({4.3, 5.2, 3.7}, {33.6, 31.1, 30.4});
  const size_t n = twice.triangles.size();
  for (size_t t = 0; t < n; ++t) twice.triangles.push_back(twice.triangles[t]);
  twice = meshOf(twice.positions, twice.triangles);
  expectExact("doubled open box", twice, 40, 1);
}
