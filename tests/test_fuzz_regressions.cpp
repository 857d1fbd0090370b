// Every input the fuzzers found a fault with (tests/fuzz/regressions/<target>/)
// and every committed seed (tests/fuzz/seeds/<target>/), run through the
// target's own entry point (tests/fuzz/fuzz_<target>.cpp compiled with
// VOX_FUZZ_REPLAY), so the fixes stay covered without clang. A regression
// that comes back crashes or aborts this test, or throws past it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "formats/image/image.h"
#include "formats/mesh/gltf_reader.h"
#include "libvox/core/error.h"
#include "test_util.h"

#define VOX_FUZZ_DECLARE(name) int voxFuzz_##name(const uint8_t* data, size_t size);
VOX_FUZZ_DECLARE(gltf)
VOX_FUZZ_DECLARE(blockmap)
VOX_FUZZ_DECLARE(classes)
VOX_FUZZ_DECLARE(camera)
VOX_FUZZ_DECLARE(touched)
VOX_FUZZ_DECLARE(classtable)
VOX_FUZZ_DECLARE(rendermeta)
VOX_FUZZ_DECLARE(atlasmeta)
VOX_FUZZ_DECLARE(png)
VOX_FUZZ_DECLARE(exr)

namespace {

namespace fs = std::filesystem;

/// The files of tests/fuzz/<kind>/<target>/, sorted (none when the folder is absent).
std::vector<fs::path> inputsOf(const std::string& kind, const std::string& target) {
  std::vector<fs::path> files;
  const fs::path dir = fs::path(voxtest::sourceDir()) / "tests" / "fuzz" / kind / target;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// Runs every regression and seed of `target`; returns how many ran.
size_t replay(const std::string& target, int (*entry)(const uint8_t*, size_t)) {
  size_t count = 0;
  for (const char* kind : {"regressions", "seeds"})
    for (const fs::path& file : inputsOf(kind, target)) {
      SCOPED_TRACE(file.string());
      std::ifstream in(file, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_EQ(entry(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()), 0);
      ++count;
    }
  return count;
}

}  // namespace

#define VOX_FUZZ_REPLAY_TEST(name) \
  TEST(FuzzRegressions, name) { EXPECT_GT(replay(#name, &voxFuzz_##name), 0u) << "no seeds for " #name; }

VOX_FUZZ_REPLAY_TEST(gltf)
VOX_FUZZ_REPLAY_TEST(blockmap)
VOX_FUZZ_REPLAY_TEST(classes)
VOX_FUZZ_REPLAY_TEST(camera)
VOX_FUZZ_REPLAY_TEST(touched)
VOX_FUZZ_REPLAY_TEST(classtable)
VOX_FUZZ_REPLAY_TEST(rendermeta)
VOX_FUZZ_REPLAY_TEST(atlasmeta)
VOX_FUZZ_REPLAY_TEST(png)
VOX_FUZZ_REPLAY_TEST(exr)

// The file reader shares the fuzzed decoder's checks: each PNG regression is
// refused (vox::Error) by readPng too, before its pixels are allocated.
TEST(FuzzRegressions, pngFileReader) {
  for (const fs::path& file : inputsOf("regressions", "png")) {
    SCOPED_TRACE(file.string());
    EXPECT_THROW(vox::readPng(file.string()), vox::Error);
  }
}

// The fuzzed in-memory glTF path is the file path: readGltf of each seed file
// gives what readGltfMemory gives for its bytes.
TEST(FuzzRegressions, gltfMemoryIsFilePath) {
  for (const fs::path& file : inputsOf("seeds", "gltf")) {
    SCOPED_TRACE(file.string());
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::string> w1, w2;
    const vox::Mesh a = vox::readGltf(file.string(), {}, w1);
    const vox::Mesh b = vox::readGltfMemory(bytes, file.string(), file.extension() == ".glb", {}, w2);
    EXPECT_GT(a.triangles.size(), 0u);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.triangleMaterial, b.triangleMaterial);
    EXPECT_EQ(a.uv0, b.uv0);
    EXPECT_EQ(a.colors, b.colors);
    EXPECT_EQ(a.textures.size(), b.textures.size());
    EXPECT_EQ(a.filesRead, b.filesRead);
    EXPECT_EQ(w1, w2);
  }
}

// An empty .glb is refused by name (tinygltf's file loader indexed past the
// end of the empty buffer: std::out_of_range, reported as an internal error).
TEST(FuzzRegressions, gltfEmptyFiles) {
  std::vector<std::string> w;
  EXPECT_THROW(vox::readGltfMemory("", "empty.glb", true, {}, w), vox::Error);
  EXPECT_THROW(vox::readGltfMemory("", "empty.gltf", false, {}, w), vox::Error);
}
