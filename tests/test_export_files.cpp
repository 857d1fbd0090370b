// The exporters' files read back by other code: glTF through tinygltf (an
// independent parser), PLY and MagicaVoxel byte layouts against their specs,
// and the palette quantiser.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>

#include "formats/core/file_util.h"
#include "formats/core/uri_segment.h"
#include "formats/export/gltf_writer.h"
#include "formats/export/magicavoxel_writer.h"
#include "formats/export/vdb_volume_writer.h"
#include "formats/vdb/vdb_structure.h"
#include "formats/export/ply_writer.h"
#include "libvox/core/color_quantize.h"
#include "libvox/core/block_mesh.h"
#include "libvox/core/error.h"
#include "test_util.h"

namespace {

vox::ClassTable paletteTable() {
  vox::ClassTable t;
  t.add({1, "Grass", {87, 173, 92}, vox::FacePalette{{87, 173, 92}, {102, 77, 41}, {115, 148, 77}}});
  t.add({3, "Stone", {148, 153, 163}, std::nullopt});
  return t;
}

// Two blocks of different classes side by side, and one apart.
vox::BlockMesh smallMesh() {
  vox::ClassVolume vol({{0, 0, 0}, {7, 7, 7}}, false);
  vox::ClassVolume::Brick b = vol.makeBrick({0, 0, 0});
  b.classes[size_t(vox::ClassVolume::voxelIndex(0, 0, 0))] = 1;
  b.classes[size_t(vox::ClassVolume::voxelIndex(1, 0, 0))] = 3;
  b.classes[size_t(vox::ClassVolume::voxelIndex(5, 5, 5))] = 1;
  vol.add(std::move(b));
  vol.finish();
  return vox::meshVisibleFaces(vol, paletteTable(), {});
}

// With VOX_EXPORT_KEEP_DIR set, written files are copied there for the Khronos
// validator (tests/export/validate_unit_files.sh, a CTest test).
void keep(const std::string& path) {
  if (const char* dir = std::getenv("VOX_EXPORT_KEEP_DIR"))
    std::filesystem::copy_file(path, std::filesystem::path(dir) / std::filesystem::path(path).filename(),
                               std::filesystem::copy_options::overwrite_existing);
}

template <typename T>
std::vector<T> accessorValues(const tinygltf::Model& m, int accessor, size_t components) {
  const tinygltf::Accessor& a = m.accessors[size_t(accessor)];
  const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
  const size_t stride = v.byteStride ? v.byteStride : components * sizeof(T);
  std::vector<T> out;
  const uint8_t* base = m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset;
  for (size_t i = 0; i < a.count; ++i)
    for (size_t c = 0; c < components; ++c) {
      T x;
      std::memcpy(&x, base + i * stride + c * sizeof(T), sizeof(T));
      out.push_back(x);
    }
  return out;
}

// A percent-encoded URI's bytes (RFC 3986), for keeping a buffer under the
// name it decodes to, as the validator looks it up.
std::string uriDecoded(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i)
    if (uri[i] == '%' && i + 2 < uri.size()) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  return out;
}

tinygltf::Model load(const std::string& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = path.ends_with(".glb") ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                                         : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  EXPECT_TRUE(ok) << err;
  EXPECT_EQ(warn, "");
  keep(path);
  for (const tinygltf::Buffer& b : model.buffers)
    if (!b.uri.empty()) keep((std::filesystem::path(path).parent_path() / uriDecoded(b.uri)).string());
  return model;
}

vox::GltfScene sceneOf(const vox::BlockMesh& mesh, bool indexed) {
  vox::GltfScene s;
  s.name = "small";
  s.generator = "test";
  s.frame = {{-8.0, 0.0, -8.0}, 2.0};
  s.indexed = indexed;
  s.materials = {{"blocks", std::nullopt}};
  s.primitives = {{mesh.quads, 0}};
  return s;
}

TEST(GltfWriter, GlbReadsBackAsTheRenderersVertexStream) {
  voxtest::TempDir dir;
  const vox::BlockMesh mesh = smallMesh();
  ASSERT_EQ(mesh.quads.size(), 16u);
  const vox::GltfScene scene = sceneOf(mesh, false);
  const vox::GltfWriteResult r = vox::writeGlb(scene, dir.file("a.glb"));
  EXPECT_EQ(r.vertices, 96u);
  EXPECT_EQ(r.triangles, 32u);
  EXPECT_EQ(r.indices, 0u);
  EXPECT_EQ(r.fileBytes, uint64_t(std::filesystem::file_size(dir.file("a.glb"))));
  const tinygltf::Model m = load(dir.file("a.glb"));
  ASSERT_EQ(m.meshes.size(), 1u);
  ASSERT_EQ(m.meshes[0].primitives.size(), 1u);
  const tinygltf::Primitive& p = m.meshes[0].primitives[0];
  EXPECT_EQ(p.indices, -1);
  EXPECT_EQ(p.mode, TINYGLTF_MODE_TRIANGLES);
  const auto pos = accessorValues<float>(m, p.attributes.at("POSITION"), 3);
  const auto nrm = accessorValues<float>(m, p.attributes.at("NORMAL"), 3);
  const auto col = accessorValues<float>(m, p.attributes.at("COLOR_0"), 3);
  const auto uv = accessorValues<float>(m, p.attributes.at("TEXCOORD_0"), 2);
  ASSERT_EQ(pos.size(), 96u * 3);
  // Six vertices per quad: corners 0,1,2,0,2,3.
  for (size_t q = 0; q < mesh.quads.size(); ++q) {
    const auto corners = vox::quadVertices(mesh.quads[q], scene.frame);
    for (size_t k = 0; k < 6; ++k) {
      const vox::BlockVertex& v = corners[vox::kQuadTriangles[k]];
      const size_t i = q * 6 + k;
      for (size_t a = 0; a < 3; ++a) {
        ASSERT_EQ(pos[i * 3 + a], v.position[a]);
        ASSERT_EQ(nrm[i * 3 + a], v.normal[a]);
        ASSERT_EQ(col[i * 3 + a], v.color[a]);
      }
      ASSERT_EQ(uv[i * 2], v.uv[0]);
      ASSERT_EQ(uv[i * 2 + 1], v.uv[1]);
    }
  }
  // POSITION bounds: blocks (0..1, 0, 0) and (5, 5, 5) at voxel size 2, origin (-8, 0, -8).
  const tinygltf::Accessor& pa = m.accessors[size_t(p.attributes.at("POSITION"))];
  EXPECT_EQ(pa.minValues, (std::vector<double>{-8, 0, -8}));
  EXPECT_EQ(pa.maxValues, (std::vector<double>{4, 12, 4}));
  EXPECT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].pbrMetallicRoughness.metallicFactor, 0.0);
}

// Over many batches (the writer expands 32768 quads at a time, the next batch
// on a second thread with threads > 1): the same bytes at any thread count,
// and POSITION's bounds (taken from the quads' integer corners, not from the
// vertices) equal to those of every vertex, with rectangles of several
// extents, an origin off zero and a voxel size that is not a power of two.
TEST(GltfWriter, ManyBatchesGiveTheSameBytesAtAnyThreadCountAndExactBounds) {
  voxtest::TempDir dir;
  vox::BlockMesh mesh;
  uint32_t h = 12345;
  auto next = [&h] { h = h * 1664525u + 1013904223u; return h >> 8; };
  for (int i = 0; i < 100000; ++i) {
    vox::BlockQuad q;
    q.block = {int32_t(next() % 3000) - 1000, int32_t(next() % 700), int32_t(next() % 2000) - 1500};
    q.face = vox::BlockFace(next() % 6);
    q.extent = {1 + next() % 9, 1 + next() % 5};
    q.classId = 1;
    q.color = {0.25f, 0.5f, float(next() % 100) / 100.0f};
    mesh.quads.push_back(q);
  }
  for (bool indexed : {false, true}) {
    vox::GltfScene scene = sceneOf(mesh, indexed);
    scene.frame = {{-3.7, 1e3, 0.123}, 0.3};
    std::string bytes;
    for (unsigned threads : {1u, 2u, 3u}) {
      scene.threads = threads;
      const std::string file = dir.file("m" + std::to_string(threads) + ".glb");
      vox::writeGlb(scene, file);
      const std::string got = vox::readFileBytes(file);
      if (threads == 1) bytes = got;
      else EXPECT_TRUE(got == bytes) << "threads " << threads << (indexed ? ", indexed" : "");
    }
    std::array<float, 3> lo, hi;
    lo.fill(INFINITY);
    hi.fill(-INFINITY);
    for (const vox::BlockQuad& q : mesh.quads)
      for (const vox::BlockVertex& v : vox::quadVertices(q, scene.frame))
        for (size_t a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], v.position[a]);
          hi[a] = std::max(hi[a], v.position[a]);
        }
    const tinygltf::Model m = load(dir.file("m1.glb"));
    const tinygltf::Accessor& pa = m.accessors[size_t(m.meshes[0].primitives[0].attributes.at("POSITION"))];
    for (size_t a = 0; a < 3; ++a) {
      EXPECT_EQ(float(pa.minValues[a]), lo[a]) << "axis " << a;
      EXPECT_EQ(float(pa.maxValues[a]), hi[a]) << "axis " << a;
    }
  }
}

TEST(GltfWriter, IndexedGltfSharesTheQuadCorners) {
  voxtest::TempDir dir;
  const vox::BlockMesh mesh = smallMesh();
  const vox::GltfWriteResult r =
      vox::writeGltf(sceneOf(mesh, true), dir.file("b.gltf"), dir.file("b.bin"), "b.bin");
  EXPECT_EQ(r.vertices, 64u);
  EXPECT_EQ(r.indices, 96u);
  // 64 vertices * 44 bytes + 96 uint16 indices; 96 vertices * 44 without indices.
  EXPECT_EQ(r.bufferBytes, 64u * 44 + 96 * 2);
  EXPECT_EQ(r.unindexedBufferBytes, 96u * 44);
  EXPECT_EQ(std::filesystem::file_size(dir.file("b.bin")), r.bufferBytes);
  const tinygltf::Model m = load(dir.file("b.gltf"));
  const tinygltf::Primitive& p = m.meshes[0].primitives[0];
  ASSERT_GE(p.indices, 0);
  EXPECT_EQ(m.accessors[size_t(p.indices)].componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  const auto idx = accessorValues<uint16_t>(m, p.indices, 1);
  ASSERT_EQ(idx.size(), 96u);
  for (size_t q = 0; q < 16; ++q)
    for (size_t k = 0; k < 6; ++k) EXPECT_EQ(idx[q * 6 + k], q * 4 + vox::kQuadTriangles[k]);
  const auto pos = accessorValues<float>(m, p.attributes.at("POSITION"), 3);
  const auto corners = vox::quadVertices(mesh.quads[5], {{-8.0, 0.0, -8.0}, 2.0});
  for (size_t c = 0; c < 4; ++c)
    for (size_t a = 0; a < 3; ++a) EXPECT_EQ(pos[(5 * 4 + c) * 3 + a], corners[c].position[a]);
}

TEST(GltfWriter, OnePrimitiveAndMaterialPerClass) {
  voxtest::TempDir dir;
  const vox::BlockMesh mesh = smallMesh();
  const auto groups = vox::quadsByClass(mesh);
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].size(), 11u);  // Grass: 5 faces + 6 faces
  EXPECT_EQ(groups[1].size(), 5u);
  vox::GltfScene s = sceneOf(mesh, false);
  s.materials = {{"Grass", 1}, {"Stone", 3}};
  s.primitives = {{groups[0], 0}, {groups[1], 1}};
  vox::writeGlb(s, dir.file("c.glb"));
  const tinygltf::Model m = load(dir.file("c.glb"));
  ASSERT_EQ(m.meshes[0].primitives.size(), 2u);
  EXPECT_EQ(m.materials[1].name, "Stone");
  EXPECT_EQ(m.materials[1].extras.Get("vox_class_id").GetNumberAsInt(), 3);
  EXPECT_EQ(m.accessors[size_t(m.meshes[0].primitives[1].attributes.at("POSITION"))].count, 30u);
}

TEST(GltfWriter, AnEmptyMeshIsAValidEmptyFile) {
  voxtest::TempDir dir;
  vox::GltfScene s;
  s.name = "empty";
  vox::writeGlb(s, dir.file("e.glb"));
  const tinygltf::Model m = load(dir.file("e.glb"));
  EXPECT_TRUE(m.meshes.empty());
  EXPECT_TRUE(m.buffers.empty());
  ASSERT_EQ(m.scenes.size(), 1u);
  const vox::GltfWriteResult r = vox::writeGltf(s, dir.file("e.gltf"), dir.file("e.bin"), "e.bin");
  EXPECT_EQ(r.bufferBytes, 0u);
  EXPECT_FALSE(std::filesystem::exists(dir.file("e.bin")));
}

TEST(UriPathSegment, KeepsUnreservedCharactersAndEncodesEveryOtherByte) {
  EXPECT_EQ(vox::uriPathSegment("hamlet.bin"), "hamlet.bin");
  EXPECT_EQ(vox::uriPathSegment("Az09-._~!*'().bin"), "Az09-._~!*'().bin");
  EXPECT_EQ(vox::uriPathSegment("a#b.bin"), "a%23b.bin");  // not a fragment
  EXPECT_EQ(vox::uriPathSegment("a%b.bin"), "a%25b.bin");
  EXPECT_EQ(vox::uriPathSegment("a b.bin"), "a%20b.bin");
  EXPECT_EQ(vox::uriPathSegment("a?b+c:d/e&f.bin"), "a%3Fb%2Bc%3Ad%2Fe%26f.bin");  // '+' is a space to form decoders
  EXPECT_EQ(vox::uriPathSegment("\xC3\xA9t\xC3\xA9.bin"), "%C3%A9t%C3%A9.bin");     // UTF-8 "été"
  EXPECT_EQ(vox::uriPathSegment("\xE9.bin"), "%E9.bin");  // a Latin-1 name: its own byte
  EXPECT_EQ(vox::uriPathSegment(""), "");
}

// The .gltf names its .bin by a relative URI: a name with '#', '%', '+', a
// space or UTF-8 is percent-encoded, and a reader that decodes it (tinygltf,
// the validator) finds the file.
TEST(GltfWriter, TheBufferUriIsTheBinsNamePercentEncoded) {
  voxtest::TempDir dir;
  const vox::BlockMesh mesh = smallMesh();
  const std::string bin = "a b#c%d+\xC3\xA9.bin";
  const vox::GltfWriteResult r = vox::writeGltf(sceneOf(mesh, false), dir.file("uri.gltf"), dir.file(bin), bin);
  std::ifstream in(dir.file("uri.gltf"));
  const nlohmann::json doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc["buffers"][0]["uri"], "a%20b%23c%25d%2B%C3%A9.bin");
  const tinygltf::Model m = load(dir.file("uri.gltf"));
  ASSERT_EQ(m.buffers.size(), 1u);
  EXPECT_EQ(m.buffers[0].data.size(), r.bufferBytes);
}

// A .glb's length fields are 32-bit: a mesh over 4 GiB is refused before a
// byte is written (the same quads listed by many primitives reach the limit
// without allocating it).
TEST(GltfWriter, AGlbOverFourGibIsRefusedAndNothingIsWritten) {
  voxtest::TempDir dir;
  std::vector<vox::BlockQuad> quads(1u << 17);  // 264 bytes each unindexed: 34.6 MB per primitive
  for (size_t i = 0; i < quads.size(); ++i) quads[i].block = {int32_t(i % 512), int32_t(i / 512), 0};
  vox::GltfScene s;
  s.name = "huge";
  s.materials.push_back({"m", std::nullopt});
  for (int p = 0; p < 130; ++p) s.primitives.push_back({quads, 0});  // 4.5e9 bytes
  const std::string path = dir.file("huge.glb");
  try {
    vox::writeGlb(s, path);
    FAIL() << "a 4.5 GB .glb was written";
  } catch (const vox::Error& e) {
    EXPECT_EQ(e.kind, vox::ErrorKind::BadInput);
    EXPECT_NE(std::string(e.what()).find("more than a .glb can hold (4 GiB)"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << "a temporary was left behind";
}

}  // namespace


namespace {

TEST(ColorQuantize, FewColoursAreExact) {
  vox::ColorHistogram h{{vox::packRgb({9, 8, 7}), 3}, {vox::packRgb({1, 2, 3}), 1}};
  const vox::QuantizedPalette p = vox::quantizeColors(h, 255);
  EXPECT_TRUE(p.exact);
  ASSERT_EQ(p.colors.size(), 2u);
  EXPECT_EQ(p.colors[0], (vox::Rgb8{1, 2, 3}));  // ascending 0xRRGGBB
  EXPECT_EQ(p.slotOf.at(vox::packRgb({9, 8, 7})), 1u);
  EXPECT_EQ(p.meanError, 0.0);
}

TEST(ColorQuantize, MedianCutKeepsTheLimitAndMeasuresItsError) {
  vox::ColorHistogram h;
  for (int r = 0; r < 256; r += 5)
    for (int g = 0; g < 256; g += 17) h[vox::packRgb({uint8_t(r), uint8_t(g), 40})] = 1 + uint64_t(r % 3);
  const vox::QuantizedPalette p = vox::quantizeColors(h, 16);
  EXPECT_FALSE(p.exact);
  EXPECT_EQ(p.colors.size(), 16u);
  // Every colour maps to its nearest entry; the reported errors are those distances.
  double worst = 0, sum = 0;
  uint64_t n = 0;
  for (const auto& [rgb, count] : h) {
    const vox::Rgb8 c = vox::unpackRgb(rgb);
    double best = 1e9;
    for (const vox::Rgb8& e : p.colors)
      best = std::min(best, std::hypot(double(c.r - e.r), double(c.g - e.g), double(c.b - e.b)));
    const vox::Rgb8& mine = p.colors[p.slotOf.at(rgb)];
    EXPECT_DOUBLE_EQ(std::hypot(double(c.r - mine.r), double(c.g - mine.g), double(c.b - mine.b)), best);
    worst = std::max(worst, best);
    sum += best * double(count);
    n += count;
  }
  EXPECT_DOUBLE_EQ(p.maxError, worst);
  EXPECT_NEAR(p.meanError, sum / double(n), 1e-9);
  EXPECT_LT(p.meanError, 40.0);
  EXPECT_EQ(vox::quantizeColors(h, 16).colors, p.colors);  // deterministic
}

vox::ClassVolume oneVoxel(vox::Coord3 at, uint8_t cls, vox::IndexBox box) {
  vox::ClassVolume vol(box, false);
  vox::ClassVolume::Brick b = vol.makeBrick({at.u & ~7, at.v & ~7, at.w & ~7});
  b.classes[size_t(vox::ClassVolume::voxelIndex(at.u & 7, at.v & 7, at.w & 7))] = cls;
  vol.add(std::move(b));
  vol.finish();
  return vol;
}

uint32_t le32(const std::string& s, size_t at) {
  return uint32_t(uint8_t(s[at])) | uint32_t(uint8_t(s[at + 1])) << 8 | uint32_t(uint8_t(s[at + 2])) << 16 |
         uint32_t(uint8_t(s[at + 3])) << 24;
}

TEST(MagicaVoxelWriter, ChunksFollowTheSpec) {
  voxtest::TempDir dir;
  std::array<vox::Rgb8, 255> palette{};
  palette[2] = {148, 153, 163};
  const vox::ClassVolume vol = oneVoxel({1, 2, 3}, 3, {{0, 0, 0}, {4, 5, 6}});
  const vox::MagicaVoxelResult r =
      vox::writeMagicaVoxel(vol, palette, [](const vox::ClassVolume::Brick&, int) { return uint8_t(3); },
                            dir.file("a.vox"));
  const std::string f = vox::readFileBytes(dir.file("a.vox"));
  ASSERT_EQ(f.size(), r.bytes);
  EXPECT_EQ(f.substr(0, 4), "VOX ");
  EXPECT_EQ(le32(f, 4), 150u);
  EXPECT_EQ(f.substr(8, 4), "MAIN");
  EXPECT_EQ(le32(f, 12), 0u);
  EXPECT_EQ(le32(f, 16), f.size() - 20);  // MAIN's children are the rest of the file
  // SIZE: (u, w, v) extents = (5, 7, 6); XYZI: x = u, y = wmax - w = 3, z = v.
  EXPECT_EQ(f.substr(20, 4), "SIZE");
  EXPECT_EQ((std::array<uint32_t, 3>{le32(f, 32), le32(f, 36), le32(f, 40)}), (std::array<uint32_t, 3>{5, 7, 6}));
  EXPECT_EQ(f.substr(44, 4), "XYZI");
  EXPECT_EQ(le32(f, 56), 1u);
  EXPECT_EQ(f.substr(60, 4), std::string("\x01\x03\x02\x03", 4));
  // Every chunk after MAIN's header: id, content size, children size, walked to the end.
  std::vector<std::string> ids;
  for (size_t at = 20; at < f.size(); at += 12 + le32(f, at + 4) + le32(f, at + 8)) ids.push_back(f.substr(at, 4));
  EXPECT_EQ(ids, (std::vector<std::string>{"SIZE", "XYZI", "nTRN", "nGRP", "nTRN", "nSHP", "RGBA"}));
  // The palette: entry k is index k + 1.
  EXPECT_EQ(f.substr(f.size() - 1024 + 8, 4), std::string("\x94\x99\xa3\xff", 4));
}

// Two voxels at opposite corners of a box 2^21 wide: 8192 x 8192 tiles, two
// with voxels, two models; the plan the check sees is the file written.
TEST(MagicaVoxelWriter, FarApartVoxelsMakeTwoModels) {
  voxtest::TempDir dir;
  const int32_t far = (1 << 21) - 1;
  vox::ClassVolume vol({{0, 0, 0}, {far, 3, far}}, false);
  for (const vox::Coord3 at : {vox::Coord3{0, 0, 0}, vox::Coord3{far, 3, far}}) {
    vox::ClassVolume::Brick b = vol.makeBrick({at.u & ~7, at.v & ~7, at.w & ~7});
    b.classes[size_t(vox::ClassVolume::voxelIndex(at.u & 7, at.v & 7, at.w & 7))] = 1;
    vol.add(std::move(b));
  }
  vol.finish();
  std::optional<vox::MagicaVoxelPlan> plan;
  const auto one = [](const vox::ClassVolume::Brick&, int) { return uint8_t(1); };
  const vox::MagicaVoxelResult r = vox::writeMagicaVoxel(
      vol, {}, one, dir.file("far.vox"), [&](const vox::MagicaVoxelPlan& p) { plan = p; });
  ASSERT_TRUE(plan);
  EXPECT_EQ(r.models, 2u);
  EXPECT_EQ(r.voxels, 2u);
  EXPECT_EQ(plan->models, 2u);
  EXPECT_EQ(plan->voxels, 2u);
  EXPECT_EQ(plan->fileBytes, r.bytes);
  EXPECT_LT(plan->memoryBytes, 4096u);
  const std::string f = vox::readFileBytes(dir.file("far.vox"));
  ASSERT_EQ(f.size(), r.bytes);
  // Models in (z, y, x) tile order: (u, w) = (far, far) is tile (8191, 0, 0),
  // before (0, 0), tile (0, 8191, 0); translations o + 128 - 2^20 (z: 0 + 2 - 2).
  EXPECT_NE(f.find("1048448 -1048448 0"), std::string::npos);
  EXPECT_LT(f.find("1048448 -1048448 0"), f.find("-1048448 1048448 0"));
  // A check that refuses: nothing written.
  EXPECT_TRUE(voxtest::throwsVoxError(
      [&] {
        vox::writeMagicaVoxel(vol, {}, one, dir.file("no.vox"),
                              [](const vox::MagicaVoxelPlan&) { vox::throwBadInput("refused"); });
      },
      vox::ErrorKind::BadInput, {"refused"}));
  EXPECT_FALSE(std::filesystem::exists(dir.file("no.vox")));
}

TEST(PlyWriter, HeaderAndRecords) {
  voxtest::TempDir dir;
  vox::ClassTable t;
  t.add({5, "Snow", {235, 240, 245}, std::nullopt});
  const vox::ClassVolume vol = oneVoxel({9, 0, 2}, 5, {{0, 0, 0}, {15, 7, 7}});
  const vox::PlyWriteResult r =
      vox::writeVoxelPly(vol, t, vox::FaceColor::Palette, {{1.0, 2.0, 3.0}, 0.5}, dir.file("p.ply"));
  EXPECT_EQ(r.points, 1u);
  const std::string f = vox::readFileBytes(dir.file("p.ply"));
  const size_t body = f.find("end_header\n") + 11;
  EXPECT_NE(f.find("element vertex 1\n"), std::string::npos);
  ASSERT_EQ(f.size(), body + 16);
  float xyz[3];
  std::memcpy(xyz, f.data() + body, 12);
  EXPECT_EQ(xyz[0], 1.0f + 9.5f * 0.5f);
  EXPECT_EQ(xyz[1], 2.0f + 0.25f);
  EXPECT_EQ(xyz[2], 3.0f + 1.25f);
  EXPECT_EQ(f.substr(body + 12), std::string("\xeb\xf0\xf5\x05", 4));
  EXPECT_TRUE(voxtest::throwsVoxError(
      [&] { vox::writeVoxelPly(vol, vox::ClassTable{}, vox::FaceColor::Palette, {}, dir.file("q.ply")); },
      vox::ErrorKind::BadInput, {"class 5", "(9, 0, 2)"}));
}

}  // namespace

namespace {
/// A volume of `n` voxels: a sphere shell of radius `radius` voxels (one voxel
/// thick), or single voxels `spacing` apart on a line when `radius` is 0.
vox::ClassVolume shellOrDots(int radius, int n, int spacing) {
  const int side = radius > 0 ? 2 * radius + 2 : n * spacing + 1;
  vox::ClassVolume vol({{0, 0, 0}, {side, side, side}}, false);
  std::map<std::array<int, 3>, vox::ClassVolume::Brick> bricks;
  auto set = [&](int x, int y, int z) {
    const std::array<int, 3> o{x & ~7, y & ~7, z & ~7};
    auto it = bricks.find(o);
    if (it == bricks.end()) it = bricks.emplace(o, vol.makeBrick({o[0], o[1], o[2]})).first;
    it->second.classes[size_t(vox::ClassVolume::voxelIndex(x & 7, y & 7, z & 7))] = 1;
  };
  if (radius > 0) {
    for (int x = 0; x <= side; ++x)
      for (int y = 0; y <= side; ++y)
        for (int z = 0; z <= side; ++z) {
          const double d = std::sqrt(double((x - radius) * (x - radius) + (y - radius) * (y - radius) +
                                            (z - radius) * (z - radius)));
          if (std::abs(d - radius + 0.5) < 0.5) set(x, y, z);
        }
  } else {
    for (int i = 0; i < n; ++i) set(i * spacing, 0, 0);
  }
  for (auto& [o, b] : bricks) vol.add(std::move(b));
  vol.finish();
  return vol;
}
}  // namespace

// The memory check of a .vdb export counts the leaves OpenVDB's float grid
// spans before building it: never fewer than the level set it writes holds.
TEST(VdbVolumeWriter, LeafCountCoversTheBandOpenVdbWrites) {
  voxtest::TempDir dir;
  for (const int radius : {6, 20})
    for (const int halfWidth : {1, 3, 8, 9, 20}) {
      const vox::ClassVolume vol = shellOrDots(radius, 0, 0);
      const uint64_t counted = vox::vdbVolumeLeafCount(vol, vox::VdbVolumeKind::LevelSet, halfWidth);
      const std::string path = dir.file("l.vdb");
      vox::writeVdbVolume(vol, {{0, 0, 0}, 1.0}, vox::VdbVolumeKind::LevelSet, halfWidth, path);
      const vox::VdbFrame frame = vox::checkVdbStructure(path);
      ASSERT_EQ(frame.grids.size(), 1u);
      EXPECT_GE(counted, frame.grids[0].leafCount) << "radius " << radius << ", half width " << halfWidth;
    }
  // A fog volume: one float leaf per occupied leaf.
  const vox::ClassVolume shell = shellOrDots(20, 0, 0);
  EXPECT_EQ(vox::vdbVolumeLeafCount(shell, vox::VdbVolumeKind::Fog, 3), shell.bricks().size());
}

TEST(VdbVolumeWriter, LeafCountOfScatteredLeavesAndItsBound) {
  // Leaves far apart dilate independently: (2r + 1)^3 each, r = ceil(hw / 8).
  const vox::ClassVolume dots = shellOrDots(0, 10, 200);
  ASSERT_EQ(dots.bricks().size(), 10u);
  EXPECT_EQ(vox::vdbVolumeLeafCount(dots, vox::VdbVolumeKind::LevelSet, 3), 10u * 27);
  EXPECT_EQ(vox::vdbVolumeLeafCount(dots, vox::VdbVolumeKind::LevelSet, 64), 10u * 17 * 17 * 17);
  // Past maxKeys keys the count is bounded, never under the exact one: here
  // the bound is exact for isolated leaves, and the dilated box caps leaves
  // packed closer than the band.
  EXPECT_EQ(vox::vdbVolumeLeafCount(dots, vox::VdbVolumeKind::LevelSet, 64, 100), 10u * 17 * 17 * 17);
  const vox::ClassVolume packed = shellOrDots(0, 10, 8);  // ten adjacent leaves in a row
  const uint64_t exact = vox::vdbVolumeLeafCount(packed, vox::VdbVolumeKind::LevelSet, 64);
  EXPECT_EQ(exact, uint64_t(10 + 16) * 17 * 17);
  const uint64_t bounded = vox::vdbVolumeLeafCount(packed, vox::VdbVolumeKind::LevelSet, 64, 100);
  EXPECT_GE(bounded, exact);
  EXPECT_EQ(bounded, uint64_t(10 + 16) * 17 * 17);  // the box: (10 + 2r) x (1 + 2r) x (1 + 2r)
}
