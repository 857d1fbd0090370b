// Polygons cut into triangles (formats/mesh/polygon_triangulation.h): convex
// ones keep the fan they always had, concave ones are cut inside the polygon
// (every triangle wound as the polygon, areas adding up to the polygon's, no
// triangle outside it), degenerate and self-intersecting ones get n - 2
// triangles all the same; then the OBJ and PLY readers and the voxels they
// give, against the same shapes written as triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

#include "formats/mesh/mesh_input.h"
#include "formats/mesh/polygon_triangulation.h"
#include "libvox/scene/voxelize_scene.h"
#include "test_util.h"
#include "voxelize_test_meshes.h"

using namespace vox;

namespace {

using P3 = std::array<double, 3>;
using Tri = std::array<uint32_t, 3>;

std::vector<Tri> cut(const std::vector<P3>& corners) {
  std::vector<Tri> out;
  PolygonScratch scratch;
  triangulatePolygon(corners.data(), corners.size(), out, scratch);
  return out;
}

std::vector<Tri> fanOf(size_t n) {
  std::vector<Tri> out;
  for (uint32_t k = 1; k + 1 < n; ++k) out.push_back({0, k, k + 1});
  return out;
}

std::vector<P3> flat(const std::vector<std::array<double, 2>>& xy) {
  std::vector<P3> out;
  for (const auto& p : xy) out.push_back({p[0], p[1], 0});
  return out;
}

/// Twice the signed area of a polygon in the xy plane (counter-clockwise > 0).
double area2(const std::vector<P3>& p, const std::vector<uint32_t>& idx) {
  double a = 0;
  for (size_t i = 0; i < idx.size(); ++i) {
    const P3& u = p[idx[i]];
    const P3& v = p[idx[(i + 1) % idx.size()]];
    a += u[0] * v[1] - v[0] * u[1];
  }
  return a;
}

/// Point strictly inside the polygon (even-odd), xy plane.
bool inside(const std::vector<P3>& poly, double x, double y) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const P3& a = poly[i];
    const P3& b = poly[j];
    if ((a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0]) in = !in;
  }
  return in;
}

/// The properties every triangulation of a simple polygon in the xy plane has
/// (`centroids`: and each triangle's centroid inside the polygon, O(n^2)).
::testing::AssertionResult coversExactly(const std::vector<P3>& poly, const std::vector<Tri>& tris, bool centroids = true) {
  if (tris.size() != poly.size() - 2) return ::testing::AssertionFailure() << tris.size() << " triangles";
  std::vector<uint32_t> all(poly.size());
  for (uint32_t i = 0; i < poly.size(); ++i) all[i] = i;
  const double total = area2(poly, all);
  double sum = 0;
  for (const Tri& t : tris) {
    const double a = area2(poly, {t[0], t[1], t[2]});
    if (a * total < 0) return ::testing::AssertionFailure() << "a triangle wound against the polygon";
    sum += a;
    if (a != 0 && centroids) {  // a zero-area triangle has no centroid inside
      const double cx = (poly[t[0]][0] + poly[t[1]][0] + poly[t[2]][0]) / 3;
      const double cy = (poly[t[0]][1] + poly[t[1]][1] + poly[t[2]][1]) / 3;
      if (!inside(poly, cx, cy))
        return ::testing::AssertionFailure() << "triangle " << t[0] << " " << t[1] << " " << t[2] << " lies outside";
    }
  }
  if (std::fabs(sum - total) > 1e-9 * std::fabs(total))
    return ::testing::AssertionFailure() << "areas add up to " << sum << ", the polygon's is " << total;
  return ::testing::AssertionSuccess();
}

// The U of the exploratory test: 8 x 8 with a 4 x 6 notch from the top.
const std::vector<P3> kU = flat({{0, 0}, {8, 0}, {8, 8}, {6, 8}, {6, 2}, {2, 2}, {2, 8}, {0, 8}});

/// A random polygon star-shaped about the origin: one corner at a random angle
/// in each of n equal slices (so the origin is inside, and the polygon
/// simple), at a random radius (mostly concave).
std::vector<P3> randomStar(std::mt19937& rng, size_t n) {
  std::uniform_real_distribution<double> within(0, 1), radius(0.2, 10);
  std::vector<P3> out;
  for (size_t k = 0; k < n; ++k) {
    const double a = (double(k) + within(rng)) * 2 * M_PI / double(n), r = radius(rng);
    out.push_back({r * std::cos(a), r * std::sin(a), 0});
  }
  return out;
}

/// The polygon placed in 3D: rotated about a tilted axis and moved.
std::vector<P3> placed(const std::vector<P3>& poly) {
  std::vector<P3> out;
  const double c = std::cos(0.7), s = std::sin(0.7), c2 = std::cos(-1.1), s2 = std::sin(-1.1);
  for (const P3& p : poly) {
    const double x = p[0], y = c * p[1] - s * p[2], z = s * p[1] + c * p[2];
    out.push_back({c2 * x - s2 * z + 100, y - 3, s2 * x + c2 * z + 0.5});
  }
  return out;
}

std::set<std::tuple<int, int, int>> voxelsOf(const Mesh& m, const SceneHeader& h) {
  VoxelizeSettings s;
  const Scene scene = voxelizeMesh(m, std::vector<uint8_t>(m.triangles.size(), 1), h, s);
  std::set<std::tuple<int, int, int>> out;
  scene.forEachVoxel([&](const VoxelView& v) { out.insert({v.at.u, v.at.v, v.at.w}); });
  return out;
}

Mesh readText(const std::string& dir, const std::string& file, const std::string& text, MeshReadOptions o = {}) {
  voxtest::writeText(dir + "/" + file, text);
  std::vector<std::string> warnings;
  return readMeshFile(dir + "/" + file, o, warnings);
}

// The U's plane z = 0 in the middle of one layer of 1-unit voxels.
const SceneHeader kUHeader = voxtest::twoClassHeader({8, 8, 1}, 1.0, {0, 0, -0.5});

}  // namespace

TEST(PolygonTriangulation, ConvexPolygonsKeepTheFan) {
  EXPECT_EQ(cut(flat({{0, 0}, {1, 0}, {0, 1}})), fanOf(3));
  EXPECT_EQ(cut(flat({{0, 0}, {2, 0}, {2, 2}, {0, 2}})), fanOf(4));
  EXPECT_EQ(cut(flat({{0, 0}, {0, 2}, {2, 2}, {2, 0}})), fanOf(4)) << "clockwise";
  std::vector<P3> ngon;
  for (int k = 0; k < 12; ++k) ngon.push_back({5 * std::cos(k * M_PI / 6), 5 * std::sin(k * M_PI / 6), 0});
  EXPECT_EQ(cut(placed(ngon)), fanOf(12)) << "a regular 12-gon in a tilted plane";
  // Collinear and repeated corners do not turn: still convex, still the fan
  // (its zero-area triangles included, as before).
  EXPECT_EQ(cut(flat({{0, 0}, {1, 0}, {2, 0}, {2, 2}, {2, 2}, {0, 2}})), fanOf(6));
  // A slightly twisted (non-planar) quad is convex as seen along its normal.
  EXPECT_EQ(cut({{0, 0, 0}, {1, 0, 0.1}, {1, 1, 0}, {0, 1, 0.1}}), fanOf(4));
}

TEST(PolygonTriangulation, ConcavePolygonsAreCutInside) {
  const std::vector<Tri> u = cut(kU);
  EXPECT_TRUE(coversExactly(kU, u));
  EXPECT_NE(u, fanOf(8)) << "the fan covers the notch";
  const std::vector<P3> l = flat({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}});
  EXPECT_TRUE(coversExactly(l, cut(l)));
  std::vector<P3> star;  // five points, ten corners
  for (int k = 0; k < 10; ++k) {
    const double r = k % 2 ? 2 : 5, a = k * M_PI / 5;
    star.push_back({r * std::cos(a), r * std::sin(a), 0});
  }
  EXPECT_TRUE(coversExactly(star, cut(star)));
  std::vector<P3> comb;  // teeth up along x, back along the bottom
  for (int k = 0; k < 20; ++k) comb.push_back({double(k), k % 2 ? 1.0 : 9.0, 0});
  comb.push_back({19, -1, 0});
  comb.push_back({0, -1, 0});
  std::reverse(comb.begin(), comb.end());  // counter-clockwise
  EXPECT_TRUE(coversExactly(comb, cut(comb)));
  // A dart (a quad with one reflex corner) is cut through that corner: the
  // fan when it is corner 0 or 2 (valid, and kept as files always had it).
  const std::vector<P3> dart0 = flat({{1, 1}, {0, 0}, {1, 3}, {2, 0}});
  EXPECT_EQ(cut(dart0), fanOf(4));
  EXPECT_TRUE(coversExactly(dart0, cut(dart0)));
  const std::vector<P3> dart1 = flat({{0, 0}, {1, 1}, {2, 0}, {1, 3}});
  EXPECT_EQ(cut(dart1), (std::vector<Tri>{{1, 2, 3}, {1, 3, 0}}));
  EXPECT_TRUE(coversExactly(dart1, cut(dart1)));
  // Either winding, the triangles are wound as the polygon.
  std::vector<P3> reversed(kU.rbegin(), kU.rend());
  EXPECT_TRUE(coversExactly(reversed, cut(reversed)));
}

TEST(PolygonTriangulation, CollinearAndRepeatedCorners) {
  // An L with midpoints on its edges, a corner repeated, a point on the inner corner's line.
  const std::vector<P3> l = flat({{0, 0}, {2, 0}, {4, 0}, {4, 1}, {2, 1}, {1, 1}, {1, 1}, {1, 2}, {1, 3}, {0, 3}, {0, 1.5}});
  const std::vector<Tri> t = cut(l);
  EXPECT_TRUE(coversExactly(l, t));
  // Every corner on one line: no plane, the fan (zero-area triangles).
  EXPECT_EQ(cut({{0, 0, 0}, {1, 1, 1}, {3, 3, 3}, {2, 2, 2}}), fanOf(4));
  // A spike (a corner that turns back) makes a polygon non-convex.
  const std::vector<P3> spike = flat({{0, 0}, {4, 0}, {4, 4}, {2, 4}, {2, 6}, {2, 4}, {0, 4}});
  const std::vector<Tri> s = cut(spike);
  EXPECT_NE(s, fanOf(7));
  EXPECT_EQ(s.size(), 5u);
  double sum = 0;
  for (const Tri& tri : s) sum += area2(spike, {tri[0], tri[1], tri[2]});
  EXPECT_DOUBLE_EQ(sum, 32.0) << "the spike adds no area";
}

TEST(PolygonTriangulation, RandomPolygonsInTiltedPlanes) {
  std::mt19937 rng(7);
  for (int round = 0; round < 300; ++round) {
    const std::vector<P3> poly = randomStar(rng, 4 + size_t(round % 40));
    EXPECT_TRUE(coversExactly(poly, cut(poly))) << "round " << round;
    // The same polygon in another plane gets the same triangles (they are
    // decided on its view along the normal's largest axis, an affine map).
    const std::vector<Tri> tilted = cut(placed(poly));
    EXPECT_EQ(tilted.size(), poly.size() - 2);
    EXPECT_EQ(cut(placed(poly)), tilted) << "deterministic";
  }
}

TEST(PolygonTriangulation, SelfIntersectingAndInvalidPolygonsGetNMinus2Triangles) {
  std::vector<P3> pentagram;
  for (int k = 0; k < 5; ++k) pentagram.push_back({std::cos(k * 4 * M_PI / 5), std::sin(k * 4 * M_PI / 5), 0});
  const std::vector<Tri> p = cut(pentagram);
  EXPECT_EQ(p.size(), 3u);
  EXPECT_NE(p, fanOf(5)) << "turns one way at every corner, but goes round twice: not convex";
  EXPECT_EQ(cut(pentagram), p);
  const std::vector<P3> bowtie = flat({{0, 0}, {2, 2}, {2, 0}, {0, 2}});
  EXPECT_EQ(cut(bowtie).size(), 2u);
  // Non-finite or out-of-range coordinates: the fan (--drop-invalid drops the
  // triangles touching a non-finite corner).
  std::vector<P3> nan = kU;
  nan[3][0] = std::nan("");
  EXPECT_EQ(cut(nan), fanOf(8));
  std::vector<P3> huge = kU;
  huge[3][0] = 1e200;
  EXPECT_EQ(cut(huge), fanOf(8));
  EXPECT_TRUE(cut(flat({{0, 0}, {1, 1}})).empty());
}

TEST(PolygonTriangulation, LargeConcavePolygonIsQuick) {
  // A 100,002-corner comb (half of its corners reflex), a 100,000-corner
  // random star and a 20-turn spiral band: an ear looks only at the reflex
  // corners in the grid cells along it, and none of them runs out of ear
  // tests (the fan they would then get leaves the polygon). About 1 s each on
  // the 2-core machine; a scan of every reflex corner took 17 s for the comb.
  std::vector<P3> comb;
  for (int k = 0; k < 100000; ++k) comb.push_back({double(k), k % 2 ? 1.0 : 9.0, 0});
  comb.push_back({99999, -1, 0});
  comb.push_back({0, -1, 0});
  std::reverse(comb.begin(), comb.end());
  EXPECT_TRUE(coversExactly(comb, cut(comb), false));
  std::mt19937 rng(1);
  const std::vector<P3> star = randomStar(rng, 100000);
  EXPECT_TRUE(coversExactly(star, cut(star), false));
  std::vector<P3> spiral;
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < 50000; ++k) {
      const double t = 40 * M_PI * (side ? 49999 - k : k) / 50000, r = 1 + t + 3 * side;
      spiral.push_back({r * std::cos(t), r * std::sin(t), 0});
    }
  EXPECT_TRUE(coversExactly(spiral, cut(spiral), false));
  // 100,000 random points as one face: scrambled, self-intersecting
  // everywhere; cut within its test budget, then fanned (seconds, not hours).
  std::uniform_real_distribution<double> u(0, 10);
  std::vector<P3> scrambled;
  for (int k = 0; k < 100000; ++k) scrambled.push_back({u(rng), u(rng), 0});
  EXPECT_EQ(cut(scrambled).size(), 99998u);
}

TEST(ObjPolygons, ConcaveFaceFillsOnlyThePolygon) {
  voxtest::TempDir dir;
  const std::string v = "v 0 0 0\nv 8 0 0\nv 8 8 0\nv 6 8 0\nv 6 2 0\nv 2 2 0\nv 2 8 0\nv 0 8 0\n";
  const Mesh polygon = readText(dir.path(), "u.obj", v + "f 1 2 3 4 5 6 7 8\n");
  ASSERT_EQ(polygon.triangleCount(), 6u);
  // The U as triangles written by hand: two arms and the bottom bar.
  const Mesh triangles = readText(dir.path(), "t.obj", v + "f 1 2 5\nf 1 5 6\nf 2 3 4\nf 2 4 5\nf 1 6 7\nf 1 7 8\n");
  const auto voxels = voxelsOf(polygon, kUHeader);
  EXPECT_EQ(voxels.size(), 54u) << "the fan gave 61: voxels in the notch";
  EXPECT_EQ(voxels, voxelsOf(triangles, kUHeader));
  // A convex face keeps the fan's triangles, vertex for vertex.
  const Mesh quad = readText(dir.path(), "q.obj", v + "f 1 2 3 8\n");
  EXPECT_EQ(quad.triangles, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}}));
}

TEST(PlyPolygons, ConcaveFaceFillsOnlyThePolygon) {
  voxtest::TempDir dir;
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n8 0 0\n8 8 0\n6 8 0\n6 2 0\n2 2 0\n2 8 0\n0 8 0\n";
  const Mesh polygon = readText(dir.path(), "u.ply", head + "8 0 1 2 3 4 5 6 7\n");
  ASSERT_EQ(polygon.triangleCount(), 6u);
  EXPECT_EQ(voxelsOf(polygon, kUHeader).size(), 54u);
  const Mesh quad = readText(dir.path(), "q.ply", head + "4 0 1 2 7\n");
  EXPECT_EQ(quad.triangles, (std::vector<Tri>{{0, 1, 2}, {0, 2, 7}})) << "a convex face keeps its fan";
  // Binary little endian, the same U.
  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
  for (const P3& p : kU)
    for (double c : p) {
      const float f = float(c);
      bin.append(reinterpret_cast<const char*>(&f), 4);
    }
  bin.push_back(char(8));
  for (uint32_t i = 0; i < 8; ++i) bin.append(reinterpret_cast<const char*>(&i), 4);
  EXPECT_EQ(readText(dir.path(), "b.ply", bin).triangles, polygon.triangles);
}

// The shared test meshes: the concave 66-gon MANIFEST.md describes (~13k
// voxels fanned, ~2.3k cut by ear clipping, as obj2voxel does), and Suzanne's
// quads, convex, which must keep exactly the fan's triangles.
TEST(PolygonData, SharedConcavePolygonAndConvexQuads) {
  const std::string data = voxtest::sharedDataDir();
  if (!std::filesystem::exists(data + "/MANIFEST.md")) GTEST_SKIP() << data << " is absent: shared polygons not checked";
  MeshReadOptions ignore;
  ignore.ignoreMissingMaterials = true;  // its .mtl is not shipped
  std::vector<std::string> warnings;
  const Mesh concave = readMeshFile(data + "/mesh-misc/assimp/concave_polygon.obj", ignore, warnings);
  ASSERT_EQ(concave.triangleCount(), 64u);
  // Every triangle inside the polygon: each triangle's normal points the
  // polygon's way (the face is flat, x = 0).
  double nx = 0;
  for (const Tri& t : concave.triangles) {
    const P3 &a = concave.positions[t[0]], &b = concave.positions[t[1]], &c = concave.positions[t[2]];
    const double n = (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]);
    if (nx == 0) nx = n;
    EXPECT_GE(n * nx, 0) << "a triangle wound against the others";
  }
  // Suzanne: every face of the file fanned gives the mesh's triangles.
  const std::string suzanne = data + "/common-3d-test-models/suzanne.obj";
  const Mesh m = readMeshFile(suzanne, {}, warnings);
  std::ifstream in(suzanne);
  std::vector<P3> v;
  std::vector<std::array<P3, 3>> fanned;
  size_t polygons = 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "v") {
      P3 p;
      ls >> p[0] >> p[1] >> p[2];
      v.push_back(p);
    } else if (key == "f") {
      std::vector<P3> corners;
      for (std::string c; ls >> c;) corners.push_back(v[size_t(std::stol(c)) - 1]);
      polygons += corners.size() > 3;
      for (size_t k = 1; k + 1 < corners.size(); ++k) fanned.push_back({corners[0], corners[k], corners[k + 1]});
    }
  }
  EXPECT_GT(polygons, 400u);
  ASSERT_EQ(m.triangleCount(), fanned.size());
  for (size_t t = 0; t < fanned.size(); ++t)
    for (int k = 0; k < 3; ++k) ASSERT_EQ(m.positions[m.triangles[t][size_t(k)]], fanned[t][size_t(k)]) << "triangle " << t;
}
