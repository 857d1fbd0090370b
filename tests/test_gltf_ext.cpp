// glTF extensions (docs/gltf.md) on files written here, each read against the
// same model without the extension (the oracle): EXT_meshopt_compression
// (compressed with libmeshoptimizer's encoder; the shared sample against its
// own fallback buffer), and the malformed variants refused by name.
// Draco's voxel-level comparisons are in tests/cli/gltfext_test.sh; a Draco face
// index out of range is here (it needs Draco's encoder). Images:
// decoded once, for base colour only (gltf_images.h).
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <array>
#include <cstring>
#include <functional>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "formats/mesh/mesh_input.h"
#include "test_util.h"


using namespace vox;
using nlohmann::json;

namespace {

const std::string kData = voxtest::sharedDataDir();

Mesh read(const std::string& path, std::vector<std::string>* warnings = nullptr) {
  std::vector<std::string> w;
  Mesh m = readMeshFile(path, {}, w);
  if (warnings) *warnings = w;
  return m;
}

::testing::AssertionResult rejects(const std::string& path, std::initializer_list<std::string> needles) {
  return voxtest::throwsVoxError([&] { read(path); }, ErrorKind::BadInput, needles);
}

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
    for (int k = 18; k >= 0; k -= 6) out += t[(v >> k) & 63];
  }
  if (i + 1 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    out += std::string{t[(v >> 18) & 63], t[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8;
    out += std::string{t[(v >> 18) & 63], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
  }
  return out;
}
std::string dataUri(const std::string& bin) { return "data:application/octet-stream;base64," + base64(bin); }

template <typename T>
std::string bytesOf(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

void writeGlb(const std::string& path, const json& doc, std::string bin) {
  std::string text = doc.dump();
  while (text.size() % 4) text += ' ';
  while (bin.size() % 4) bin += '\0';
  const uint32_t header[5] = {0x46546C67u, 2, uint32_t(28 + text.size() + bin.size()), uint32_t(text.size()), 0x4E4F534Au};
  const uint32_t binHeader[2] = {uint32_t(bin.size()), 0x004E4942u};
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(header), sizeof header);
  f << text;
  f.write(reinterpret_cast<const char*>(binHeader), sizeof binHeader);
  f << bin;
}

/// The triangle with its smallest index first, winding kept: meshopt's
/// triangle codec may rotate a triangle's corners (its specification allows it).
std::array<uint32_t, 3> rotated(std::array<uint32_t, 3> t) {
  while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
  return t;
}

void expectSameGeometry(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (size_t i = 0; i < a.positions.size(); ++i) EXPECT_EQ(a.positions[i], b.positions[i]) << "vertex " << i;
  for (size_t i = 0; i < a.triangles.size(); ++i) EXPECT_EQ(rotated(a.triangles[i]), rotated(b.triangles[i])) << "triangle " << i;
}

// A box: 8 corners, 12 triangles, positions and 32-bit indices.
const std::vector<float> kBoxPositions = {0, 0, 0, 2, 0, 0, 2, 3, 0, 0, 3, 0, 0, 0, 5, 2, 0, 5, 2, 3, 5, 0, 3, 5};
const std::vector<uint32_t> kBoxIndices = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                           3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

json boxDoc() {
  return json::parse(R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3","min":[0,0,0],"max":[2,3,5]},
                 {"bufferView":1,"componentType":5125,"count":36,"type":"SCALAR"}]})");
}

/// The box with both views EXT_meshopt_compression-compressed into buffer 0;
/// buffer 1 is the fallback, without data. `mutate` breaks it for the refusal tests.
json meshoptBox(std::string& compressed, const std::function<void(json&)>& mutate = {}) {
  meshopt_encodeVertexVersion(0);  // the version the extension specifies
  std::vector<unsigned char> v(meshopt_encodeVertexBufferBound(8, 12));
  v.resize(meshopt_encodeVertexBuffer(v.data(), v.size(), kBoxPositions.data(), 8, 12));
  std::vector<unsigned char> ix(meshopt_encodeIndexBufferBound(36, 8));
  ix.resize(meshopt_encodeIndexBuffer(ix.data(), ix.size(), kBoxIndices.data(), 36));
  compressed = bytesOf(v);
  while (compressed.size() % 4) compressed += '\0';
  const size_t ixOffset = compressed.size();
  compressed += bytesOf(ix);
  json doc = boxDoc();
  doc["extensionsUsed"] = doc["extensionsRequired"] = {"EXT_meshopt_compression"};
  doc["buffers"] = {{{"byteLength", compressed.size()}},
                    {{"byteLength", 96 + 144}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
  doc["bufferViews"] = {
      {{"buffer", 1}, {"byteOffset", 0}, {"byteLength", 96}, {"byteStride", 12},
       {"extensions", {{"EXT_meshopt_compression", {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", v.size()},
                                                    {"byteStride", 12}, {"count", 8}, {"mode", "ATTRIBUTES"}}}}}},
      {{"buffer", 1}, {"byteOffset", 96}, {"byteLength", 144},
       {"extensions", {{"EXT_meshopt_compression", {{"buffer", 0}, {"byteOffset", ixOffset}, {"byteLength", ix.size()},
                                                    {"byteStride", 4}, {"count", 36}, {"mode", "TRIANGLES"}}}}}}};
  if (mutate) mutate(doc);
  return doc;
}

json& meshoptOf(json& doc, int view) { return doc["bufferViews"][size_t(view)]["extensions"]["EXT_meshopt_compression"]; }

}  // namespace

TEST(GltfMeshopt, DecodesToTheUncompressedBox) {
  voxtest::TempDir dir;
  json plain = boxDoc();
  const std::string bin = bytesOf(kBoxPositions) + bytesOf(kBoxIndices);
  plain["buffers"] = {{{"byteLength", bin.size()}, {"uri", dataUri(bin)}}};
  plain["bufferViews"] = {{{"buffer", 0}, {"byteLength", 96}}, {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 144}}};
  voxtest::writeText(dir.file("plain.gltf"), plain.dump());
  const Mesh reference = read(dir.file("plain.gltf"));
  ASSERT_EQ(reference.triangleCount(), 12u);

  std::string compressed;
  json doc = meshoptBox(compressed);
  doc["buffers"][0]["uri"] = dataUri(compressed);
  voxtest::writeText(dir.file("meshopt.gltf"), doc.dump());
  expectSameGeometry(read(dir.file("meshopt.gltf")), reference);

  // The same as a .glb: buffer 0 is the BIN chunk, the fallback has no data.
  json glb = meshoptBox(compressed);
  writeGlb(dir.file("meshopt.glb"), glb, compressed);
  expectSameGeometry(read(dir.file("meshopt.glb")), reference);
}

TEST(GltfMeshopt, CorruptViewsAreRefusedByName) {
  voxtest::TempDir dir;
  struct Case {
    const char* name;
    std::function<void(json&)> mutate;
    std::vector<std::string> says;
  };
  const std::vector<Case> cases = {
      {"truncated", [](json& d) { meshoptOf(d, 0)["byteLength"] = meshoptOf(d, 0)["byteLength"].get<int>() / 2; },
       {"bufferViews[0] (EXT_meshopt_compression)", "does not decode"}},
      {"past_buffer", [](json& d) { meshoptOf(d, 1)["byteOffset"] = 4000; }, {"bufferViews[1]", "past the end of buffer 0"}},
      {"stride", [](json& d) { meshoptOf(d, 0)["byteStride"] = 6; }, {"bufferViews[0]", "byteStride 6"}},
      {"mode", [](json& d) { meshoptOf(d, 1)["mode"] = "LINES"; }, {"bufferViews[1]", "mode \"LINES\""}},
      {"count", [](json& d) { meshoptOf(d, 0)["count"] = 1000000000; }, {"bufferViews[0]", "cannot come from"}},
      {"filter", [](json& d) { meshoptOf(d, 0)["filter"] = "QUATERNION"; }, {"bufferViews[0]", "QUATERNION"}},
      {"no_buffer", [](json& d) { meshoptOf(d, 0)["buffer"] = 7; }, {"bufferViews[0]", "buffer 7 does not exist"}},
  };
  for (const Case& c : cases) {
    std::string compressed;
    json doc = meshoptBox(compressed, c.mutate);
    doc["buffers"][0]["uri"] = dataUri(compressed);
    const std::string file = dir.file(std::string(c.name) + ".gltf");
    voxtest::writeText(file, doc.dump());
    for (const std::string& s : c.says) EXPECT_TRUE(rejects(file, {s})) << c.name;
  }
}

TEST(GltfMeshopt, SharedSampleMatchesItsFallback) {
  const std::string dir = kData + "/gltf/gltf-pipeline/extensions/EXT_meshopt_compression/meshopt-fallback/";
  if (!std::filesystem::exists(dir + "meshopt-fallback.gltf"))
    GTEST_SKIP() << "../shared/data is absent: the meshopt sample is not checked";
  // Decoded (octahedral-filtered normals, triangle codec) against the
  // uncompressed fallback buffer the same file carries: the extension removed
  // from every bufferView makes the reader use the fallback.
  voxtest::TempDir tmp;
  json doc = json::parse(std::ifstream(dir + "meshopt-fallback.gltf"));
  for (const char* bin : {"meshopt-fallback.bin", "meshopt-fallback.fallback.bin"})
    std::filesystem::copy_file(dir + bin, tmp.file(bin));
  for (auto& v : doc["bufferViews"]) v.erase("extensions");
  voxtest::writeText(tmp.file("fallback.gltf"), doc.dump());
  const Mesh decoded = read(dir + "meshopt-fallback.gltf");
  expectSameGeometry(decoded, read(tmp.file("fallback.gltf")));
  EXPECT_EQ(decoded.triangleCount(), 60u);
}

namespace {

// A 2x2 RGBA PNG: red, green / blue, white (alpha 128 on the white).
const char* kPng2x2 =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAE0lEQVR4nGP4z8DwHwyBNAg0AABJSQl4KKDbdwAAAABJRU5ErkJggg==";

/// A triangle with UVs whose materials use images: image 0 (the PNG) as base
/// colour of materials 0 and 1 (through textures 0 and 1, one sampler each),
/// image 1 (`normalMap` bytes) only as material 0's normal map.
std::string imagesGltf(const std::string& normalMap) {
  std::vector<float> bin = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1};
  json doc = json::parse(R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0},{"mesh":1}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":0}]},
              {"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":1}]}],
    "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"normalTexture":{"index":2}},
                 {"pbrMetallicRoughness":{"baseColorTexture":{"index":1}}}],
    "samplers":[{"magFilter":9728},{"magFilter":9729}],
    "textures":[{"source":0,"sampler":0},{"source":0,"sampler":1},{"source":1}],
    "bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                 {"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}]})");
  doc["buffers"] = {{{"byteLength", 60}, {"uri", dataUri(bytesOf(bin))}}};
  doc["images"] = {{{"uri", std::string("data:image/png;base64,") + kPng2x2}},
                   {{"uri", "data:image/png;base64," + base64(normalMap)}}};
  return doc.dump();
}

}  // namespace

TEST(GltfImages, DecodedOnceForBaseColourOnly) {
  voxtest::TempDir dir;
  // The normal map is not a PNG at all: never decoded, so not an error.
  voxtest::writeText(dir.file("t.gltf"), imagesGltf("not an image"));
  std::vector<std::string> warnings;
  const Mesh m = read(dir.file("t.gltf"), &warnings);
  ASSERT_EQ(m.textures.size(), 2u) << "one per base colour texture (two samplers)";
  for (const MeshTexture& t : m.textures) {
    ASSERT_EQ(t.width, 2u);
    ASSERT_EQ(t.height, 2u);
    const std::vector<uint8_t> want = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128};
    EXPECT_EQ(t.rgba, want) << "the same pixels for both textures of the shared image";
  }
  EXPECT_TRUE(m.textures[0].nearest);
  EXPECT_FALSE(m.textures[1].nearest);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
}

TEST(GltfImages, UndecodableBaseColourImageIsNamed) {
  voxtest::TempDir dir;
  std::string doc = imagesGltf("x");
  const std::string good = std::string("data:image/png;base64,") + kPng2x2;
  doc.replace(doc.find(good), good.size(), "data:image/png;base64," + base64("garbage bytes"));
  voxtest::writeText(dir.file("bad.gltf"), doc);
  EXPECT_TRUE(rejects(dir.file("bad.gltf"), {"bad.gltf", "image 0", "cannot be decoded"}));
  std::vector<std::string> w;
  MeshReadOptions lenient;
  lenient.ignoreMissingMaterials = true;
  const Mesh m = readMeshFile(dir.file("bad.gltf"), lenient, w);
  EXPECT_TRUE(m.textures.empty());
  ASSERT_FALSE(w.empty());
  EXPECT_NE(w[0].find("image 0"), std::string::npos) << w[0];
}

TEST(GltfFuzzFindings, HugeFloatIndexAndImageViewPastItsBuffer) {
  voxtest::TempDir dir;
  // An indices accessor of floats (invalid, but read) naming vertex 1.8e28:
  // refused with the number, not an out-of-range conversion.
  std::vector<float> bin = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1.8e28f, 0, 1};
  json doc = json::parse(R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
    "bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":12}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                 {"bufferView":1,"componentType":5126,"count":3,"type":"SCALAR"}]})");
  doc["buffers"] = {{{"byteLength", 48}, {"uri", dataUri(bytesOf(bin))}}};
  voxtest::writeText(dir.file("f.gltf"), doc.dump());
  EXPECT_TRUE(rejects(dir.file("f.gltf"), {"accessor 1 (indices)", "refers to vertex 1799"}));
  // An image's bufferView past the end of its buffer: tinygltf would hand the
  // image reader bytes past the buffer; the JSON check refuses it first.
  doc["bufferViews"][1]["byteLength"] = 40;
  voxtest::writeText(dir.file("v.gltf"), doc.dump());
  EXPECT_TRUE(rejects(dir.file("v.gltf"), {"bufferViews[1]", "past the end of buffer 0 (48 bytes)"}));
}

namespace {

/// The box as KHR_draco_mesh_compression data: sequential connectivity with raw
/// 8-bit indices (Draco's choice for fewer than 256 points when connectivity
/// compression is off), so that a face index can be patched in place.
std::string dracoBox() {
  draco::Mesh mesh;
  mesh.set_num_points(8);
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, sizeof(float) * 3, 0);
  const int att = mesh.AddAttribute(ga, /*identity_mapping=*/true, 8);
  for (int i = 0; i < 8; ++i)
    mesh.attribute(att)->SetAttributeValue(draco::AttributeValueIndex(i), &kBoxPositions[size_t(3 * i)]);
  for (size_t t = 0; t < kBoxIndices.size(); t += 3)
    mesh.AddFace({draco::PointIndex(kBoxIndices[t]), draco::PointIndex(kBoxIndices[t + 1]),
                  draco::PointIndex(kBoxIndices[t + 2])});
  draco::Encoder encoder;
  encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
  draco::EncoderBuffer out;
  const draco::Status s = encoder.EncodeMeshToBuffer(mesh, &out);
  EXPECT_TRUE(s.ok()) << s.error_msg_string();
  return std::string(out.data(), out.size());
}

json dracoBoxDoc(size_t bytes) {
  json doc = json::parse(R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"name":"box","primitives":[{"attributes":{"POSITION":0},"indices":1,
      "extensions":{"KHR_draco_mesh_compression":{"bufferView":0,"attributes":{"POSITION":0}}}}]}],
    "extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"],
    "accessors":[{"componentType":5126,"count":8,"type":"VEC3","min":[0,0,0],"max":[2,3,5]},
                 {"componentType":5125,"count":36,"type":"SCALAR"}]})");
  doc["buffers"] = {{{"byteLength", bytes}}};
  doc["bufferViews"] = {{{"buffer", 0}, {"byteLength", bytes}}};
  return doc;
}

}  // namespace

// A face index past the decoded points (what a corrupt or hostile encoder can
// store in raw sequential connectivity) is refused naming the primitive and the
// face, before any triangle reaches the voxelizer.
TEST(GltfDraco, FaceIndexOutOfRangeIsRefusedByName) {
  voxtest::TempDir dir;
  std::string draco = dracoBox();
  ASSERT_FALSE(draco.empty());
  writeGlb(dir.file("box.glb"), dracoBoxDoc(draco.size()), draco);
  const Mesh good = read(dir.file("box.glb"));
  ASSERT_EQ(good.triangleCount(), 12u) << "the uncorrupted file decodes";

  std::string raw;
  for (uint32_t i : kBoxIndices) raw += char(uint8_t(i));
  const size_t at = draco.find(raw);
  ASSERT_NE(at, std::string::npos) << "raw 8-bit indices not found in the Draco stream";
  ASSERT_EQ(draco.find(raw, at + 1), std::string::npos);
  draco[at + 3 * 5 + 1] = char(200);  // face 5, second corner: point 200 of 8
  writeGlb(dir.file("oob.glb"), dracoBoxDoc(draco.size()), draco);
  EXPECT_TRUE(rejects(dir.file("oob.glb"),
                      {"oob.glb", "mesh 'box' primitive 0 (KHR_draco_mesh_compression)", "face 5", "point 200 of 8"}));
}
