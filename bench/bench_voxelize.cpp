// Google Benchmark kernels for the voxelizer: an analytic sphere mesh of about
// 100k triangles (the size of a typical scan) at 256 and 512 voxels, surface
// and solid fill. Parsing and writing are measured end to end by
// scripts/bench_voxelize.sh; these isolate the voxelizing itself.
#include <benchmark/benchmark.h>

#include <cmath>

#include "libvox/scene/voxelize_scene.h"

namespace {

vox::Mesh sphere(int slices) {
  vox::Mesh m;
  const int stacks = slices / 2;
  for (int i = 0; i <= stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const double th = M_PI * i / stacks, ph = 2 * M_PI * j / slices;
      m.positions.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
  auto id = [&](int i, int j) { return uint32_t(i * slices + (j % slices)); };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  m.triangleMaterial.assign(m.triangles.size(), 0);
  m.trianglePart.assign(m.triangles.size(), 0);
  m.materials.push_back({});
  m.parts.push_back({"sphere", "sphere"});
  return m;
}

void run(benchmark::State& state, vox::FillMode fill) {
  static const vox::Mesh mesh = sphere(316);  // 316 * 158 * 2 = 99 856 triangles
  const uint32_t res = uint32_t(state.range(0));
  vox::SceneHeader h;
  h.dims = {res, res, res};
  h.voxelSize = 2.0 / res;
  h.origin = {-1, -1, -1};
  h.classes.add({1, "sphere", {200, 200, 200}, std::nullopt});
  const std::vector<uint8_t> cls(mesh.triangles.size(), 1);
  vox::VoxelizeSettings s;
  s.fill = fill;
  s.threads = unsigned(state.range(1));
  uint64_t voxels = 0;
  for (auto _ : state) {
    vox::Scene scene = vox::voxelizeMesh(mesh, cls, h, s);
    voxels = scene.occupiedCount();
    benchmark::DoNotOptimize(voxels);
  }
  state.counters["triangles"] = double(mesh.triangles.size());
  state.counters["voxels"] = double(voxels);
}

void BM_Surface(benchmark::State& s) { run(s, vox::FillMode::Surface); }
void BM_Solid(benchmark::State& s) { run(s, vox::FillMode::Solid); }

}  // namespace

BENCHMARK(BM_Surface)->Args({256, 1})->Args({256, 2})->Args({512, 2})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Solid)->Args({256, 2})->Args({512, 2})->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
