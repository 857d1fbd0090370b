// Textures decoded while the mesh is baked (VoxelizeSettings::awaitTextures,
// formats/mesh/deferred_textures.h): the bake takes texels only after the
// pixels are in, and its colours are those of a bake whose textures were
// there from the start, at any thread count.
#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include "formats/mesh/deferred_textures.h"
#include "formats/mesh/gltf_reader.h"
#include "libvox/core/error.h"
#include "libvox/scene/voxelize_scene.h"
#include "test_util.h"
#include "voxelize_test_meshes.h"

using namespace vox;

namespace {

/// A 16 x 16 voxel square at z = 0.5 textured by a 2 x 2 nearest-filtered
/// texture (each quarter of the square one texel), next to an untextured
/// square of the same material's factor (its pieces are coloured during the
/// geometry), sharing voxels along x = 16.
Mesh texturedSquares() {
  Mesh m = voxtest::meshOf({{0, 0, 0.5}, {16, 0, 0.5}, {16, 16, 0.5}, {0, 16, 0.5},  // textured
                            {16, 0, 0.5}, {30, 0, 0.5}, {30, 16, 0.5}, {16, 16, 0.5}},
                           {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}});
  m.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}};  // glTF: t = 0 is the top row
  m.textures.push_back(voxtest::quadrantTexture());  // top row: red, green; bottom row: blue, sRGB 188 grey
  m.materials[0].texture = 0;
  m.materials[0].baseColorFactor = {1, 1, 0.5f, 1};
  m.materials.push_back({"plain", {0.25f, 0.5f, 0.75f, 1}, -1, 0});
  m.triangleMaterial = {0, 0, 1, 1};
  return m;
}

using Colours = std::map<std::tuple<int, int, int>, std::array<float, 3>>;

Colours colours(const Scene& s) {
  Colours out;
  s.forEachVoxel([&](const VoxelView& v) {
    if (v.color) out[{v.at.u, v.at.v, v.at.w}] = {v.color->r, v.color->g, v.color->b};
  });
  return out;
}

SceneHeader squaresHeader() {
  SceneHeader h = voxtest::twoClassHeader({32, 16, 1});
  return h;
}

}  // namespace

TEST(DeferredTextures, TheBakeSamplesTexturesOnlyOnceTheyAreAwaited) {
  const Mesh ready = texturedSquares();
  const std::vector<uint8_t> cls(ready.triangles.size(), 1);
  VoxelizeSettings plain;
  const Colours expected = colours(voxelizeMesh(ready, cls, squaresHeader(), plain));
  ASSERT_FALSE(expected.empty());

  for (unsigned threads : {1u, 2u}) {
    Mesh late = texturedSquares();
    const MeshTexture pixels = late.textures[0];
    late.textures[0].width = late.textures[0].height = 0;  // as a deferred read leaves it
    late.textures[0].rgba.clear();
    int calls = 0;
    VoxelizeSettings s;
    s.threads = threads;
    s.awaitTextures = [&](bool wait) {
      ++calls;
      if (wait) late.textures[0] = pixels;  // not decoded when first asked
      return wait;
    };
    const Colours got = colours(voxelizeMesh(late, cls, squaresHeader(), s));
    EXPECT_EQ(calls, 2) << "threads " << threads << ": asked without waiting, then waiting";
    EXPECT_EQ(got, expected) << "threads " << threads << ": colours differ from the bake with pixels from the start";
    // The known texels (a texel taken before the pixels were in would be white).
    ASSERT_TRUE(got.count({2, 13, 0}));
    EXPECT_EQ(got.at({2, 13, 0})[0], 1.0f) << "top-left texel: red";
    EXPECT_EQ(got.at({2, 13, 0})[1], 0.0f);
    EXPECT_EQ(got.at({13, 13, 0})[1], 1.0f) << "top-right texel: green";
    EXPECT_EQ(got.at({13, 13, 0})[0], 0.0f);
    EXPECT_NEAR(got.at({2, 2, 0})[2], 0.5f, 1e-4) << "bottom-left: blue x factor 0.5";
    EXPECT_NEAR(got.at({13, 2, 0})[0], 0.50289f, 1e-3) << "sRGB 188 decodes to linear 0.5029";
    EXPECT_NEAR(got.at({24, 8, 0})[1], 0.5f, 1e-4) << "the untextured square keeps its factor";
  }
}

TEST(DeferredTextures, AnErrorFromTheAwaitEndsTheBake) {
  Mesh late = texturedSquares();
  late.textures[0].width = late.textures[0].height = 0;
  late.textures[0].rgba.clear();
  VoxelizeSettings s;
  s.threads = 2;
  s.awaitTextures = [](bool wait) {
    if (wait) throwBadInput("m.glb: image 0 cannot be decoded (test)");
    return false;
  };
  EXPECT_THROW(voxelizeMesh(late, std::vector<uint8_t>(late.triangles.size(), 1), squaresHeader(), s), Error);
}

TEST(DeferredTextures, AGltfReadLeavesThePixelsToFinish) {
  // A 2 x 2 RGBA PNG (red, green / blue, white) as a data URI on a textured triangle.
  const std::string png =
      "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAEklEQVR4nGP4z8DwHwyBNBgAAEnICff5q7YNAAAAAElFTkSuQmCC";
  auto gltf = [&](const std::string& image) {
    return std::string(R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":0}]}],
      "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
      "textures":[{"source":0}],"images":[{"uri":"data:image/png;base64,)") + image + R"("}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                   {"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}],
      "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24}],
      "buffers":[{"byteLength":60,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/"}]})";
  };
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("ok.gltf"), gltf(png));
  std::vector<std::string> warnings;
  const Mesh now = readGltf(dir.file("ok.gltf"), {}, warnings);
  ASSERT_EQ(now.textures.size(), 1u);
  ASSERT_EQ(now.textures[0].width, 2u);

  DeferredTextures deferred;
  Mesh later = readGltf(dir.file("ok.gltf"), {}, warnings, &deferred);
  ASSERT_EQ(later.textures.size(), 1u);
  EXPECT_EQ(later.textures[0].width, 0u) << "no pixels before finish()";
  EXPECT_EQ(deferred.pendingImages(), 1u);
  EXPECT_EQ(deferred.pendingPixelBytes(), 16u) << "2 x 2 RGBA, from the header";
  deferred.finish(later);
  EXPECT_EQ(deferred.pendingImages(), 0u);
  EXPECT_EQ(deferred.decodedImages(), 1u);
  EXPECT_EQ(later.textures[0].width, 2u);
  EXPECT_EQ(later.textures[0].rgba, now.textures[0].rgba);

  // An image that does not decode: the read succeeds, finish() throws what a decoding read throws.
  voxtest::writeText(dir.file("bad.gltf"), gltf("Z2FyYmFnZSBieXRlcw=="));
  std::string direct;
  try {
    readGltf(dir.file("bad.gltf"), {}, warnings);
  } catch (const Error& e) {
    direct = e.what();
  }
  ASSERT_NE(direct.find("cannot be decoded"), std::string::npos) << direct;
  DeferredTextures failing;
  Mesh bad = readGltf(dir.file("bad.gltf"), {}, warnings, &failing);
  try {
    failing.finish(bad);
    ADD_FAILURE() << "finish() accepted an undecodable image";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), direct);
    EXPECT_EQ(e.kind, ErrorKind::BadInput);
  }
}
