// Mesh readers: hand-written files for every feature and error, plus the
// third-party files of ../shared/data when present.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "formats/image/image.h"
#include "formats/mesh/mesh_input.h"
#include "test_util.h"

using namespace vox;

namespace {
Mesh read(const std::string& path, bool drop = false) {
  std::vector<std::string> w;
  MeshReadOptions o;
  o.dropInvalid = drop;
  return readMeshFile(path, o, w);
}
::testing::AssertionResult rejects(const std::string& path, std::initializer_list<std::string> needles) {
  return voxtest::throwsVoxError([&] { read(path); }, ErrorKind::BadInput, needles);
}
const std::string kData = voxtest::sharedDataDir();
bool haveData() { return std::filesystem::exists(kData + "/MANIFEST.md"); }
}  // namespace

TEST(ObjReader, QuadsNegativeIndicesMaterialsGroupsAndTextures) {
  voxtest::TempDir dir;
  Image tex(2, 1, 4, SampleType::U8);
  tex.pixels = {255, 0, 0, 255, 0, 0, 255, 255};
  writePng(tex, dir.file("t.png"));
  voxtest::writeText(dir.file("m.mtl"), "newmtl Red\nKd 1 0 0\nnewmtl Tex\nKd 1 1 1\nmap_Kd t.png\n");
  voxtest::writeText(dir.file("m.obj"),
                     "# comment\nmtllib m.mtl\no first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\n"
                     "usemtl Red\nf 1 2 3 4\ng second\nusemtl Tex\nf -4/1 -3/2 -2/1\nf 1//1 2//1 3//1\n");
  const Mesh m = read(dir.file("m.obj"));
  EXPECT_EQ(m.triangleCount(), 4u) << "a quad fan-triangulates into 2";
  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[0].name, "Red");
  EXPECT_EQ(m.materials[0].baseColorFactor[1], 0.0f);
  EXPECT_EQ(m.materials[1].texture, 0);
  ASSERT_EQ(m.textures.size(), 1u);
  EXPECT_EQ(m.textures[0].width, 2u);
  EXPECT_EQ(m.triangleMaterial, (std::vector<uint32_t>{0, 0, 1, 1}));
  EXPECT_EQ(m.parts[m.trianglePart[2]].nodeName, "second");
  EXPECT_EQ(m.parts[m.trianglePart[0]].nodeName, "first");
  EXPECT_EQ(m.uv0.size(), m.positions.size());
  EXPECT_EQ(m.filesRead.size(), 3u) << "obj, mtl, texture";
  EXPECT_TRUE(m.hasColor());
}

TEST(ObjReader, ErrorsNameTheLine) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("a.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
  EXPECT_TRUE(rejects(dir.file("a.obj"), {"a.obj:3", "vertex 3", "2 are defined"}));
  voxtest::writeText(dir.file("b.obj"), "v 0 0 zero\n");
  EXPECT_TRUE(rejects(dir.file("b.obj"), {"b.obj:1", "expected a number"}));
  voxtest::writeText(dir.file("c.obj"), "v 0 0 0\nv 1 0 nan\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n");
  EXPECT_TRUE(rejects(dir.file("c.obj"), {"c.obj:2", "1 vertex has NaN", "vertex 2", "drop their triangles"}));
  EXPECT_EQ(voxtest::settingOfError([&] { read(dir.file("c.obj")); }), Setting::DropInvalid);
  EXPECT_EQ(read(dir.file("c.obj"), true).triangleCount(), 1u);
  voxtest::writeText(dir.file("d.obj"), "mtllib missing.mtl\n");
  EXPECT_TRUE(rejects(dir.file("d.obj"), {"d.obj:1", "missing.mtl"}));
  voxtest::writeText(dir.file("e.obj"), "v 0 0 0\nf 1 1\n");
  EXPECT_TRUE(rejects(dir.file("e.obj"), {"e.obj:2", "at least 3"}));
  EXPECT_EQ(read((voxtest::writeText(dir.file("empty.obj"), ""), dir.file("empty.obj"))).triangleCount(), 0u);
}

// The parallel pre-pass must not change anything: the same OBJ text split into
// chunks of 1, 5 and 64 bytes (boundaries inside every kind of line, CRLF
// included) gives the mesh, warnings and error of one chunk. The texts mix
// every line form, the pre-pass's and the serial pass's, and errors on
// either kind of line.
TEST(ObjReader, SameResultWhateverTheChunks) {
  const std::vector<std::string> good = {"v 0 0 0", "v 1 0 0", "v 0 1 0", "v 0 0 1", "vt 0 0", "vt 1 1",
                                         "f 1 2 3", "f -1 -2 -3", "f 1//1 2//2 3//3", "f 1/1 2/2 3/1", "f 1 2 3 4",
                                         "g part", "o other", "usemtl red", "# c", "", "  ", "v 1 1 1 0.5 0.2 0.1",
                                         "v 2 2 2 1", "\tv\t3 3 3", "vn 0 0 1", "s off"};
  const std::vector<std::string> bad = {"f 1 2", "f 1 2 99", "f 0 1 2", "f 1 2 x", "f 1/9 2 3", "f +1 2 3",
                                        "v 1 2", "v 1 2 nan", "v 1 2 3 x", "v 1e999 0 0", "f 1 2 3 # c",
                                        "f 99999999999 1 2", "v +1 +2 +3", "f -99 1 2", "f 1//x 2 3"};
  std::mt19937 rng(3);
  for (int i = 0; i < 200; ++i) {
    std::vector<std::string> lines = {"v 0 0 0", "v 1 0 0", "v 0 1 0", "v 0 0 1", "vt 0 0"};
    for (int k = int(rng() % 40); k > 0; --k) lines.push_back(good[rng() % good.size()]);
    if (i % 3 == 0) lines.insert(lines.begin() + 5 + rng() % (lines.size() - 4), bad[rng() % bad.size()]);
    const std::string nl = i % 5 == 0 ? "\r\n" : "\n";
    std::string text;
    for (const std::string& l : lines) text += l + nl;
    if (i % 4 == 0) text.resize(text.size() - nl.size());  // no newline at the end
    MeshReadOptions options;
    options.dropInvalid = i % 2 == 0;
    auto parse = [&](size_t chunkBytes, std::vector<std::string>& warnings, std::string& error) {
      try {
        return parseObj(text.data(), text.size(), "t.obj", options, warnings, "", chunkBytes);
      } catch (const Error& e) {
        error = e.what();
        return Mesh{};
      }
    };
    std::vector<std::string> w0;
    std::string e0;
    const Mesh m0 = parse(size_t(1) << 20, w0, e0);
    for (size_t chunkBytes : {size_t(1), size_t(5), size_t(64)}) {
      std::vector<std::string> w;
      std::string e;
      const Mesh m = parse(chunkBytes, w, e);
      const std::string what = "text " + std::to_string(i) + ", chunks of " + std::to_string(chunkBytes) + " bytes";
      EXPECT_EQ(e, e0) << what;
      EXPECT_EQ(w, w0) << what;
      EXPECT_EQ(m.positions, m0.positions) << what;
      EXPECT_EQ(m.triangles, m0.triangles) << what;
      EXPECT_EQ(m.triangleMaterial, m0.triangleMaterial) << what;
      EXPECT_EQ(m.trianglePart, m0.trianglePart) << what;
      EXPECT_EQ(m.uv0, m0.uv0) << what;
      EXPECT_EQ(m.colors, m0.colors) << what;
      EXPECT_EQ(m.materials.size(), m0.materials.size()) << what;
      EXPECT_EQ(m.parts.size(), m0.parts.size()) << what;
    }
  }
}

TEST(StlReader, AsciiAndBinaryIncludingASolidHeader) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("a.stl"),
                     "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid x\n");
  EXPECT_EQ(read(dir.file("a.stl")).triangleCount(), 1u);
  std::string bin(84 + 50, '\0');
  std::memcpy(bin.data(), "solid but binary", 16);
  const uint32_t n = 1;
  std::memcpy(bin.data() + 80, &n, 4);
  const float v[9] = {0, 0, 0, 2, 0, 0, 0, 2, 0};
  std::memcpy(bin.data() + 84 + 12, v, 36);
  voxtest::writeText(dir.file("b.stl"), bin);
  const Mesh m = read(dir.file("b.stl"));
  ASSERT_EQ(m.triangleCount(), 1u);
  EXPECT_EQ(m.positions[1][0], 2.0);
  voxtest::writeText(dir.file("c.stl"), "solid x\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n");
  EXPECT_TRUE(rejects(dir.file("c.stl"), {"c.stl:6", "2 vertices"}));
  voxtest::writeText(dir.file("d.stl"), "garbage");
  EXPECT_TRUE(rejects(dir.file("d.stl"), {"not an STL"}));
}

TEST(PlyReader, AsciiAndBinaryBothEndiansWithColours) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("a.ply"),
                     "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                     "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n"
                     "property list uchar int vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n"
                     "0 1 0 188 188 188\n4 0 1 2 3\n");
  const Mesh a = read(dir.file("a.ply"));
  EXPECT_EQ(a.triangleCount(), 2u);
  ASSERT_EQ(a.colors.size(), 4u);
  EXPECT_NEAR(a.colors[3][0], 0.50289f, 1e-4) << "sRGB 188 -> linear";
  for (bool big : {false, true}) {
    std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
                    "element face 1\nproperty list uchar ushort vertex_index\nend_header\n";
    auto put = [&](const void* p, size_t n) {
      std::string b(static_cast<const char*>(p), n);
      if (big) std::reverse(b.begin(), b.end());
      s += b;
    };
    const double coords[9] = {0, 0, 0, 3, 0, 0, 0, 3, 0};
    for (double c : coords) put(&c, 8);
    const uint8_t cnt = 3;
    s += char(cnt);
    for (uint16_t i : {uint16_t(0), uint16_t(1), uint16_t(2)}) put(&i, 2);
    voxtest::writeText(dir.file("b.ply"), s);
    const Mesh b = read(dir.file("b.ply"));
    ASSERT_EQ(b.triangleCount(), 1u) << big;
    EXPECT_EQ(b.positions[1][0], 3.0) << big;
    voxtest::writeText(dir.file("c.ply"), s.substr(0, s.size() - 3));
    EXPECT_TRUE(rejects(dir.file("c.ply"), {"c.ply", "ends early"}));
  }
  voxtest::writeText(dir.file("d.ply"), "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                        "end_header\n0 0 0\n3 0 0 5\n");
  EXPECT_TRUE(rejects(dir.file("d.ply"), {"face 0", "vertex 5"}));
}

TEST(GltfReader, DataUriNodeTransformsStripsAndDraco) {
  voxtest::TempDir dir;
  // Three float positions (36 bytes) + strip indices 0,1,2 (ushort, 6 bytes + 2 padding).
  std::string bin;
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  bin.append(reinterpret_cast<const char*>(p), 36);
  const uint16_t idx[4] = {0, 1, 2, 0};
  bin.append(reinterpret_cast<const char*>(idx), 8);
  static const char* b64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string enc;
  for (size_t i = 0; i < bin.size(); i += 3) {
    const uint32_t n = (uint8_t(bin[i]) << 16) | (i + 1 < bin.size() ? uint8_t(bin[i + 1]) << 8 : 0) |
                       (i + 2 < bin.size() ? uint8_t(bin[i + 2]) : 0);
    enc += b64[(n >> 18) & 63];
    enc += b64[(n >> 12) & 63];
    enc += i + 1 < bin.size() ? b64[(n >> 6) & 63] : '=';
    enc += i + 2 < bin.size() ? b64[n & 63] : '=';
  }
  const std::string gltf = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"name":"root","translation":[10,0,0],"children":[1]},{"name":"child","scale":[2,2,2],"mesh":0}],
    "meshes":[{"name":"tri","primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":5,"material":0}]}],
    "materials":[{"name":"red","pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1]}}],
    "buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,)" + enc + R"("}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                 {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
  voxtest::writeText(dir.file("t.gltf"), gltf);
  const Mesh m = read(dir.file("t.gltf"));
  ASSERT_EQ(m.triangleCount(), 1u);
  EXPECT_EQ(m.positions[1][0], 12.0) << "child scale 2 then root translation 10";
  EXPECT_EQ(m.parts[m.trianglePart[0]].nodeName, "root/child");
  EXPECT_EQ(m.parts[m.trianglePart[0]].meshName, "tri");
  EXPECT_EQ(m.materials[m.triangleMaterial[0]].name, "red");
  std::string draco = gltf;
  draco.insert(1, R"("extensionsRequired":["KHR_draco_mesh_compression"],"extensionsUsed":["KHR_draco_mesh_compression"],)");
  voxtest::writeText(dir.file("d.gltf"), draco);
  EXPECT_EQ(read(dir.file("d.gltf")).triangleCount(), 1u) << "Draco is read; these primitives are not compressed";
  voxtest::writeText(dir.file("bad.gltf"), "{not json");
  EXPECT_TRUE(rejects(dir.file("bad.gltf"), {"bad.gltf", "cannot read"}));
  EXPECT_TRUE(rejects(dir.file("none.glb"), {"none.glb"}));
}

TEST(MeshData, ThirdPartyFilesWhenPresent) {
  if (!haveData()) GTEST_SKIP() << "../shared/data is absent: third-party mesh checks skipped";
  EXPECT_EQ(read(kData + "/common-3d-test-models/stanford-bunny.obj").triangleCount(), 69451u);
  EXPECT_EQ(read(kData + "/cgal-data/pig.stl").triangleCount(), 16848u);
  EXPECT_EQ(read(kData + "/cgal-data/b9.ply").triangleCount(), 0u) << "a point cloud has no faces";
  EXPECT_EQ(read(kData + "/common-3d-test-models/teapot.obj").triangleCount(), 6320u);
  EXPECT_EQ(read(kData + "/cuda_voxelizer/bunny.OBJ").triangleCount(), 5110u) << "upper-case extension";
  EXPECT_EQ(read(kData + "/khronos-gltf-sample-models/SimpleSparseAccessor/SimpleSparseAccessor.gltf").triangleCount(), 12u);
  const Mesh box = read(kData + "/gltf/assimp/BoxTextured-glTF/BoxTextured.gltf");
  EXPECT_EQ(box.triangleCount(), 12u);
  EXPECT_EQ(box.textures.size(), 1u);
  EXPECT_EQ(box.filesRead.size(), 3u) << "gltf, bin, png";
  EXPECT_TRUE(rejects(kData + "/gltf/assimp/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb",
                      {"accessor", "(POSITION)", "NaN or infinite"}));
  EXPECT_TRUE(rejects(kData + "/gltf/assimp/MissingBin/BoxTextured.gltf", {"BoxTextured0.bin"}));
  EXPECT_EQ(read(kData + "/gltf/assimp/draco/2CylinderEngine.gltf").triangleCount(), 110336u) << "Draco-compressed";
  EXPECT_EQ(read(kData + "/gltf/assimp/Triangle-Mesh-Quantized/triangle_mesh_quantized.gltf").triangleCount(), 1u);
}

TEST(Mesh, KeepTrianglesKeepsOrderMaterialsPartsAndTheCallersValues) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  m.triangleMaterial = {10, 11, 12, 13};
  m.trianglePart = {20, 21, 22, 23};
  std::vector<uint8_t> classes{1, 2, 3, 4};
  EXPECT_EQ(m.keepTriangles({true, false, true, false}, &classes), 2u);
  EXPECT_EQ(m.triangles, (std::vector<std::array<uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(m.triangleMaterial, (std::vector<uint32_t>{10, 12}));
  EXPECT_EQ(m.trianglePart, (std::vector<uint32_t>{20, 22}));
  EXPECT_EQ(classes, (std::vector<uint8_t>{1, 3}));
  EXPECT_EQ(m.positions.size(), 4u);  // vertices stay: indices remain valid
  Mesh bare;  // no materials or parts recorded per triangle
  bare.positions = m.positions;
  bare.triangles = {{0, 1, 2}, {1, 2, 3}};
  EXPECT_EQ(bare.keepTriangles({false, true}), 1u);
  EXPECT_EQ(bare.triangles, (std::vector<std::array<uint32_t, 3>>{{1, 2, 3}}));
  EXPECT_TRUE(bare.triangleMaterial.empty());
}
