// --fill solid by the generalised winding number (libvox/mesh/winding_number.h)
// against the brute-force oracle (solid angles over every triangle, long double)
// at every voxel centre of small grids: open meshes (holes, a crack, an
// open-topped box, a sheet) and closed ones (self-intersecting, nested,
// inverted), fuzzed and random open soups whose caps pass through centres;
// the caps close the boundary, also across unwelded seams and at centres on
// a cap; the caps' ball bound holds; the result does not depend on the
// thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <random>
#include <string>

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

/// Appends `b` to `a` (one mesh with both parts).
Mesh join(Mesh a, const Mesh& b) {
  const uint32_t off = uint32_t(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
  return meshOf(a.positions, a.triangles);
}

/// UV sphere, outward normals; `keep(theta, phi)` of a triangle's first corner drops it when false.
template <class Keep>
Mesh sphere(std::array<double, 3> c, double r, int slices, bool inverted, Keep keep) {
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
      std::array<uint32_t, 3> a{id(i, j), id(i + 1, j), id(i + 1, j + 1)}, b{id(i, j), id(i + 1, j + 1), id(i, j + 1)};
      if (inverted) std::swap(a[1], a[2]), std::swap(b[1], b[2]);
      t.push_back(a), t.push_back(b);
    }
  return meshOf(p, t);
}
Mesh sphere(std::array<double, 3> c, double r, int slices, bool inverted = false) {
  return sphere(c, r, slices, inverted, [](double, double) { return true; });
}

/// Box [lo, hi], outward normals; without its top (+z) face when `openTop`.
Mesh box(std::array<double, 3> lo, std::array<double, 3> hi, bool openTop = false) {
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 8; ++i) p.push_back({i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  std::vector<std::array<uint32_t, 3>> t = {{0, 2, 1}, {1, 2, 3}, {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                            {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  if (!openTop) t.push_back({4, 5, 6}), t.push_back({5, 7, 6});
  return meshOf(p, t);
}

Scene solid(const Mesh& m, uint32_t n, SolidRule rule, unsigned threads = 1) {
  VoxelizeSettings s;
  s.fill = FillMode::Solid;
  s.solidRule = rule;
  s.threads = threads;
  return voxelizeMesh(m, std::vector<uint8_t>(m.triangles.size(), 1), header(n), s);
}

struct Agreement {
  uint64_t interior = 0, both = 0, missed = 0, extra = 0;
  double iou() const { return both + missed + extra ? double(both) / double(both + missed + extra) : 1.0; }
};

/// Every non-surface voxel centre of the grid against the brute-force oracle.
Agreement compare(const Mesh& m, const Scene& s, uint32_t n) {
  Agreement a;
  std::vector<ClassVotes> tmp;
  for (int32_t u = 0; u < int32_t(n); ++u)
    for (int32_t v = 0; v < int32_t(n); ++v)
      for (int32_t w = 0; w < int32_t(n); ++w) {
        const auto vox = s.voxel({u, v, w}, tmp);
        if (vox && vox->surface) continue;
        const bool inside = std::abs(windingNumber(m, {u + 0.5, v + 0.5, w + 0.5})) > 0.5;
        a.interior += inside;
        a.both += inside && vox;
        a.missed += inside && !vox;
        a.extra += !inside && vox;
      }
  return a;
}

void expectIou(const char* name, const Mesh& m, uint32_t n, double target) {
  const Agreement a = compare(m, solid(m, n, SolidRule::Winding), n);
  std::printf("  %-22s winding IoU %.6f (missed %llu, extra %llu of %llu inside)\n", name, a.iou(),
              (unsigned long long)a.missed, (unsigned long long)a.extra, (unsigned long long)a.interior);
  if (target >= 1.0) {
    EXPECT_EQ(a.missed, 0u) << name;
    EXPECT_EQ(a.extra, 0u) << name;
  } else {
    EXPECT_GE(a.iou(), target) << name;
  }
}

constexpr uint32_t kN = 32;

/// A closed sphere cut into three bands along two latitudes, each band with
/// vertices of its own and a radius larger by 2e-4 than the one above, so the
/// seams are not welded: two pairs of rims side by side, 1e-3 voxel apart,
/// running in opposite directions (as in meshes exported patch by patch).
Mesh seamedSphere() {
  const std::array<double, 3> c{16.2, 15.9, 16.1};
  const Mesh top = sphere(c, 12.3, 40, false, [](double th, double) { return th < 1.0; });
  const Mesh middle = sphere(c, 12.3 * (1 + 2e-4), 40, false, [](double th, double) { return th >= 1.0 && th < 2.0; });
  const Mesh bottom = sphere(c, 12.3 * (1 + 4e-4), 40, false, [](double th, double) { return th >= 2.0; });
  return join(join(top, middle), bottom);
}

std::vector<LatticePoint> latticeOf(const Mesh& m) {
  std::vector<LatticePoint> lattice;
  for (const auto& p : m.positions) lattice.push_back({std::llround(p[0] * 65536), std::llround(p[1] * 65536), std::llround(p[2] * 65536)});
  return lattice;
}

}  // namespace

TEST(Winding, UnweldedSeamsAreZipped) {
  // The seams' four rims are joined into one walk and capped across the 1e-3
  // voxel gaps, not by four caps as large as the sphere's cross-sections.
  const Mesh m = seamedSphere();
  const std::vector<CapTriangle> caps = capBoundaryLoops(m.triangles, latticeOf(m));
  ASSERT_FALSE(caps.empty());
  const CapField field(caps);
  // reach = sqrt(area / 2pi). Zipped: two strips ~65 voxels long, ~2.5e-3
  // wide, 0.32 voxels^2 (reach 0.23); four separate caps: ~1400 (reach ~15).
  EXPECT_LT(field.reach(), 0.5);
  EXPECT_EQ(CapField::reachOf(caps), field.reach());  // the fill grows its box by this one, bit for bit
  // mesh + caps is still closed: an integer winding number everywhere off it.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(0, 32);
  for (int i = 0; i < 200; ++i) {
    const double p[3] = {d(rng), d(rng), d(rng)};
    const double w = windingNumber(m, {p[0], p[1], p[2]}) + field.winding(p);
    EXPECT_NEAR(w, std::round(w), 1e-4) << p[0] << " " << p[1] << " " << p[2];
  }
  // The solid fill is the closed sphere's.
  expectIou("seamed sphere", m, kN, 1.0);
}

/// `m` as a soup: every triangle with corners of its own, each moved by up to
/// `noise` voxels on every axis (a deterministic hash, not a generator): the
/// float noise of a mesh written from transformed coordinates.
Mesh noisySoup(const Mesh& m, double noise) {
  Mesh out;
  uint64_t h = 0x9e3779b97f4a7c15ull;
  auto next = [&] {
    h ^= h >> 31, h *= 0xbf58476d1ce4e5b9ull, h ^= h >> 29;
    return double(h >> 11) / double(uint64_t(1) << 53) * 2 - 1;  // [-1, 1)
  };
  for (const auto& t : m.triangles) {
    const uint32_t base = uint32_t(out.positions.size());
    for (uint32_t v : t) {
      auto p = m.positions[v];
      for (double& c : p) c += noise * next();
      out.positions.push_back(p);
    }
    out.triangles.push_back({base, base + 1, base + 2});
  }
  return out;
}

TEST(Winding, FloatNoiseSoupIsWelded) {
  // Corners 1e-4 voxel apart (about 7 lattice steps, so no two are equal on
  // the lattice): without the weld every triangle is a loop of its own.
  const Mesh m = noisySoup(sphere({16.2, 15.9, 16.1}, 12.3, 24), 1e-4);
  const std::vector<LatticePoint> raw = latticeOf(m);
  EXPECT_GT(capBoundaryLoops(m.triangles, raw).size(), m.triangles.size() / 2);
  const std::vector<LatticePoint> welded = weldNearVertices(raw, kWeldSteps);
  ASSERT_EQ(welded.size(), raw.size());
  EXPECT_TRUE(capBoundaryLoops(m.triangles, welded).empty()) << "welded, the soup is the closed sphere";
  for (size_t v = 0; v < raw.size(); ++v)
    for (int k = 0; k < 3; ++k) ASSERT_LE(std::abs(welded[v][k] - raw[v][k]), 4 * kWeldSteps);
  // The solid fill is the oracle's on the soup itself.
  expectIou("float-noise soup", m, kN, 1.0);
}

TEST(Winding, WeldKeepsDistantAndChainedVerticesApart) {
  const int64_t s = kWeldSteps;
  // Nothing within reach: nothing moves.
  EXPECT_TRUE(weldNearVertices({{0, 0, 0}, {s + 1, 0, 0}, {0, 0, 5 * s}}, s).empty());
  // A pair within reach moves onto its first member; a third point apart stays.
  const auto pair = weldNearVertices({{100, 0, 0}, {100 + s, -s, 3}, {0, 10 * s, 0}}, s);
  ASSERT_EQ(pair.size(), 3u);
  EXPECT_EQ(pair[0], (LatticePoint{100, 0, 0}));
  EXPECT_EQ(pair[1], (LatticePoint{100, 0, 0}));
  EXPECT_EQ(pair[2], (LatticePoint{0, 10 * s, 0}));
  // A chain of near points wider than 4 x reach is left as it is (a fine mesh
  // at a coarse resolution, not noise).
  std::vector<LatticePoint> chain;
  for (int64_t i = 0; i < 8; ++i) chain.push_back({i * s, 0, 0});
  EXPECT_TRUE(weldNearVertices(chain, s).empty());
  // Negative coordinates weld the same way across zero.
  const auto across = weldNearVertices({{-3, -3, -3}, {2, 2, 2}}, s);
  ASSERT_EQ(across.size(), 2u);
  EXPECT_EQ(across[1], (LatticePoint{-3, -3, -3}));
}

TEST(Winding, SphereWithHolesPunched) {
  const Mesh m = sphere({16.2, 15.9, 16.1}, 12.3, 40, false, [](double th, double ph) {
    return !(th < 0.5) && !(std::abs(th - M_PI / 2) < 0.35 && std::abs(ph - 1.0) < 0.4) && !(th > 2.7);
  });
  expectIou("sphere with 3 holes", m, kN, 1.0);
}

TEST(Winding, CrackedSphere) {
  const Mesh m = sphere({16.2, 15.9, 16.1}, 12.3, 40, false, [](double, double ph) { return ph > 0.2; });
  expectIou("cracked sphere", m, kN, 1.0);
}

TEST(Winding, OpenToppedBox) { expectIou("open-topped box", box({4.3, 5.2, 3.7}, {27.6, 25.1, 26.4}, true), kN, 1.0); }

TEST(Winding, SingleSheetHasNoInterior) {
  const Mesh m = meshOf({{3.3, 4.1, 15.2}, {28.2, 4.4, 16.3}, {27.7, 27.9, 15.7}, {4.2, 28.1, 16.9}}, {{0, 1, 2}, {0, 2, 3}});
  const Scene s = solid(m, kN, SolidRule::Winding);
  EXPECT_EQ(s.occupiedCount(), s.surfaceCount());
  expectIou("single sheet", m, kN, 1.0);
}

TEST(Winding, ClosedMeshesExact) {
  expectIou("closed sphere", sphere({16.2, 15.9, 16.1}, 12.3, 24), kN, 1.0);
  expectIou("inverted sphere", sphere({16.2, 15.9, 16.1}, 12.3, 24, true), kN, 1.0);
  expectIou("nested spheres", join(sphere({16.2, 15.9, 16.1}, 13.3, 24), sphere({15.8, 16.3, 16.2}, 6.1, 16)), kN, 1.0);
  expectIou("self-intersecting boxes", join(box({3.3, 3.6, 4.2}, {20.1, 19.7, 22.3}), box({12.2, 11.9, 9.4}, {28.3, 27.1, 27.7})),
            kN, 1.0);
}

TEST(Winding, SelfIntersectingOpenParts) {
  const Mesh a = sphere({13.2, 14.9, 16.1}, 10.3, 36, false, [](double th, double) { return th > 0.6; });
  expectIou("open overlapping parts", join(a, box({14.3, 10.2, 6.7}, {28.6, 25.1, 24.4}, true)), kN, 1.0);
}

TEST(Winding, CapsCloseTheBoundary) {
  // mesh + caps is closed: its winding number is an integer at any point off it.
  const Mesh m = sphere({16.2, 15.9, 16.1}, 12.3, 24, false, [](double th, double ph) { return th > 0.7 && ph > 0.4; });
  std::vector<LatticePoint> lattice;
  for (const auto& p : m.positions) lattice.push_back({std::llround(p[0] * 65536), std::llround(p[1] * 65536), std::llround(p[2] * 65536)});
  const std::vector<CapTriangle> caps = capBoundaryLoops(m.triangles, lattice);
  ASSERT_FALSE(caps.empty());
  const CapField field(caps);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(0, 32);
  for (int i = 0; i < 200; ++i) {
    const double p[3] = {d(rng), d(rng), d(rng)};
    const double w = windingNumber(m, {p[0], p[1], p[2]}) + field.winding(p);
    EXPECT_NEAR(w, std::round(w), 1e-4)  // the caps are on the snapped lattice
    << p[0] << " " << p[1] << " " << p[2];
  }
  // A closed mesh has no caps, also as a soup (every triangle its own vertices).
  const Mesh closed = sphere({16.2, 15.9, 16.1}, 12.3, 24);
  std::vector<std::array<uint32_t, 3>> soup;
  std::vector<LatticePoint> soupLattice;
  for (const auto& t : closed.triangles) {
    for (uint32_t v : t) {
      const auto& p = closed.positions[v];
      soupLattice.push_back({std::llround(p[0] * 65536), std::llround(p[1] * 65536), std::llround(p[2] * 65536)});
    }
    const uint32_t f = uint32_t(soupLattice.size() - 3);
    soup.push_back({f, f + 1, f + 2});
  }
  EXPECT_TRUE(capBoundaryLoops(soup, soupLattice).empty());
}

/// CapField::ballField's bounds, jump counts and magnitude (and
/// CapField::magnitudeBound) against exact evaluation at random points of
/// random balls, near and far from the holes' rims and cutting through the caps.
void expectBallBoundHolds(const Mesh& m, unsigned seed, double radius, int& checked, int& cutting, int& clustered,
                          int& nearRim, int& small) {
  std::vector<LatticePoint> lattice;
  for (const auto& p : m.positions) lattice.push_back({std::llround(p[0] * 65536), std::llround(p[1] * 65536), std::llround(p[2] * 65536)});
  const std::vector<CapTriangle> caps = capBoundaryLoops(m.triangles, lattice);
  const CapField field(caps);
  ASSERT_FALSE(field.empty());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-10, 42), unit(-1, 1), u01(0, 1);
  CapField::Ball ball;
  for (int b = 0; b < 800; ++b) {
    double c[3] = {d(rng), d(rng), d(rng)};
    if (b % 2) {  // every other ball centred near a random point of a random cap
      const CapTriangle& t = caps[rng() % caps.size()];
      double x = u01(rng), y = u01(rng);
      if (x + y > 1) x = 1 - x, y = 1 - y;
      for (int k = 0; k < 3; ++k)
        c[k] = (double(t.v[0][k]) + x * double(t.v[1][k] - t.v[0][k]) + y * double(t.v[2][k] - t.v[0][k])) / 65536 +
               unit(rng) * radius;
    }
    if (!field.ballField(c, radius, ball)) continue;
    const double magnitude = field.magnitudeBound(c, radius, 1e9);
    cutting += !ball.cut.empty();
    nearRim += !ball.rimsClear;
    clustered += ball.valueError > 0 && ball.gradientError > 0;
    for (int i = 0; i < 20; ++i) {
      double q[3];
      do {
        for (double& x : q) x = unit(rng) * radius;
      } while (std::hypot(q[0], q[1], q[2]) > radius);
      const double p[3] = {c[0] + q[0], c[1] + q[1], c[2] + q[2]};
      int jump = 0;
      if (!field.jumps(ball, p, jump)) continue;
      const double exact = field.winding(p), dist = std::hypot(q[0], q[1], q[2]);
      EXPECT_LE(std::abs(exact), ball.magnitude) << p[0] << " " << p[1] << " " << p[2];
      EXPECT_LE(std::abs(exact), magnitude) << p[0] << " " << p[1] << " " << p[2];
      small += magnitude < 0.5;
      const double linear = ball.value + jump + ball.gradient[0] * q[0] + ball.gradient[1] * q[1] + ball.gradient[2] * q[2];
      EXPECT_LE(std::abs(exact - ball.value - jump), ball.slope * dist + ball.valueError + ball.slack)
          << p[0] << " " << p[1] << " " << p[2];
      EXPECT_LE(std::abs(exact - linear),
                ball.curvature * dist * dist + ball.gradientError * dist + ball.valueError + ball.slack)
          << p[0] << " " << p[1] << " " << p[2];
      ++checked;
    }
    if (b % 50 == 0 && ball.cut.empty()) {  // the gradient against central differences
      const double h = 1e-4;
      for (int k = 0; k < 3; ++k) {
        double a[3] = {c[0], c[1], c[2]}, z[3] = {c[0], c[1], c[2]};
        a[k] += h, z[k] -= h;
        EXPECT_NEAR(ball.gradient[k], (field.winding(a) - field.winding(z)) / (2 * h),
                    ball.gradientError + 1e-6 + 1e-4 * std::abs(ball.gradient[k]));
      }
    }
  }
}

TEST(Winding, BallBoundHolds) {
  int checked = 0, cutting = 0, clustered = 0, nearRim = 0, small = 0;
  // One big hole (a flat-ish cap), a crack (long thin caps), three holes.
  expectBallBoundHolds(sphere({16.2, 15.9, 16.1}, 12.3, 24, false, [](double th, double) { return th > 1.1; }), 11,
                       6.06, checked, cutting, clustered, nearRim, small);
  expectBallBoundHolds(sphere({16.2, 15.9, 16.1}, 12.3, 40, false, [](double, double ph) { return ph > 0.2; }), 12,
                       3.0, checked, cutting, clustered, nearRim, small);
  expectBallBoundHolds(sphere({16.2, 15.9, 16.1}, 12.3, 40, false,
                              [](double th, double ph) {
                                return !(th < 0.5) && !(std::abs(th - M_PI / 2) < 0.35 && std::abs(ph - 1.0) < 0.4) &&
                                       !(th > 2.7);
                              }),
                       13, 1.5, checked, cutting, clustered, nearRim, small);
  // Seams zipped by thin caps: the area bound is the smaller one near them.
  expectBallBoundHolds(seamedSphere(), 14, 2.0, checked, cutting, clustered, nearRim, small);
  std::printf("  %d points checked, %d balls cutting caps, %d with far clusters, %d reaching a rim, %d points under"
              " a magnitude bound < 0.5\n", checked, cutting, clustered, nearRim, small);
  EXPECT_GT(clustered, 100);  // the trees' far-field approximations were exercised
  EXPECT_GT(checked, 10000);
  EXPECT_GT(cutting, 20);  // balls through the caps were exercised
  EXPECT_GT(nearRim, 20);   // and balls reaching a rim (the magnitude bound alone)
  EXPECT_GT(small, 1000);   // and the magnitude bound deciding
}

TEST(Winding, SameAtAnyThreadCount) {
  const Mesh m = join(sphere({16.2, 15.9, 16.1}, 12.3, 40, false, [](double th, double ph) { return th > 0.5 && ph > 0.3; }),
                      box({2.3, 3.2, 5.7}, {12.6, 14.1, 20.4}, true));
  const Scene a = solid(m, kN, SolidRule::Winding, 1), b = solid(m, kN, SolidRule::Winding, 2);
  ASSERT_EQ(a.occupiedCount(), b.occupiedCount());
  std::vector<ClassVotes> ta, tb;
  a.forEachVoxel([&](const VoxelView& v) {
    const auto w = b.voxel(v.at, tb);
    ASSERT_TRUE(w.has_value());
    EXPECT_EQ(w->surface, v.surface);
    EXPECT_EQ(w->totalVotes(), v.totalVotes());
  });
}

// The winding pass reports its progress per tile of columns (it used to stay
// at the surface pass's 0.5 until the end, minutes on a soup), from 0.5 to 1,
// never backwards on one thread; tiles are cut smaller on small boxes so that
// every worker gets several.
TEST(Winding, ProgressAdvancesThroughTheInterior) {
  const Mesh m = join(sphere({16.2, 15.9, 16.1}, 12.3, 40, false, [](double th, double ph) { return th > 0.5 && ph > 0.3; }),
                      box({2.3, 3.2, 5.7}, {12.6, 14.1, 20.4}, true));
  for (unsigned threads : {1u, 3u}) {
    std::mutex lock;
    std::vector<double> seen;
    VoxelizeSettings s;
    s.fill = FillMode::Solid;
    s.threads = threads;
    s.progress = [&](double f) {
      std::lock_guard<std::mutex> hold(lock);
      seen.push_back(f);
    };
    const Scene scene = voxelizeMesh(m, std::vector<uint8_t>(m.triangles.size(), 1), header(kN), s);
    ASSERT_FALSE(seen.empty());
    EXPECT_EQ(seen.back(), 1.0);
    const size_t between = size_t(std::count_if(seen.begin(), seen.end(), [](double f) { return f > 0.5 && f < 1.0; }));
    EXPECT_GE(between, 3u) << "threads " << threads;  // at least four tiles: a bar that moves
    if (threads == 1) {
      EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    }
    const Scene one = solid(m, kN, SolidRule::Winding, 1);
    EXPECT_EQ(scene.occupiedCount(), one.occupiedCount());
  }
}


// ---------------------------------------------------------------- centres on caps

namespace {

/// A soup from a flat list of corners (9 numbers a triangle), moved by `offset`
/// voxels and scaled by `scale` (voxels per unit: voxel size 1 / scale).
Mesh soupOf(const std::vector<double>& corners, double scale, double offset) {
  std::vector<std::array<double, 3>> p;
  std::vector<std::array<uint32_t, 3>> t;
  for (size_t i = 0; i + 8 < corners.size(); i += 9) {
    const uint32_t b = uint32_t(p.size());
    for (int c = 0; c < 3; ++c)
      p.push_back({corners[i + 3 * c] * scale + offset, corners[i + 3 * c + 1] * scale + offset,
                   corners[i + 3 * c + 2] * scale + offset});
    t.push_back({b, b + 1, b + 2});
  }
  return meshOf(p, t);
}

/// Where the lattice point q lies on cap triangle c (exact): 0 off it, 1 inside,
/// 2 on an edge or corner.
int onCap(const CapTriangle& c, const LatticePoint& q) {
  using i128 = __int128;
  i128 a[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) a[i][k] = i128(c.v[i][k]) - q[k];
  auto cross = [](const i128* x, const i128* y, i128* out) {
    out[0] = x[1] * y[2] - x[2] * y[1], out[1] = x[2] * y[0] - x[0] * y[2], out[2] = x[0] * y[1] - x[1] * y[0];
  };
  const i128 e1[3] = {a[1][0] - a[0][0], a[1][1] - a[0][1], a[1][2] - a[0][2]};
  const i128 e2[3] = {a[2][0] - a[0][0], a[2][1] - a[0][1], a[2][2] - a[0][2]};
  i128 n[3];
  cross(e1, e2, n);
  if (n[0] == 0 && n[1] == 0 && n[2] == 0) return 0;
  if (n[0] * a[0][0] + n[1] * a[0][1] + n[2] * a[0][2] != 0) return 0;
  int zeros = 0;
  for (int k = 0; k < 3; ++k) {
    i128 s[3];
    cross(a[k], a[(k + 1) % 3], s);  // (v_k - q) x (v_k+1 - q): along n inside
    const i128 d = s[0] * n[0] + s[1] * n[1] + s[2] * n[2];
    if (d < 0) return 0;
    zeros += d == 0;
  }
  return zeros ? 2 : 1;
}

struct CapStats {
  uint64_t centres = 0, missed = 0, extra = 0, ties = 0, snapDecides = 0;
  uint64_t onCapInside = 0, onCapEdge = 0, onVerticalCap = 0;
};

/// Every centre of the n^3 grid that is not a surface voxel against the
/// brute-force oracle on the mesh snapped to the lattice, which the fill
/// decides exactly (|w| within 1e-9 of 0.5, a tie that rounding decides, is
/// counted apart, and so are the centres where the snap moves w across 0.5);
/// at the centres on a cap, w_mesh + w_caps (as the crossing count sees the
/// caps) is an integer and the point evaluation of the caps' tree agrees with
/// the direct sum.
void compareAllCentres(const Mesh& m, uint32_t n, CapStats& st, const char* what) {
  const Scene s = solid(m, n, SolidRule::Winding);
  const std::vector<LatticePoint> lattice = latticeOf(m);
  const std::vector<CapTriangle> caps = capBoundaryLoops(m.triangles, lattice);
  const CapField field(caps);
  Mesh snapped = m;
  for (size_t i = 0; i < lattice.size(); ++i)
    for (int k = 0; k < 3; ++k) snapped.positions[i][k] = double(lattice[i][k]) / 65536;
  // The centres on caps, found from each cap's box (exact tests).
  std::vector<uint8_t> on(size_t(n) * n * n, 0), vertical(size_t(n) * n * n, 0);
  for (const CapTriangle& c : caps) {
    int32_t lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      const int64_t mn = std::min({c.v[0][k], c.v[1][k], c.v[2][k]}), mx = std::max({c.v[0][k], c.v[1][k], c.v[2][k]});
      lo[k] = std::max<int32_t>(0, int32_t(std::floor(double(mn) / 65536 - 0.5)));
      hi[k] = std::min<int32_t>(int32_t(n) - 1, int32_t(std::ceil(double(mx) / 65536 - 0.5)));
    }
    const int64_t nz = (c.v[1][0] - c.v[0][0]) * (c.v[2][1] - c.v[0][1]) - (c.v[1][1] - c.v[0][1]) * (c.v[2][0] - c.v[0][0]);
    for (int32_t u = lo[0]; u <= hi[0]; ++u)
      for (int32_t v = lo[1]; v <= hi[1]; ++v)
        for (int32_t w = lo[2]; w <= hi[2]; ++w) {
          const LatticePoint q{(2 * int64_t(u) + 1) * 32768, (2 * int64_t(v) + 1) * 32768, (2 * int64_t(w) + 1) * 32768};
          const int where = onCap(c, q);
          const size_t i = (size_t(u) * n + size_t(v)) * n + size_t(w);
          on[i] = std::max<uint8_t>(on[i], uint8_t(where));
          if (where && nz == 0) vertical[i] = 1;
        }
  }
  std::vector<ClassVotes> tmp;
  CapField::Ball ball;
  for (int32_t u = 0; u < int32_t(n); ++u)
    for (int32_t v = 0; v < int32_t(n); ++v)
      for (int32_t w = 0; w < int32_t(n); ++w) {
        const auto vox = s.voxel({u, v, w}, tmp);
        if (vox && vox->surface) continue;
        const double p[3] = {u + 0.5, v + 0.5, w + 0.5};
        const double wm = windingNumber(snapped, {p[0], p[1], p[2]});
        const size_t i = (size_t(u) * n + size_t(v)) * n + size_t(w);
        ++st.centres;
        if (on[i]) {
          ++(on[i] == 1 ? st.onCapInside : st.onCapEdge);
          st.onVerticalCap += vertical[i];
          const double total = wm + field.winding(p);
          EXPECT_NEAR(total, std::round(total), 1e-9) << what << " at " << p[0] << " " << p[1] << " " << p[2];
          const bool evaluated = field.ballField(p, 0, ball);
          EXPECT_TRUE(evaluated) << what;
          if (evaluated) {
            EXPECT_LE(std::abs(ball.value - field.winding(p)), ball.valueError + ball.slack + 1e-12) << what;
          }
        }
        if (std::abs(std::abs(wm) - 0.5) < 1e-9) {
          ++st.ties;
          continue;
        }
        const bool inside = std::abs(wm) > 0.5;
        if (std::abs(std::abs(wm) - 0.5) < 1e-4 && (std::abs(windingNumber(m, {p[0], p[1], p[2]})) > 0.5) != inside)
          ++st.snapDecides;  // --check, on the mesh as read, would count this centre
        st.missed += inside && !vox;
        st.extra += !inside && vox;
        EXPECT_EQ(inside, vox.has_value()) << what << " at " << p[0] << " " << p[1] << " " << p[2] << ": w " << wm;
      }
}

}  // namespace

TEST(Winding, FuzzedSoupsWithCentresOnCaps) {
  // Open soups a fuzzer found (corners on an integer grid; its soups had
  // +-1e-12 of noise on them, far below the lattice step): with round
  // coordinates, caps (spanned between mesh vertices) pass exactly through
  // voxel centres. W counts such a centre as lying below the cap, while the
  // solid angles summed at the centre itself gave each cap through it half a
  // jump or none, so w was off by 0.5 or 1 there: an interior voxel where w =
  // -0.22, whole rows of them at voxel size 0.5.
  const std::vector<double> fig = {3, 6, 4, 3, 0, 0, 8, 4, 7, 4, 1, 5, 6, 1, 8, 3, 6, 5,
                                   6, 0, 7, 1, 0, 4, 3, 1, 5, 7, 2, 7, 2, 0, 4, 2, 3, 5};
  {
    const Mesh m = soupOf(fig, 1, 0);
    const Scene s = solid(m, 12, SolidRule::Winding);
    std::vector<ClassVotes> tmp;
    EXPECT_NEAR(windingNumber(m, {2.5, 4.5, 4.5}), -0.223, 1e-3);
    EXPECT_FALSE(s.voxel({2, 4, 4}, tmp).has_value()) << "w = -0.22: not inside";
  }
  const std::vector<std::pair<const char*, std::vector<double>>> soups = {
      {"brief's soup", fig},
      {"min3", {0, 8, 4, 4, 8, 0, 8, 8, 8, 4, 4, 4, 8, 8, 0, 0, 4, 8, 0, 0, 0, 8, 4, 0, 8, 4, 8, 4, 0, 4, 8, 8, 0, 4, 8, 8}},
      {"min7", {0, 0, 4, 0, 8, 0, 4, 0, 4, 4, 0, 0, 0, 4, 4, 0, 0, 0, 4, 0, 0, 8, 0, 8, 4, 8, 4,
                4, 4, 0, 0, 0, 0, 8, 8, 4, 0, 8, 4, 8, 4, 8, 4, 0, 0, 8, 8, 4, 0, 4, 4, 0, 4, 8}},
      {"min23", {4, 8, 0, 0, 4, 4, 0, 8, 4, 4, 0, 4, 0, 8, 0, 0, 8, 4, 0, 8, 4, 4, 0,
                 8, 4, 4, 4, 8, 4, 8, 4, 4, 8, 4, 0, 4, 4, 4, 4, 0, 4, 4, 0, 0, 4}},
      {"min25", {3, 0, 6, 3, 0, 3, 1, 3, 0, 2, 8, 2, 8, 5, 1, 8, 6, 0, 8, 4, 7, 6, 0, 8, 3, 0, 2,
                 8, 5, 1, 1, 3, 1, 1, 5, 4, 4, 4, 4, 2, 7, 5, 3, 0, 1, 1, 2, 7, 2, 7, 5, 4, 3, 0}},
      {"bads3", {0, 4, 4, 0, 4, 4, 4, 4, 0, 0, 0, 4, 0, 4, 8, 0, 0, 4, 0, 8, 4, 4, 8, 0, 8, 8, 8, 4, 4, 4,
                 8, 0, 8, 8, 8, 8, 8, 8, 8, 8, 8, 0, 0, 0, 4, 4, 8, 8, 8, 8, 4, 0, 0, 8, 0, 8, 8, 4, 0, 0,
                 0, 8, 4, 4, 4, 4, 8, 8, 0, 0, 4, 8, 4, 8, 0, 0, 4, 0, 0, 4, 8, 4, 4, 0, 0, 0, 0, 4, 8, 4,
                 0, 0, 0, 8, 4, 0, 8, 4, 8, 0, 4, 0, 0, 8, 4, 8, 4, 4, 0, 0, 4, 0, 8, 8, 4, 0, 4, 0, 4, 0,
                 0, 8, 8, 0, 4, 4, 4, 0, 4, 8, 8, 0, 4, 8, 8, 4, 8, 0, 4, 4, 4, 8, 4, 8, 4, 8, 4, 0, 0, 0,
                 4, 0, 4, 4, 8, 0, 0, 8, 4, 4, 8, 0, 4, 4, 8, 4, 4, 4, 8, 0, 8, 8, 0, 0, 4, 4, 4, 0, 4, 4}},
      {"bads5", {3, 6, 4, 3, 0, 0, 8, 4, 7, 4, 5, 3, 7, 8, 3, 8, 3, 0, 6, 4, 0, 0, 3, 7, 6, 1, 4, 3, 6, 5,
                 3, 7, 0, 5, 6, 5, 6, 3, 0, 4, 8, 1, 3, 7, 3, 4, 3, 3, 7, 3, 4, 4, 1, 7, 2, 3, 7, 6, 0, 2,
                 6, 0, 3, 0, 2, 6, 0, 0, 2, 6, 7, 5, 1, 1, 2, 5, 3, 2, 8, 7, 0, 4, 6, 5, 5, 7, 2, 1, 0, 1,
                 4, 1, 5, 6, 1, 8, 3, 6, 5, 4, 6, 1, 0, 7, 3, 5, 8, 7, 3, 5, 5, 7, 0, 6, 3, 6, 0, 6, 0, 7,
                 1, 0, 4, 3, 1, 5, 5, 4, 5, 0, 4, 5, 4, 4, 0, 1, 0, 3, 1, 7, 7, 6, 4, 6, 7, 2, 7, 2, 0, 4,
                 2, 3, 5, 5, 7, 5, 1, 8, 3, 6, 2, 3, 6, 1, 0, 7, 8, 8, 5, 2, 6}},
      {"bads7", {8, 4, 0, 8, 4, 4, 0, 0, 0, 4, 4, 0, 0, 8, 8, 0, 8, 8, 0, 4, 0, 0, 0, 4, 4, 0, 4, 8, 4, 8,
                 8, 8, 8, 8, 4, 8, 0, 8, 4, 0, 0, 0, 8, 0, 4, 4, 4, 8, 8, 4, 0, 4, 4, 8, 0, 0, 4, 0, 8, 0,
                 4, 0, 4, 4, 4, 8, 0, 8, 0, 4, 8, 0, 4, 0, 0, 8, 0, 0, 4, 8, 0, 4, 4, 4, 4, 0, 8, 0, 4, 8,
                 4, 0, 0, 0, 4, 4, 0, 0, 0, 4, 8, 8, 0, 8, 4, 4, 4, 8, 4, 0, 0, 8, 0, 8, 4, 8, 4, 0, 0, 0,
                 8, 4, 8, 0, 4, 8, 0, 0, 8, 4, 8, 8, 4, 4, 0, 4, 4, 0, 0, 0, 0, 8, 8, 4, 0, 8, 4, 8, 4, 8,
                 4, 0, 0, 8, 4, 0, 0, 0, 8, 0, 4, 8, 8, 8, 4, 0, 4, 4, 0, 4, 8, 4, 8, 0, 8, 0, 0, 0, 0, 4,
                 8, 8, 4, 8, 4, 8, 4, 0, 8, 0, 0, 0, 8, 0, 4, 0, 8, 8, 4, 8, 0, 4, 0, 4, 4, 8, 8, 0, 0, 0,
                 0, 0, 0, 0, 8, 8}},
      {"bads23", {4, 8, 8, 8, 8, 8, 4, 4, 4, 8, 4, 4, 4, 8, 8, 4, 8, 8, 4, 8, 0, 0, 4, 4, 0, 8, 4, 4, 0, 4, 0, 8,
                  0, 0, 8, 4, 0, 8, 4, 4, 0, 8, 4, 4, 4, 0, 4, 8, 0, 8, 0, 8, 0, 4, 8, 4, 8, 4, 4, 8, 4, 0, 4, 4,
                  4, 4, 0, 4, 4, 0, 0, 4}},
      {"bads25", {8, 4, 8, 5, 2, 5, 5, 4, 1, 0, 2, 5, 6, 0, 7, 1, 5, 1, 2, 5, 7, 7, 1, 5, 5, 7, 2, 1, 8, 4,
                  8, 6, 3, 5, 4, 0, 3, 4, 8, 6, 6, 2, 6, 2, 2, 0, 1, 3, 8, 6, 0, 0, 1, 7, 0, 3, 8, 1, 5, 5,
                  8, 7, 7, 3, 0, 3, 3, 5, 6, 1, 1, 2, 3, 7, 7, 7, 1, 0, 7, 2, 6, 3, 7, 7, 2, 1, 7, 6, 1, 3,
                  3, 0, 6, 3, 0, 3, 1, 3, 0, 0, 7, 0, 6, 3, 3, 0, 8, 6, 4, 0, 2, 7, 0, 7, 1, 1, 2, 2, 8, 2,
                  8, 5, 1, 8, 6, 0, 1, 0, 8, 1, 8, 8, 8, 1, 0, 8, 4, 7, 6, 0, 8, 3, 0, 2, 8, 7, 3, 1, 3, 6,
                  1, 1, 8, 8, 5, 1, 1, 3, 1, 1, 5, 4, 4, 4, 4, 2, 7, 5, 3, 0, 1, 1, 0, 1, 3, 8, 6, 7, 6, 3,
                  1, 0, 0, 0, 2, 6, 0, 2, 4, 7, 4, 2, 4, 4, 5, 0, 5, 6, 1, 2, 7, 2, 7, 5, 4, 3, 0, 6, 8, 0,
                  5, 3, 8, 5, 5, 0}},
  };
  CapStats st;
  for (const auto& [name, corners] : soups)
    for (double scale : {1.0, 2.0, 4.0}) {  // voxel size 1, 1/2, 1/4
      SCOPED_TRACE(std::string(name) + " at voxel size 1/" + std::to_string(int(scale)));
      compareAllCentres(soupOf(corners, scale, 2), uint32_t(8 * scale + 6), st, name);
    }
  std::printf("  %llu centres: missed %llu, extra %llu, %llu ties; on caps: %llu inside one, %llu on an edge or corner,"
              " %llu on vertical ones\n", (unsigned long long)st.centres, (unsigned long long)st.missed,
              (unsigned long long)st.extra, (unsigned long long)st.ties, (unsigned long long)st.onCapInside,
              (unsigned long long)st.onCapEdge, (unsigned long long)st.onVerticalCap);
  EXPECT_EQ(st.missed, 0u);
  EXPECT_EQ(st.extra, 0u);
  EXPECT_GT(st.onCapInside + st.onCapEdge, 100u);
}

TEST(Winding, RandomSoupsAgreeWithTheOracle) {
  // Many small random open meshes, each from mt19937 started at its number
  // (the raw sequence, which the standard fixes: deterministic): soups of
  // triangles with corners on an integer grid, triangles over a few shared
  // vertices on a coarser one (open surfaces with shared edges), boxes half a
  // voxel off the grid missing faces or with faces flipped (caps in planes of
  // centres, their diagonals through centres), prisms' walls over polygons
  // with diagonal sides (vertical caps through centres), and soups in general
  // position; at voxel sizes 1, 1/2 and 1/4 of the grid, every centre.
  CapStats st;
  int soups = 0;
  for (uint32_t number = 1; number <= 200; ++number) {
    std::mt19937 rng(number);
    const int kind = int(number % 5);
    const double scale = number % 3 == 0 ? 4.0 : number % 3 == 1 ? 1.0 : 2.0;
    std::vector<double> corners;
    auto add = [&](std::array<double, 3> p) { corners.insert(corners.end(), p.begin(), p.end()); };
    auto grid = [&](uint32_t steps) { return double(rng() % (steps + 1)) * 8 / steps; };  // [0, 8] in `steps` steps
    if (kind == 0) {
      const uint32_t steps = number % 2 ? 2 : 8;
      for (int t = 0, nt = 2 + int(rng() % 10); t < nt; ++t)
        for (int c = 0; c < 9; ++c) corners.push_back(grid(steps));
    } else if (kind == 1) {
      const uint32_t steps = number % 2 ? 2 : 4;
      std::vector<std::array<double, 3>> pool(4 + rng() % 6);
      for (auto& p : pool) p = {grid(steps), grid(steps), grid(steps)};
      for (int t = 0, nt = 2 + int(rng() % 12); t < nt; ++t) {
        const uint32_t a = rng() % pool.size(), b = rng() % pool.size(), c = rng() % pool.size();
        if (a == b || b == c || a == c) continue;
        for (uint32_t i : {a, b, c}) add(pool[i]);
      }
    } else if (kind == 2) {
      // Corners half a voxel off the grid at every scale: faces and the caps
      // across missing ones lie in planes of centres.
      for (int b = 0, nb = 1 + int(rng() % 3); b < nb; ++b) {
        const double side = 1 + rng() % 4;
        double lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
          lo[k] = (rng() % 6 + 0.5) / scale;
          hi[k] = lo[k] + (rng() % 2 ? side : 1 + rng() % 4) / scale;
        }
        const Mesh bx = box({lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]});
        for (size_t f = 0; f < bx.triangles.size(); f += 2) {
          if (rng() % 4 == 0) continue;  // a missing face
          for (size_t h = f; h < f + 2; ++h) {
            auto t = bx.triangles[h];
            if (rng() % 8 == 0) continue;               // a missing half
            if (rng() % 5 == 0) std::swap(t[1], t[2]);  // a flipped one
            for (uint32_t i : t) add(bx.positions[i]);
          }
        }
      }
    } else if (kind == 3) {
      std::vector<std::array<double, 2>> ring(3 + rng() % 3);
      for (auto& q : ring) q = {grid(16), grid(16)};
      const double z0 = grid(16), z1 = z0 + 0.5 * (1 + rng() % 6);
      for (size_t i = 0; i < ring.size(); ++i) {
        if (rng() % 3 == 0) continue;  // a missing wall
        const auto &a = ring[i], &b = ring[(i + 1) % ring.size()];
        add({a[0], a[1], z0}), add({b[0], b[1], z0}), add({b[0], b[1], z1});
        add({a[0], a[1], z0}), add({b[0], b[1], z1}), add({a[0], a[1], z1});
      }
      if (rng() % 2)  // the bottom
        for (size_t i = 1; i + 1 < ring.size(); ++i)
          add({ring[0][0], ring[0][1], z0}), add({ring[i + 1][0], ring[i + 1][1], z0}), add({ring[i][0], ring[i][1], z0});
    } else {
      for (int t = 0, nt = 2 + int(rng() % 10); t < nt; ++t)
        for (int c = 0; c < 9; ++c) corners.push_back(double(rng() % 8001) / 1000);
    }
    if (corners.empty()) continue;
    ++soups;
    const std::string what = "random mesh " + std::to_string(number);
    compareAllCentres(soupOf(corners, scale, 2), uint32_t(8 * scale + 6), st, what.c_str());
  }
  std::printf("  %d soups, %llu centres: missed %llu, extra %llu, %llu ties, %llu decided by the snap; on caps: %llu"
              " inside one, %llu on an edge or corner, %llu on vertical ones\n", soups, (unsigned long long)st.centres,
              (unsigned long long)st.missed, (unsigned long long)st.extra, (unsigned long long)st.ties,
              (unsigned long long)st.snapDecides,
              (unsigned long long)st.onCapInside, (unsigned long long)st.onCapEdge,
              (unsigned long long)st.onVerticalCap);
  EXPECT_EQ(st.missed, 0u);
  EXPECT_EQ(st.extra, 0u);
  EXPECT_GT(soups, 190);
  EXPECT_GT(st.onCapInside, 500u);  // the cases were exercised
  EXPECT_GT(st.onCapEdge, 30u);
  EXPECT_GT(st.onVerticalCap, 100u);
}
