// render-canonical's kernels: cast one exact ray per pixel centre into a
// RayGrid (castView) and check views against the brute force (checkView). The
// images made from the hits are render_modes.h; the voxels they touch,
// touched_voxels.h.
//
// Spaces: cameras are in world space; the grid maps world p to grid space
// (p - origin) / voxelSize (voxel (u, v, w) = [u, u+1] x [v, v+1] x [w, w+1]).
// Depths are world distances from the eye along the ray.
//
// Threading: castView and checkView spread pixels over `threads` workers
// (0 = all cores, vox::parallelForEach); every pixel is computed on its own and
// stored in its own slot, so the results do not depend on the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "libvox/render/camera.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/raycast.h"

namespace vox {

/// Where the grid sits in world space (SceneHeader's origin and voxelSize).
struct GridFrame {
  std::array<double, 3> origin{0, 0, 0};
  double voxelSize = 1.0;
};

/// One pixel's hit. `faceAxis` -1 means the ray started inside the voxel.
struct PixelHit {
  int32_t u = 0, v = 0, w = 0;
  float depth = 0;  // world distance along the ray
  int8_t faceAxis = -1, faceSign = 0;
  bool hit = false;
};

struct ViewHits {
  uint32_t width = 0, height = 0;
  std::vector<PixelHit> pixels;  // row-major, row 0 at the top
  uint64_t hitCount = 0;
  uint64_t steps = 0;  // DDA events over all rays
};

/// The grid-space rays of a camera's pixels, with the per-column and per-row
/// terms computed once: ray(x, y) starts at the eye, (eye - origin) / voxelSize,
/// along the camera's direction through the pixel centre (Camera::pixelRay's
/// formula, not normalised) times 1 / voxelSize. Every caster and checker
/// builds its rays here, so they trace bit-identical rays. Immutable after
/// construction: thread-safe.
class PixelRays {
 public:
  PixelRays(const Camera& camera, const GridFrame& frame);
  Ray ray(uint32_t x, uint32_t y) const {
    const double cx = column_[x], cy = row_[y];
    Ray r;
    r.origin = origin_;
    for (int a = 0; a < 3; ++a)
      r.dir[size_t(a)] = (m_[size_t(a)] * cx + m_[size_t(a) + 4] * cy - m_[size_t(a) + 8]) * invVoxelSize_;
    return r;
  }
  /// World distance along `ray` (one of ours) for the ray parameter t.
  double worldDistance(const Ray& ray, double t) const;

 private:
  std::array<double, 3> origin_{};
  Mat4d m_{};  // camera -> world
  double invVoxelSize_ = 1, voxelSize_ = 1;
  std::vector<double> column_, row_;  // camera-space x and y of each pixel centre at z = -1
};

/// The grid-space ray of pixel (x, y) (PixelRays, for one-off use).
Ray gridRay(const Camera& camera, const GridFrame& frame, uint32_t x, uint32_t y);

/// Casts every pixel of `camera`. `progress` (may be empty) gets fractions
/// done, one call at a time and never smaller than the previous one.
ViewHits castView(const RayGrid& grid, const GridFrame& frame, const Camera& camera, unsigned threads,
                  const std::function<void(double)>& progress = {});

/// Comparison of a view against a reference caster on a sample of pixels.
struct ViewCheck {
  uint64_t pixelsChecked = 0;
  uint64_t pixelsDiffering = 0;
  struct Mismatch {
    uint32_t x = 0, y = 0;
    PixelHit got;
    RayHit expected;
  };
  std::vector<Mismatch> first;  // up to 10, in pixel order
};

/// The brute force's default budget: ray-voxel tests per view.
inline constexpr double kDefaultCheckBudget = 2e9;

/// The pixel stride that keeps a check of `pixels` rays against `occupied`
/// voxels within `budget` ray-voxel tests (1 = every pixel).
uint64_t checkStride(uint64_t pixels, uint64_t occupied, double budget);

/// The pixels a check with `stride` K samples: one in each run of K
/// consecutive pixels (row-major), at an offset that varies from run to run
/// (a fixed hash of the run's index) so that a stride that divides the width
/// does not check one column only. Every pixel when K = 1.
uint64_t sampledPixelCount(uint64_t pixels, uint64_t stride);
uint64_t sampledPixel(uint64_t sample, uint64_t pixels, uint64_t stride);

/// A reference caster: the hit of one grid-space ray (thread-safe).
using ReferenceCaster = std::function<RayHit(const Ray&)>;

/// Checks `hits` against `reference` on the pixels sampledPixel picks for
/// `stride`. A pixel differs when the hit flag or the voxel differs.
/// `progress` as castView's.
ViewCheck checkView(const ViewHits& hits, const ReferenceCaster& reference, const GridFrame& frame,
                    const Camera& camera, uint64_t stride, unsigned threads,
                    const std::function<void(double)>& progress = {});

/// The same against castRayBruteForce over `occupied`.
ViewCheck checkView(const ViewHits& hits, std::span<const Coord3> occupied, const GridFrame& frame,
                    const Camera& camera, uint64_t stride, unsigned threads);

}  // namespace vox
