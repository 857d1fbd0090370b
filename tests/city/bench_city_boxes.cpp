// Generation time of demo:city boxes against the voxels they produce (not a
// test: scripts/bench_city.sh runs it and docs/city.md records the table).
// Usage: vox_bench_city_boxes X,Y,Z THREADS -> a Markdown table on stdout.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "libvox/scene/demo_city.h"

using namespace vox;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s X,Y,Z THREADS\n", argv[0]);
    return 2;
  }
  std::array<uint32_t, 3> e{};
  if (std::sscanf(argv[1], "%u,%u,%u", &e[0], &e[1], &e[2]) != 3) return 2;
  const unsigned threads = unsigned(std::atoi(argv[2]));
  const int32_t X = int32_t(e[0]), Y = int32_t(e[1]), Z = int32_t(e[2]);
  struct Case {
    const char* name;
    IndexBox box;
  };
  const std::vector<Case> cases = {
      {"whole city", kWholeCity},
      {"quadrant (x, z < half)", {{0, 0, 0}, {X / 2 - 1, Y - 1, Z / 2 - 1}}},
      {"ground only (y < 8)", {{0, 0, 0}, {X - 1, 7, Z - 1}}},
      {"above the ground (y >= 8)", {{0, 8, 0}, {X - 1, Y - 1, Z - 1}}},
      {"one block layer (64 <= y < 72)", {{0, 64, 0}, {X - 1, 71, Z - 1}}},
      {"high air (y >= Y - 16)", {{0, Y - 16, 0}, {X - 1, Y - 1, Z - 1}}},
      {"a 100^3 box cutting buildings", {{1000, 8, 1000}, {1099, 107, 1099}}},
  };
  std::printf("| box (extent %s, --threads %u) | box voxels | occupied produced | blocks | time [s] | ns per produced voxel |\n",
              argv[1], threads);
  std::printf("|:---|---:|---:|---:|---:|---:|\n");
  for (const Case& c : cases) {
    CityOptions o;
    o.extent = e;
    o.threads = threads;
    o.box = c.box;
    const auto t0 = std::chrono::steady_clock::now();
    VoxelBlocks blocks = buildCityBlocks(o);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    uint64_t occupied = 0;
    for (const VoxelBlock* b : blocks.sortedBlocks())
      for (uint64_t word : b->occupied) occupied += uint64_t(__builtin_popcountll(word));
    IndexBox b = c.box;
    b.max = {std::min(b.max.u, X - 1), std::min(b.max.v, Y - 1), std::min(b.max.w, Z - 1)};
    const double volume = double(b.max.u - b.min.u + 1) * double(b.max.v - b.min.v + 1) * double(b.max.w - b.min.w + 1);
    std::printf("| %s | %.3g | %llu | %zu | %.3f | %s |\n", c.name, volume, (unsigned long long)occupied,
                blocks.blockCount(), s, occupied ? std::to_string(int(s * 1e9 / double(occupied))).c_str() : "-");
  }
  return 0;
}
