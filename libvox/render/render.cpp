#include "libvox/render/render.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>

#include "libvox/core/parallel.h"
#include "libvox/render/ray_bundle.h"

namespace vox {

namespace {

// Workers finish rows out of order and race to report them: a worker that
// counted 48 % may print after one that counted 50 %. Reports go through a
// lock and only a larger count than the last one reported is passed on.
class MonotoneProgress {
 public:
  explicit MonotoneProgress(const std::function<void(double)>& fn) : fn_(fn) {}
  void report(uint64_t done, uint64_t total) {
    if (!fn_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (done <= reported_) return;
    reported_ = done;
    fn_(double(done) / double(total));
  }

 private:
  const std::function<void(double)>& fn_;
  std::mutex mutex_;
  uint64_t reported_ = 0;
};

}  // namespace

PixelRays::PixelRays(const Camera& camera, const GridFrame& frame)
    : m_(camera.cameraToWorld), invVoxelSize_(1.0 / frame.voxelSize), voxelSize_(frame.voxelSize) {
  for (int a = 0; a < 3; ++a)
    origin_[size_t(a)] = (camera.eye[size_t(a)] - frame.origin[size_t(a)]) / frame.voxelSize;
  const Mat4d& P = camera.projection;
  column_.resize(camera.width);
  row_.resize(camera.height);
  for (uint32_t x = 0; x < camera.width; ++x)
    column_[x] = (2.0 * (double(x) + 0.5) / double(camera.width) - 1.0 + P[8]) / P[0];
  for (uint32_t y = 0; y < camera.height; ++y)
    row_[y] = (1.0 - 2.0 * (double(y) + 0.5) / double(camera.height) + P[9]) / P[5];
}

double PixelRays::worldDistance(const Ray& ray, double t) const {
  const double l = std::sqrt(ray.dir[0] * ray.dir[0] + ray.dir[1] * ray.dir[1] + ray.dir[2] * ray.dir[2]);
  return t * l * voxelSize_;
}

Ray gridRay(const Camera& camera, const GridFrame& frame, uint32_t x, uint32_t y) {
  return PixelRays(camera, frame).ray(x, y);
}

ViewHits castView(const RayGrid& grid, const GridFrame& frame, const Camera& camera, unsigned threads,
                  const std::function<void(double)>& progress) {
  ViewHits out;
  out.width = camera.width;
  out.height = camera.height;
  out.pixels.resize(size_t(camera.width) * camera.height);
  std::atomic<uint64_t> hits{0}, steps{0};  // sums: the same in any order
  std::atomic<uint32_t> rowsDone{0};
  MonotoneProgress monotone(progress);
  const PixelRays rays(camera, frame);
  // Tiles of kTile x kTile pixels share one march through empty space
  // (ray_bundle.h); a task is a band of kTile rows. The tiling does not depend
  // on the thread count, and neither does any pixel.
  constexpr uint32_t kTile = 8;  // 16 measured the same, 4 slower (more marches)
  const uint32_t bands = (camera.height + kTile - 1) / kTile;
  parallelForEach(bands, threads, 1, [&](size_t band) {
    const uint32_t y0 = uint32_t(band) * kTile, y1 = std::min(y0 + kTile, camera.height);
    uint64_t bandHits = 0, bandSteps = 0;
    RayGrid::Cursor cursor(grid);
    for (uint32_t x0 = 0; x0 < camera.width; x0 += kTile) {
      const uint32_t x1 = std::min(x0 + kTile, camera.width);
      // The pixel directions are affine in (x, y): the tile's four corner rays span them all.
      const std::array<std::array<double, 3>, 4> corners{rays.ray(x0, y0).dir, rays.ray(x1 - 1, y0).dir,
                                                         rays.ray(x0, y1 - 1).dir, rays.ray(x1 - 1, y1 - 1).dir};
      const double tStart = bundleEmptyUntil(grid, rays.ray(x0, y0).origin, corners);
      if (tStart == std::numeric_limits<double>::infinity()) continue;  // every ray of the tile misses
      for (uint32_t y = y0; y < y1; ++y) {
        PixelHit* row = out.pixels.data() + size_t(y) * camera.width;
        for (uint32_t x = x0; x < x1; ++x) {
          const Ray ray = rays.ray(x, y);
          const RayHit h = castRay(grid, ray, cursor, tStart);
          bandSteps += h.steps;
          PixelHit& p = row[x];
          if (!h.hit) continue;
          ++bandHits;
          p.hit = true;
          p.u = h.voxel.u;
          p.v = h.voxel.v;
          p.w = h.voxel.w;
          p.depth = float(rays.worldDistance(ray, h.t));
          p.faceAxis = int8_t(h.faceAxis);
          p.faceSign = int8_t(h.faceSign);
        }
      }
    }
    hits += bandHits;
    steps += bandSteps;
    const uint32_t done = rowsDone += y1 - y0;
    if ((band & 1) == 0 || done == camera.height) monotone.report(done, camera.height);
  });
  out.hitCount = hits;
  out.steps = steps;
  return out;
}

uint64_t checkStride(uint64_t pixels, uint64_t occupied, double budget) {
  const double cost = double(pixels) * double(std::max<uint64_t>(1, occupied));
  return std::max<uint64_t>(1, uint64_t(std::ceil(cost / std::max(1.0, budget))));
}

uint64_t sampledPixelCount(uint64_t pixels, uint64_t stride) {
  stride = std::max<uint64_t>(1, stride);
  return (pixels + stride - 1) / stride;
}

uint64_t sampledPixel(uint64_t sample, uint64_t pixels, uint64_t stride) {
  if (stride <= 1) return sample;
  const uint64_t begin = sample * stride, run = std::min(stride, pixels - begin);
  const uint64_t h = (sample + 1) * 0x9E3779B97F4A7C15ull;  // Fibonacci hashing: offsets spread over the run
  return begin + (h >> 32) % run;
}

ViewCheck checkView(const ViewHits& hits, const ReferenceCaster& reference, const GridFrame& frame,
                    const Camera& camera, uint64_t stride, unsigned threads,
                    const std::function<void(double)>& progress) {
  const uint64_t total = uint64_t(hits.width) * hits.height;
  const uint64_t samples = sampledPixelCount(total, stride);
  std::vector<uint8_t> differs(size_t(samples), 0);
  std::vector<RayHit> expected(static_cast<size_t>(samples));
  const PixelRays rays(camera, frame);
  MonotoneProgress monotone(progress);
  std::atomic<uint64_t> done{0};
  // Each sample writes its own slots; the mismatches are collected afterwards in pixel order.
  parallelForEach(size_t(samples), threads, 1, [&](size_t s) {
    const uint64_t i = sampledPixel(s, total, stride);
    const uint32_t x = uint32_t(i % hits.width), y = uint32_t(i / hits.width);
    const RayHit ref = reference(rays.ray(x, y));
    const PixelHit& got = hits.pixels[size_t(i)];
    const bool same =
        ref.hit == got.hit && (!ref.hit || (ref.voxel.u == got.u && ref.voxel.v == got.v && ref.voxel.w == got.w));
    if (!same) {
      differs[s] = 1;
      expected[s] = ref;
    }
    const uint64_t n = ++done;
    if ((n & 255) == 0) monotone.report(n, samples);
  });
  ViewCheck c;
  c.pixelsChecked = samples;
  for (uint64_t s = 0; s < samples; ++s) {
    if (!differs[size_t(s)]) continue;
    ++c.pixelsDiffering;
    if (c.first.size() < 10) {
      const uint64_t i = sampledPixel(s, total, stride);
      c.first.push_back({uint32_t(i % hits.width), uint32_t(i / hits.width), hits.pixels[size_t(i)], expected[size_t(s)]});
    }
  }
  return c;
}

ViewCheck checkView(const ViewHits& hits, std::span<const Coord3> occupied, const GridFrame& frame,
                    const Camera& camera, uint64_t stride, unsigned threads) {
  return checkView(
      hits, [occupied](const Ray& ray) { return castRayBruteForce(occupied, ray); }, frame, camera, stride, threads);
}

}  // namespace vox
