// Google Benchmark kernels of render-canonical: the exact DDA (castRay) and
// the brute-force reference on the 128^3 demo hamlet, one thread.
#include <benchmark/benchmark.h>

#include "libvox/scene/demo_hamlet.h"
#include "libvox/render/render.h"
#include "libvox/scene/render_scene.h"

namespace {

struct Fixture {
  vox::Scene scene;
  vox::RayGrid grid;
  vox::GridFrame frame;
  vox::Camera camera;
  static Fixture& get() {
    static Fixture f = [] {
      vox::HamletOptions o;
      o.resolution = 128;
      vox::Scene s = vox::buildHamlet(o);
      vox::RayGrid g = vox::rayGridFromScene(s);
      const vox::GridFrame fr{s.header().origin, s.header().voxelSize};
      return Fixture{std::move(s), std::move(g), fr,
                     vox::Camera::lookAt({20, 15, 20}, {0, 2, 0}, {0, 1, 0}, 50, 320, 180)};
    }();
    return f;
  }
};

void BM_CastRayView(benchmark::State& state) {
  Fixture& f = Fixture::get();
  uint64_t rays = 0;
  for (auto _ : state) {
    const vox::ViewHits h = vox::castView(f.grid, f.frame, f.camera, 1);
    benchmark::DoNotOptimize(h.hitCount);
    rays += h.pixels.size();
  }
  state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CastRayView)->Unit(benchmark::kMillisecond);

void BM_BruteForceRay(benchmark::State& state) {
  Fixture& f = Fixture::get();
  const std::vector<vox::Coord3> occupied = f.grid.occupiedVoxels();
  const vox::Ray r = vox::gridRay(f.camera, f.frame, 160, 90);
  for (auto _ : state) benchmark::DoNotOptimize(vox::castRayBruteForce(occupied, r));
  state.counters["voxel tests/s"] =
      benchmark::Counter(double(occupied.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BruteForceRay)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
