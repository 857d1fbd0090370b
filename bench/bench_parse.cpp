// Google Benchmark over the mesh parsers, one core: the same 100k-triangle
// sphere as OBJ text, binary STL, binary PLY and GLB, parsed from memory (OBJ,
// STL, PLY) or from a file in the page cache (GLB, through tinygltf). Reports
// bytes/s of input, the figure issue 4 asks >= 100 MB/s of.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "formats/mesh/gltf_reader.h"
#include "formats/mesh/mesh_input.h"

namespace {

struct Sphere {
  std::vector<std::array<float, 3>> v;
  std::vector<std::array<uint32_t, 3>> f;
};

Sphere sphere(int slices) {
  Sphere s;
  const int stacks = slices / 2;
  for (int i = 0; i <= stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const double th = M_PI * i / stacks, ph = 2 * M_PI * j / slices;
      const double r = 1 + 0.04 * std::sin(7 * th) * std::cos(5 * ph);
      s.v.push_back({float(r * std::sin(th) * std::cos(ph)), float(r * std::sin(th) * std::sin(ph)), float(r * std::cos(th))});
    }
  auto id = [&](int i, int j) { return uint32_t(i * slices + (j % slices)); };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      s.f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return s;
}

const Sphere& mesh() {
  static const Sphere s = sphere(316);  // 99 856 triangles
  return s;
}

template <typename T>
void put(std::string& out, const T& x) {
  out.append(reinterpret_cast<const char*>(&x), sizeof x);
}

std::string objText() {
  std::string out;
  char line[128];
  for (const auto& p : mesh().v) out.append(line, size_t(std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", p[0], p[1], p[2])));
  for (const auto& t : mesh().f) out.append(line, size_t(std::snprintf(line, sizeof line, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1)));
  return out;
}

std::string stlBinary() {
  std::string out(80, ' ');
  put(out, uint32_t(mesh().f.size()));
  for (const auto& t : mesh().f) {
    put(out, std::array<float, 3>{0, 0, 0});
    for (uint32_t i : t) put(out, mesh().v[i]);
    put(out, uint16_t(0));
  }
  return out;
}

std::string plyBinary() {
  std::string out = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(mesh().v.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(mesh().f.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : mesh().v) put(out, p);
  for (const auto& t : mesh().f) {
    put(out, uint8_t(3));
    for (uint32_t i : t) put(out, int32_t(i));
  }
  return out;
}

std::string glb() {
  const size_t vBytes = mesh().v.size() * 12, iBytes = mesh().f.size() * 12;
  std::string bin;
  for (const auto& p : mesh().v) put(bin, p);
  for (const auto& t : mesh().f) put(bin, t);
  float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
  for (const auto& p : mesh().v)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[size_t(k)]), hi[k] = std::max(hi[k], p[size_t(k)]);
  char json[2048];
  std::snprintf(json, sizeof json,
                "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
                "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
                "\"buffers\":[{\"byteLength\":%zu}],"
                "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
                "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\",\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]},"
                "{\"bufferView\":1,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}]}",
                bin.size(), vBytes, vBytes, iBytes, mesh().v.size(), lo[0], lo[1], lo[2], hi[0], hi[1], hi[2],
                mesh().f.size() * 3);
  std::string j = json;
  while (j.size() % 4) j += ' ';
  std::string out;
  put(out, uint32_t(0x46546C67));
  put(out, uint32_t(2));
  put(out, uint32_t(12 + 8 + j.size() + 8 + bin.size()));
  put(out, uint32_t(j.size()));
  put(out, uint32_t(0x4E4F534A));
  out += j;
  put(out, uint32_t(bin.size()));
  put(out, uint32_t(0x004E4942));
  out += bin;
  return out;
}

using Parser = vox::Mesh (*)(const char*, size_t, const std::string&, const vox::MeshReadOptions&,
                             std::vector<std::string>&);

void parseFromMemory(benchmark::State& state, const std::string& bytes, Parser parse) {
  vox::MeshReadOptions options;
  for (auto _ : state) {
    std::vector<std::string> warnings;
    vox::Mesh m = parse(bytes.data(), bytes.size(), "bench", options, warnings);
    if (m.triangles.size() != mesh().f.size()) state.SkipWithError("wrong triangle count");
    benchmark::DoNotOptimize(m);
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(bytes.size()));
  state.counters["MB"] = double(bytes.size()) / 1e6;
}

vox::Mesh parseObjNoBase(const char* d, size_t n, const std::string& name, const vox::MeshReadOptions& o,
                         std::vector<std::string>& w) {
  return vox::parseObj(d, n, name, o, w, ".");
}

void BM_ParseObj(benchmark::State& state) {
  static const std::string bytes = objText();
  parseFromMemory(state, bytes, parseObjNoBase);
}
void BM_ParseStlBinary(benchmark::State& state) {
  static const std::string bytes = stlBinary();
  parseFromMemory(state, bytes, vox::parseStl);
}
void BM_ParsePlyBinary(benchmark::State& state) {
  static const std::string bytes = plyBinary();
  parseFromMemory(state, bytes, vox::parsePly);
}
void BM_ReadGlb(benchmark::State& state) {
  static const std::string path = [] {
    const std::string p = (std::filesystem::temp_directory_path() / "vox_bench_parse.glb").string();
    std::ofstream(p, std::ios::binary) << glb();
    return p;
  }();
  const auto size = std::filesystem::file_size(path);
  vox::MeshReadOptions options;
  for (auto _ : state) {
    std::vector<std::string> warnings;
    vox::Mesh m = vox::readGltf(path, options, warnings);
    if (m.triangles.size() != mesh().f.size()) state.SkipWithError("wrong triangle count");
    benchmark::DoNotOptimize(m);
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(size));
  state.counters["MB"] = double(size) / 1e6;
}

BENCHMARK(BM_ParseObj)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ParseStlBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ParsePlyBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadGlb)->Unit(benchmark::kMillisecond);

}  // namespace

// One core: the OBJ reader (and glTF's image decoding) would otherwise take
// every core TBB sees; the figures here are per core.
static tbb::global_control oneCore(tbb::global_control::max_allowed_parallelism, 1);

BENCHMARK_MAIN();
