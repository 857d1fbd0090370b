#include "libvox/render/render.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

namespace vox {

namespace {

unsigned workerCount(unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  return threads;
}

// Rows in blocks handed out through an atomic counter; each pixel is written
// by exactly one worker, so the output does not depend on scheduling.
template <typename Fn>
void parallelRows(uint32_t height, unsigned threads, Fn&& rowFn) {
  std::atomic<uint32_t> next{0};
  auto worker = [&] {
    for (uint32_t y; (y = next.fetch_add(1)) < height;) rowFn(y);
  };
  const unsigned n = std::min<unsigned>(workerCount(threads), std::max<uint32_t>(1, height));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

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
  std::atomic<uint64_t> hits{0}, steps{0};
  std::atomic<uint32_t> rowsDone{0};
  const PixelRays rays(camera, frame);
  parallelRows(camera.height, threads, [&](uint32_t y) {
    uint64_t rowHits = 0, rowSteps = 0;
    PixelHit* row = out.pixels.data() + size_t(y) * camera.width;
    RayGrid::Cursor cursor(grid);
    for (uint32_t x = 0; x < camera.width; ++x) {
      const Ray ray = rays.ray(x, y);
      const RayHit h = castRay(grid, ray, cursor);
      rowSteps += h.steps;
      PixelHit& p = row[x];
      if (!h.hit) continue;
      ++rowHits;
      p.hit = true;
      p.u = h.voxel.u;
      p.v = h.voxel.v;
      p.w = h.voxel.w;
      p.depth = float(rays.worldDistance(ray, h.t));
      p.faceAxis = int8_t(h.faceAxis);
      p.faceSign = int8_t(h.faceSign);
    }
    hits += rowHits;
    steps += rowSteps;
    const uint32_t done = ++rowsDone;
    if (progress && (done & 15) == 0) progress(double(done) / camera.height);
  });
  out.hitCount = hits;
  out.steps = steps;
  return out;
}

ViewCheck checkView(const ViewHits& hits, std::span<const Coord3> occupied, const GridFrame& frame,
                    const Camera& camera, uint64_t stride, unsigned threads) {
  if (stride == 0) stride = 1;
  const uint64_t total = uint64_t(hits.width) * hits.height;
  const uint64_t samples = (total + stride - 1) / stride;
  std::vector<uint8_t> differs(size_t(samples), 0);
  std::vector<RayHit> expected(static_cast<size_t>(samples));
  std::atomic<uint64_t> next{0};
  const PixelRays rays(camera, frame);
  auto worker = [&] {
    for (uint64_t s; (s = next.fetch_add(1)) < samples;) {
      const uint64_t i = s * stride;
      const uint32_t x = uint32_t(i % hits.width), y = uint32_t(i / hits.width);
      const RayHit ref = castRayBruteForce(occupied, rays.ray(x, y));
      const PixelHit& got = hits.pixels[size_t(i)];
      const bool same = ref.hit == got.hit &&
                        (!ref.hit || (ref.voxel.u == got.u && ref.voxel.v == got.v && ref.voxel.w == got.w));
      if (!same) {
        differs[size_t(s)] = 1;
        expected[size_t(s)] = ref;
      }
    }
  };
  const unsigned n = std::min<unsigned>(workerCount(threads), unsigned(std::max<uint64_t>(1, samples)));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  ViewCheck c;
  c.pixelsChecked = samples;
  for (uint64_t s = 0; s < samples; ++s) {
    if (!differs[size_t(s)]) continue;
    ++c.pixelsDiffering;
    if (c.first.size() < 10) {
      const uint64_t i = s * stride;
      c.first.push_back({uint32_t(i % hits.width), uint32_t(i / hits.width), hits.pixels[size_t(i)], expected[size_t(s)]});
    }
  }
  return c;
}

int canonicalBits(const Dims& dims) {
  const uint64_t maxCoord = uint64_t(dims.maxAxis()) - 1;
  return maxCoord <= 255 ? 8 : maxCoord <= 65535 ? 16 : 32;
}

std::array<double, 3> terrainShade(const std::array<double, 3>& base, const std::array<int, 3>& normal) {
  // terrain.wgsl: sunDir = normalize(-0.4, -0.85, -0.5); diffuse = max(dot(n, -sunDir), 0) * sunColor;
  // skyFactor = clamp(n.y * 0.5 + 0.5, 0, 1); ambient = mix(horizon, sky, skyFactor) * 0.55.
  const double sl = std::sqrt(0.4 * 0.4 + 0.85 * 0.85 + 0.5 * 0.5);
  const double sun[3] = {-0.4 / sl, -0.85 / sl, -0.5 / sl};
  const double sunColor[3] = {1.0, 0.97, 0.9};
  const double horizon[3] = {0.18, 0.16, 0.12};
  const double n[3] = {double(normal[0]), double(normal[1]), double(normal[2])};
  const double diffuse = std::max(-(n[0] * sun[0] + n[1] * sun[1] + n[2] * sun[2]), 0.0);
  const double skyFactor = std::clamp(n[1] * 0.5 + 0.5, 0.0, 1.0);
  std::array<double, 3> out;
  for (int c = 0; c < 3; ++c) {
    const double ambient = (horizon[c] * (1.0 - skyFactor) + kSkyColor[size_t(c)] * skyFactor) * 0.55;
    out[size_t(c)] = base[size_t(c)] * (ambient + diffuse * sunColor[c]);
  }
  return out;
}

std::array<double, 3> facePaletteColor(const ClassInfo* info, const std::array<int, 3>& normal) {
  if (!info) return {0.5, 0.5, 0.5};
  Rgb8 c = info->color;
  if (info->faces) c = normal[1] > 0 ? info->faces->top : normal[1] < 0 ? info->faces->bottom : info->faces->side;
  return {c.r / 255.0, c.g / 255.0, c.b / 255.0};
}

std::array<int, 3> hitNormal(const PixelHit& hit, const Vec3d& dir) {
  std::array<int, 3> n{0, 0, 0};
  if (hit.faceAxis >= 0) {
    n[size_t(hit.faceAxis)] = hit.faceSign;
    return n;
  }
  int a = 0;
  for (int i = 1; i < 3; ++i)
    if (std::fabs(dir[size_t(i)]) > std::fabs(dir[size_t(a)])) a = i;
  n[size_t(a)] = dir[size_t(a)] > 0 ? -1 : 1;
  return n;
}

}  // namespace vox
