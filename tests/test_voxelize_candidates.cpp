// The surface pass finds its candidate voxels from the exact pieces of a
// triangle (the parts of it inside each x slab and y row) where every clip
// decision is certain, and from pieces clipped with a margin elsewhere. Either
// way the voxels it keeps must be exactly those the exact separating-axis test
// admits: checked here against that test on every voxel of the grid, for
// triangles that make the candidates hard (slivers a lattice step from parallel
// to a grid plane, vertices on grid planes, edges through grid lines, needles).
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "libvox/mesh/voxelize.h"
#include "libvox/scene/voxelize_scene.h"
#include "voxelize_test_meshes.h"

using namespace vox;

namespace {

using Voxels = std::set<std::tuple<int, int, int>>;

Voxels baked(const std::array<std::array<double, 3>, 3>& v, uint32_t n) {
  VoxelizeSettings s;
  s.fill = FillMode::Surface;
  s.threads = 1;
  const Mesh m = voxtest::meshOf({v[0], v[1], v[2]}, {{0, 1, 2}});
  const Scene scene = voxelizeMesh(m, {1}, voxtest::twoClassHeader({n, n, n}), s);
  Voxels out;
  scene.forEachVoxel([&](const VoxelView& x) { out.insert({x.at.u, x.at.v, x.at.w}); });
  return out;
}

Voxels exact(const std::array<std::array<double, 3>, 3>& v, uint32_t n) {
  std::array<int64_t, 3> q[3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) q[k][i] = snapToLattice(v[k][i]);
  Voxels out;
  for (int u = 0; u < int(n); ++u)
    for (int w = 0; w < int(n); ++w)
      for (int y = 0; y < int(n); ++y)
        if (triangleTouchesVoxel(q, u, y, w)) out.insert({u, y, w});
  return out;
}

}  // namespace

TEST(VoxelizeCandidates, SliversAndGridPlanesMatchTheExactTest) {
  std::mt19937 rng(14);
  const uint32_t n = 12;
  const double step = 1.0 / 65536;  // one lattice step
  std::uniform_real_distribution<double> any(-0.5, n + 0.5);
  auto onPlane = [&]() { return double(rng() % (n + 1)); };
  for (int trial = 0; trial < 600; ++trial) {
    std::array<std::array<double, 3>, 3> v;
    for (auto& p : v) p = {any(rng), any(rng), any(rng)};
    const int a = int(rng() % 3), b = (a + 1 + int(rng() % 2)) % 3;
    switch (trial % 6) {
      case 0:  // an edge a lattice step or two from parallel to the plane x_a = const
        v[1][a] = v[0][a] + step * double(1 + rng() % 2);
        break;
      case 1:  // a whole triangle within two lattice steps of a grid plane
        v[0][a] = onPlane(), v[1][a] = v[0][a] + step, v[2][a] = v[0][a] - step * double(rng() % 2);
        break;
      case 2:  // vertices on grid planes along two axes
        for (auto& p : v) p[a] = onPlane(), p[b] = rng() % 2 ? onPlane() : p[b];
        break;
      case 3:  // a needle: two vertices a few lattice steps apart, the third far away
        for (int i = 0; i < 3; ++i) v[1][i] = v[0][i] + step * double(int(rng() % 5) - 2);
        break;
      case 4: {  // an edge through a grid line (x_a, x_b integers) at a point its ends' rounding may miss
        const double ca = onPlane(), cb = onPlane(), k = double(1 + rng() % 7), da = step * double(1 + rng() % 900),
                     db = -step * double(1 + rng() % 900);
        v[0][a] = ca - da, v[0][b] = cb - db;
        v[1][a] = ca + k * da, v[1][b] = cb + k * db;
        break;
      }
      default: break;
    }
    ASSERT_EQ(baked(v, n), exact(v, n)) << "trial " << trial;
  }
}
