#include "libvox/render/ray_bundle.h"

#include <algorithm>
#include <cmath>

namespace vox {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Slack against rounding in the march's own arithmetic: coordinates are at
// most ~2^24 voxels, so double errors are far below it.
constexpr double kMargin = 0.5;

double normInf(const std::array<double, 3>& v) {
  return std::max(std::fabs(v[0]), std::max(std::fabs(v[1]), std::fabs(v[2])));
}

// A radius r such that no point q with |q - p|inf < r lies in an occupied
// voxel's closed cube; may be <= 0. Occupied voxels lie in the content box B;
// with p' = p clamped to B, |x - p| >= |x - p'| for every x in B (per axis),
// so the larger of p's gap to B and the empty radius around p' holds.
double emptyRadius(const RayGrid& grid, const std::array<double, 3>& p) {
  const std::array<int64_t, 3>& lo = grid.contentMin();
  const std::array<int64_t, 3>& hi = grid.contentEnd();
  double gap = 0, clamped[3];
  int64_t b[3];  // the brick holding p', clamped to the box's bricks
  for (int a = 0; a < 3; ++a) {
    const double l = double(lo[size_t(a)]), h = double(hi[size_t(a)]);
    gap = std::max(gap, std::max(l - p[size_t(a)], p[size_t(a)] - h));
    clamped[a] = std::clamp(p[size_t(a)], l, h);
    // The box is whole bricks clipped to the domain: its end need not be a multiple of 8.
    b[a] = std::clamp<int64_t>(int64_t(clamped[a]) >> 3, lo[size_t(a)] >> 3, (hi[size_t(a)] - 1) >> 3);
  }
  // Bricks b - (k - 1) .. b + (k - 1) are empty: the open box of voxels
  // [8 (b - k + 1), 8 (b + k)) on every axis, which holds p'.
  int64_t k = grid.emptyBricksAround(b[0], b[1], b[2]);
  // Without a distance field (very large domains) every brick reads 1: ask the tree.
  const RayGrid::Mask512* mask;
  if (k == 1 && grid.probe(8 * b[0], 8 * b[1], 8 * b[2], &mask) == 0) k = 0;
  if (k == 0) return gap;
  double inside = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    inside = std::min(inside, std::min(clamped[a] - double(8 * (b[a] - k + 1)), double(8 * (b[a] + k)) - clamped[a]));
  return std::max(gap, inside);
}

}  // namespace

double bundleEmptyUntil(const RayGrid& grid, const std::array<double, 3>& origin,
                        std::span<const std::array<double, 3>> dirs) {
  if (grid.occupiedCount() == 0) return kInf;
  if (dirs.empty()) return 0;
  std::array<double, 3> c{0, 0, 0};
  for (const auto& d : dirs)
    for (int a = 0; a < 3; ++a) c[size_t(a)] += d[size_t(a)];
  for (double& x : c) x /= double(dirs.size());
  double w = 0;
  for (const auto& d : dirs)
    w = std::max(w, normInf({d[0] - c[0], d[1] - c[1], d[2] - c[2]}));
  const double D = normInf(c);
  if (!(D > 0) || !std::isfinite(D) || !std::isfinite(w)) return 0;
  // Beyond tFar every ray is farther (L-inf) from the origin than any point of
  // the content box: |t d| >= t (D - w) > R.
  double tFar = kInf;
  if (D > w) {
    double R = 0;
    for (int corner = 0; corner < 8; ++corner)
      for (int a = 0; a < 3; ++a) {
        const double x = double((corner >> a) & 1 ? grid.contentEnd()[size_t(a)] : grid.contentMin()[size_t(a)]);
        R = std::max(R, std::fabs(x - origin[size_t(a)]));
      }
    tFar = (R + 1.0) / (D - w);
  }
  // For t' in [t, t1]: |o + t' d - (o + t c)| <= t1 w + (t1 - t) D, which must
  // stay below the empty radius around o + t c (less the margin).
  double t = 0;
  for (int iter = 0; iter < 256; ++iter) {
    if (t >= tFar) return kInf;
    const std::array<double, 3> p{origin[0] + t * c[0], origin[1] + t * c[1], origin[2] + t * c[2]};
    const double rho = emptyRadius(grid, p) - kMargin;
    if (!(rho > 0)) break;
    const double t1 = (rho + t * D) / (w + D);
    if (!(t1 > t)) break;
    const bool small = (t1 - t) * D < 1.0;  // under a voxel of progress: stop marching
    t = t1;
    if (small) break;
  }
  return t >= tFar ? kInf : t;
}

}  // namespace vox
