// Mesh readers (formats/mesh/mesh_input.h): every feature of issue 4's input list and
// the malformed inputs they must refuse with a message, on small files written here, plus
// the third-party files of ../shared/data when present (skipped with a message
// otherwise). Complements test_mesh_input.cpp.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "formats/mesh/mesh_input.h"
#include "test_util.h"


using namespace vox;

namespace {

struct Read {
  Mesh mesh;
  std::vector<std::string> warnings;
};

Read readWith(const std::string& path, MeshReadOptions o = {}) {
  Read r;
  r.mesh = readMeshFile(path, o, r.warnings);
  return r;
}
Mesh read(const std::string& path, MeshReadOptions o = {}) { return readWith(path, o).mesh; }

::testing::AssertionResult rejects(const std::string& path, std::initializer_list<std::string> needles,
                                   MeshReadOptions o = {}) {
  return voxtest::throwsVoxError([&] { read(path, o); }, ErrorKind::BadInput, needles);
}

bool anyContains(const std::vector<std::string>& v, const std::string& needle) {
  for (const std::string& s : v)
    if (s.find(needle) != std::string::npos) return true;
  return false;
}

float srgbToLinear(int c) {
  const double x = c / 255.0;
  return float(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
}

// --- byte helpers ---------------------------------------------------------

template <typename T>
void putLE(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);  // the test machine is little-endian
}
template <typename T>
void putBE(std::string& s, T v) {
  std::string b(reinterpret_cast<const char*>(&v), sizeof v);
  s.append(b.rbegin(), b.rend());
}
void pad4(std::string& s) {
  while (s.size() % 4) s.push_back('\0');
}

std::string base64(const std::string& bin) {
  static const char* b64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string enc;
  for (size_t i = 0; i < bin.size(); i += 3) {
    const uint32_t n = (uint32_t(uint8_t(bin[i])) << 16) | (i + 1 < bin.size() ? uint32_t(uint8_t(bin[i + 1])) << 8 : 0) |
                       (i + 2 < bin.size() ? uint32_t(uint8_t(bin[i + 2])) : 0);
    enc += b64[(n >> 18) & 63];
    enc += b64[(n >> 12) & 63];
    enc += i + 1 < bin.size() ? b64[(n >> 6) & 63] : '=';
    enc += i + 2 < bin.size() ? b64[n & 63] : '=';
  }
  return enc;
}

std::string dataUri(const std::string& bin) { return "data:application/octet-stream;base64," + base64(bin); }

// A 2x2 RGBA PNG: red, green / blue, white with alpha 128.
const char* kPng2x2 =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAE0lEQVR4nGP4z8DwHwyBNAg0AABJSQl4KKDbdwAAAABJRU5ErkJggg==";
std::string pngBytes() {
  std::string out;
  uint32_t acc = 0;
  int bits = 0;
  for (const char* p = kPng2x2; *p && *p != '='; ++p) {
    const char* b64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    acc = (acc << 6) | uint32_t(std::strchr(b64, *p) - b64);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(char((acc >> bits) & 0xff));
    }
  }
  return out;
}

const std::string kGltfHead = R"({"asset":{"version":"2.0"},)";

// One triangle (0,0,0) (1,0,0) (0,1,0) as a data-URI buffer + accessor 0.
std::string triangleBuffers() {
  std::string bin;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) putLE(bin, f);
  return R"("buffers":[{"byteLength":36,"uri":")" + dataUri(bin) + R"("}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}])";
}

std::array<double, 3> normal(const Mesh& m, size_t t) {
  const auto& a = m.positions[m.triangles[t][0]];
  const auto& b = m.positions[m.triangles[t][1]];
  const auto& c = m.positions[m.triangles[t][2]];
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}

const std::string kData = voxtest::sharedDataDir();
bool haveData() { return std::filesystem::exists(kData + "/MANIFEST.md"); }

}  // namespace

// ============================== OBJ ==============================

TEST(ObjIo, NegativeIndicesPolygonsPartsMaterialsAndCrlf) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("m.mtl"), "# lib\r\nnewmtl Red\r\nKd 1 0 0\r\nnewmtl Half\r\nKd 0.5 0.25 1e-1\r\n");
  voxtest::writeText(dir.file("m.obj"),
                     "mtllib m.mtl\r\no box\r\nv 0 0 0\r\nv +1.5 0 0\r\nv 1.5 1 0\r\nv 0 1 0\r\nv -0.5 0.5 0\r\n"
                     "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvn 0 0 1\r\nusemtl Red\r\nf 1 2 3 4 5\r\ng lid\r\nusemtl Half\r\n"
                     "f -5/-3/1 -4/-2/1 -3/-1/1\r\nf 1//1 3//1 4//1  \r\n");
  const Read r = readWith(dir.file("m.obj"));
  const Mesh& m = r.mesh;
  ASSERT_EQ(m.triangleCount(), 5u) << "pentagon fan (3) + 2 triangles";
  EXPECT_TRUE(r.warnings.empty());
  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[1].name, "Half");
  EXPECT_FLOAT_EQ(m.materials[1].baseColorFactor[2], 0.1f) << "Kd is taken as linear, as written";
  EXPECT_EQ(m.triangleMaterial, (std::vector<uint32_t>{0, 0, 0, 1, 1}));
  EXPECT_EQ(m.parts[m.trianglePart[0]].nodeName, "box");
  EXPECT_EQ(m.parts[m.trianglePart[4]].nodeName, "lid");
  EXPECT_EQ(m.parts[m.trianglePart[0]].meshName, "m.obj");
  // The relative face -5 -4 -3 is v1 v2 v3.
  const auto& t = m.triangles[3];
  EXPECT_EQ(m.positions[t[0]], (std::array<double, 3>{0, 0, 0}));
  EXPECT_EQ(m.positions[t[1]], (std::array<double, 3>{1.5, 0, 0}));
  EXPECT_EQ(m.positions[t[2]], (std::array<double, 3>{1.5, 1, 0}));
  ASSERT_EQ(m.uv0.size(), m.positions.size());
  EXPECT_FLOAT_EQ(m.uv0[t[2]][1], 0.0f) << "OBJ v=1 is the image top: stored flipped (glTF convention)";
  // Fan order of the pentagon: (1,2,3) (1,3,4) (1,4,5).
  EXPECT_EQ(m.positions[m.triangles[2][2]], (std::array<double, 3>{-0.5, 0.5, 0}));
  EXPECT_EQ(m.filesRead.size(), 2u) << "obj and mtl";
}

// What Windows editors and some exporters write: a byte-order mark, lines
// continued with a backslash (the OBJ specification's), comments after a face.
TEST(ObjIo, ByteOrderMarkContinuedLinesAndCommentsAfterFaces) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("c.mtl"), "\xEF\xBB\xBFnewmtl Red\nKd 1 0 0\n");
  voxtest::writeText(dir.file("c.obj"),
                     "\xEF\xBB\xBFmtllib c.mtl\n"
                     "# exported to C:\\models\\\n"  // a comment ending in a backslash does not go on
                     "v 0 0 0\nv 1 0 \\\n 0\nv 1 1 0\r\nv 0 1 0 \\  \r\n\nvt 0 0\nvt 1 0\nvt 1 1\n"
                     "usemtl Red\nf 1 2 \\\n3 # the first\nf 1/1 3/3 4/2# the second\n");
  const Mesh m = read(dir.file("c.obj"));
  ASSERT_EQ(m.triangleCount(), 2u);
  EXPECT_EQ(m.positions[m.triangles[0][1]], (std::array<double, 3>{1, 0, 0})) << "v 1 0 \\ 0";
  EXPECT_EQ(m.positions[m.triangles[0][2]], (std::array<double, 3>{1, 1, 0}));
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].name, "Red") << "the byte-order marks hid neither mtllib nor newmtl";
  EXPECT_EQ(m.triangleMaterial, (std::vector<uint32_t>{0, 0}));
  EXPECT_EQ(m.positions[m.triangles[1][2]], (std::array<double, 3>{0, 1, 0}));
  // Messages still name the line as it is in the file: 5 lines, the second
  // and third continued, then the bad face on line 6.
  voxtest::writeText(dir.file("n.obj"), "v 0 0 0\nv 1 \\\n0 \\\n0\nv 0 1 0\nf 1 2 4\n");
  EXPECT_TRUE(rejects(dir.file("n.obj"), {"n.obj:6:", "vertex 4"}));
  voxtest::writeText(dir.file("e.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \\");  // ends inside a continued line
  EXPECT_TRUE(rejects(dir.file("e.obj"), {"e.obj:4", "at least 3"})) << "as without the backslash";
  voxtest::writeText(dir.file("x.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 x\n");
  EXPECT_TRUE(rejects(dir.file("x.obj"), {"x.obj:4"})) << "text after a face that is not a comment is still an error";
}

TEST(ObjIo, SeveralLibrariesOnOneLineAndWindowsTexturePaths) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("a.mtl"), "newmtl A\nKd 1 0 0\n");
  voxtest::writeText(dir.file("b.mtl"), "newmtl B\nKd 0 1 0\nmap_Kd .\\tex.png\n");
  voxtest::writeText(dir.file("tex.png"), pngBytes());
  voxtest::writeText(dir.file("m.obj"), "mtllib a.mtl b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl B\nf 1 2 3\n");
  const Read r = readWith(dir.file("m.obj"));
  ASSERT_EQ(r.mesh.materials.size(), 2u);
  EXPECT_EQ(r.mesh.materials[r.mesh.triangleMaterial[0]].name, "B");
  ASSERT_EQ(r.mesh.textures.size(), 1u) << "'.\\tex.png' (written on Windows) resolves to tex.png";
  EXPECT_EQ(r.mesh.textures[0].width, 2u);
  EXPECT_EQ(r.mesh.textures[0].rgba.size(), 16u);
  EXPECT_EQ(r.mesh.textures[0].rgba[4 * 3 + 3], 128) << "texels stay as stored (RGBA8, sRGB-encoded)";
  EXPECT_EQ(r.mesh.filesRead.size(), 4u) << "obj, two mtl, texture";
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ObjIo, TextureCoordinatesThatAreNotNumbersNameTheLine) {
  voxtest::TempDir dir;
  for (const char* vt : {"vt nan 0", "vt 0 inf", "vt 1e300 0"}) {
    voxtest::writeText(dir.file("t.obj"), std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\n") + vt + "\nf 1/1 2/1 3/1\n");
    EXPECT_TRUE(rejects(dir.file("t.obj"), {"t.obj:4", "texture coordinate is not a finite number"})) << vt;
  }
}

TEST(ObjIo, TextureOptionsAndFileNamesWithSpaces) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("my tex.png"), pngBytes());
  voxtest::writeText(dir.file("plain.png"), pngBytes());
  voxtest::writeText(dir.file("m.mtl"),
                     "newmtl A\nmap_Kd -bm 1 -s 1 1 1 -o 0 0 -clamp on my tex.png\n"   // options at their defaults
                     "newmtl B\nmap_Kd -o 0.5 0.25 0 -s 2 4 plain.png\n"              // a placement, applied
                     "newmtl C\nmap_Kd -unknown 3 plain.png\n"                         // an unknown option
                     "newmtl D\nmap_Kd -t 0.1 0 0 -s 3 plain.png\n");                  // turbulence: not applied
  voxtest::writeText(dir.file("m.obj"), "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl A\nf 1 2 3\n");
  const Read r = readWith(dir.file("m.obj"));
  ASSERT_EQ(r.mesh.materials.size(), 4u);
  ASSERT_EQ(r.mesh.textures.size(), 4u) << "every map_Kd found its file";
  EXPECT_TRUE(anyContains(r.mesh.filesRead, "my tex.png")) << "a file name with a space, after the options";
  EXPECT_EQ(r.mesh.textures[0].wrapS, MeshTexture::Wrap::ClampToEdge) << "-clamp on";
  EXPECT_EQ(r.mesh.textures[0].wrapT, MeshTexture::Wrap::ClampToEdge);
  EXPECT_EQ(r.mesh.textures[1].wrapS, MeshTexture::Wrap::Repeat) << "the default repeats";
  EXPECT_FALSE(r.mesh.materials[0].placesTexture()) << "options at their defaults place nothing";
  // B: u' = 2u + 0.5, v' = 4v + 0.25 in the MTL's (u, v), v up; the mesh's t is 1 - v.
  const std::array<double, 6> b = r.mesh.materials[1].uvTransform;
  EXPECT_EQ(b, (std::array<double, 6>{2, 0, 0.5, 0, 4, 1 - 4 - 0.25}));
  const double u = 0.3, v = 0.6;  // a point in MTL coordinates: s = u, t = 1 - v
  EXPECT_DOUBLE_EQ(b[0] * u + b[1] * (1 - v) + b[2], 2 * u + 0.5);
  EXPECT_DOUBLE_EQ(b[3] * u + b[4] * (1 - v) + b[5], 1 - (4 * v + 0.25));
  EXPECT_FALSE(r.mesh.materials[2].placesTexture());
  EXPECT_EQ(r.mesh.materials[3].uvTransform, (std::array<double, 6>{3, 0, 0, 0, 1, 0})) << "-s 3: v keeps 1";
  ASSERT_EQ(r.warnings.size(), 1u) << "only D's turbulence is left out";
  EXPECT_TRUE(anyContains(r.warnings, "m.mtl:8")) << r.warnings[0];
  EXPECT_TRUE(anyContains(r.warnings, "-t 0.1 0 0 (turbulence) is not applied")) << r.warnings[0];
}

TEST(ObjIo, LibraryAfterTheFacesThatUseItStillColoursThem) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("red.mtl"), "newmtl Red\nKd 1 0 0\n");
  voxtest::writeText(dir.file("late.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Blue\nf 1 2 3\nusemtl Red\nf 1 2 3\n"
                                           "mtllib red.mtl\nusemtl Red\nf 1 3 2\n");
  const Read r = readWith(dir.file("late.obj"));
  ASSERT_EQ(r.mesh.triangleCount(), 3u);
  const MeshMaterial& red = r.mesh.materials[r.mesh.triangleMaterial[1]];
  EXPECT_EQ(red.name, "Red");
  EXPECT_EQ(red.baseColorFactor[1], 0.0f) << "defined by the library that comes after its first faces";
  EXPECT_EQ(r.mesh.triangleMaterial[1], r.mesh.triangleMaterial[2]) << "one material, before and after the mtllib";
  ASSERT_EQ(r.warnings.size(), 1u) << "only Blue is undefined";
  EXPECT_TRUE(anyContains(r.warnings, "late.obj:4: material 'Blue' is not defined")) << r.warnings[0];
}

TEST(ObjIo, MissingLibraryOrTextureIsAnErrorUnlessIgnored) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("a.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib gone.mtl\nusemtl X\nf 1 2 3\n");
  EXPECT_TRUE(rejects(dir.file("a.obj"), {"a.obj:4", "gone.mtl", "missing"}));
  voxtest::writeText(dir.file("t.mtl"), "newmtl X\nKd 1 1 1\nmap_Kd nothere.png\n");
  voxtest::writeText(dir.file("b.obj"), "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl X\nf 1 2 3\n");
  EXPECT_TRUE(rejects(dir.file("b.obj"), {"t.mtl:3", "map_Kd", "nothere.png", "missing"}));
  // Both name the setting that bakes without them (the CLI adds --ignore-missing-materials).
  EXPECT_EQ(voxtest::settingOfError([&] { read(dir.file("a.obj")); }), Setting::IgnoreMissingMaterials);
  EXPECT_EQ(voxtest::settingOfError([&] { read(dir.file("b.obj")); }), Setting::IgnoreMissingMaterials);
  voxtest::writeText(dir.file("bad.png"), "not a png");
  voxtest::writeText(dir.file("u.mtl"), "newmtl X\nmap_Kd bad.png\n");
  voxtest::writeText(dir.file("c.obj"), "mtllib u.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_TRUE(rejects(dir.file("c.obj"), {"u.mtl:2", "bad.png", "cannot decode"}));

  MeshReadOptions ignore;
  ignore.ignoreMissingMaterials = true;
  const Read a = readWith(dir.file("a.obj"), ignore);
  EXPECT_EQ(a.mesh.triangleCount(), 1u);
  EXPECT_EQ(a.mesh.materials[a.mesh.triangleMaterial[0]].name, "X") << "the name survives for --classes";
  EXPECT_TRUE(anyContains(a.warnings, "gone.mtl"));
  const Read b = readWith(dir.file("b.obj"), ignore);
  EXPECT_EQ(b.mesh.textures.size(), 0u);
  EXPECT_TRUE(anyContains(b.warnings, "nothere.png"));
  EXPECT_TRUE(rejects(dir.file("c.obj"), {"bad.png"}, ignore)) << "a corrupt texture is still an error";
}

TEST(ObjIo, NanNamesTheLineAndDropInvalidCountsTheTriangles) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("n.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 inf\nv nan 1 1\nf 4 1 2\nf 1 2 3\nf 5 1 3\n");
  EXPECT_TRUE(rejects(dir.file("n.obj"), {"n.obj:4", "2 vertices have", "vertex 4", "drop their triangles"}));
  voxtest::writeText(dir.file("n1.obj"), "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
  EXPECT_TRUE(rejects(dir.file("n1.obj"), {"n1.obj:3", "1 vertex has NaN", "vertex 3"}));
  EXPECT_EQ(voxtest::settingOfError([&] { read(dir.file("n.obj")); }), Setting::DropInvalid);
  MeshReadOptions drop;
  drop.dropInvalid = true;
  const Read r = readWith(dir.file("n.obj"), drop);
  EXPECT_EQ(r.mesh.triangleCount(), 1u);
  EXPECT_EQ(r.mesh.triangleMaterial.size(), 1u);
  EXPECT_EQ(r.mesh.trianglePart.size(), 1u);
  EXPECT_TRUE(anyContains(r.warnings, "dropped 2 triangles"));
  MeshReadOptions dropOne = drop;
  EXPECT_TRUE(anyContains(readWith(dir.file("n1.obj"), dropOne).warnings, "dropped 1 triangle touching 1 vertex with"));
  for (const auto& p : r.mesh.positions)
    for (double c : p) EXPECT_TRUE(std::isfinite(c));
}

TEST(ObjIo, MalformedFacesNameTheLine) {
  voxtest::TempDir dir;
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  voxtest::writeText(dir.file("a.obj"), v + "f 0 1 2\n");
  EXPECT_TRUE(rejects(dir.file("a.obj"), {"a.obj:4", "vertex 0"}));
  voxtest::writeText(dir.file("b.obj"), v + "f 1 2 -4\n");
  EXPECT_TRUE(rejects(dir.file("b.obj"), {"b.obj:4", "vertex -4", "3 are defined"}));
  voxtest::writeText(dir.file("c.obj"), v + "f 1 2 3x\n");
  EXPECT_TRUE(rejects(dir.file("c.obj"), {"c.obj:4", "unexpected character"}));
  voxtest::writeText(dir.file("d.obj"), v + "f 1/5 2/5 3/5\n");
  EXPECT_TRUE(rejects(dir.file("d.obj"), {"d.obj:4", "texture coordinate 5"}));
  voxtest::writeText(dir.file("e.obj"), "v 0 0\n");
  EXPECT_TRUE(rejects(dir.file("e.obj"), {"e.obj:1", "expected a number"}));
  voxtest::writeText(dir.file("f.obj"), v + "f 99999999999999999999 1 2\n");
  EXPECT_TRUE(rejects(dir.file("f.obj"), {"f.obj:4"}));
  voxtest::writeText(dir.file("g.obj"), "# only a comment\n\n");
  const Mesh g = read(dir.file("g.obj"));
  EXPECT_EQ(g.triangleCount(), 0u) << "an empty mesh is not a reader error";
  EXPECT_FALSE(g.hasColor());
}

// Classic Mac OS text (CR alone ends a line) reads as the same file with LF;
// a lone CR inside an LF file ends a line too (text editors show it so).
TEST(ObjIo, CarriageReturnLineEnds) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("lf.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
  voxtest::writeText(dir.file("cr.obj"), "v 0 0 0\rv 1 0 0\rv 0 1 0\rv 1 1 0\rf 1 2 3\rf 2 4 3\r");
  voxtest::writeText(dir.file("mixed.obj"), "v 0 0 0\r\nv 1 0 0\rv 0 1 0\nv 1 1 0\r\nf 1 2 3\rf 2 4 3\n");
  const Mesh lf = read(dir.file("lf.obj"));
  for (const char* f : {"cr.obj", "mixed.obj"}) {
    const Mesh m = read(dir.file(f));
    EXPECT_EQ(m.triangles, lf.triangles) << f;
    EXPECT_EQ(m.positions, lf.positions) << f;
  }
  voxtest::writeText(dir.file("bad.obj"), "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 9\r");
  EXPECT_TRUE(rejects(dir.file("bad.obj"), {"bad.obj:4", "vertex 9"})) << "lines counted at each CR";
  voxtest::writeText(dir.file("m.mtl"), "newmtl Red\rKd 1 0 0\r");
  voxtest::writeText(dir.file("c.obj"), "mtllib m.mtl\rv 0 0 0\rv 1 0 0\rv 0 1 0\rusemtl Red\rf 1 2 3\r");
  const Mesh c = read(dir.file("c.obj"));
  ASSERT_EQ(c.materials.size(), 1u);
  EXPECT_EQ(c.materials[0].name, "Red");
  EXPECT_EQ(c.materials[0].baseColorFactor[1], 0.0f) << "the MTL's CR lines too";
}

// A face of fewer than 3 vertices: refused naming the line, or dropped and
// counted with --drop-invalid, as PLY faces are.
TEST(ObjIo, ShortFacesAreRefusedOrDroppedAndCounted) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("s.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\nf 3\n");
  EXPECT_TRUE(rejects(dir.file("s.obj"), {"s.obj:4", "a face has 2 vertices", "at least 3"}));
  EXPECT_EQ(voxtest::settingOfError([&] { read(dir.file("s.obj")); }), Setting::DropInvalid);
  MeshReadOptions drop;
  drop.dropInvalid = true;
  const Read r = readWith(dir.file("s.obj"), drop);
  EXPECT_EQ(r.mesh.triangleCount(), 1u);
  EXPECT_TRUE(anyContains(r.warnings, "s.obj:4: dropped 2 faces of fewer than 3 vertices"));
  voxtest::writeText(dir.file("one.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 3\n");
  EXPECT_TRUE(rejects(dir.file("one.obj"), {"one.obj:5", "a face has 1 vertex;"}));
  EXPECT_TRUE(anyContains(readWith(dir.file("one.obj"), drop).warnings, "dropped 1 face of"));
}

// ============================== PLY ==============================

TEST(PlyIo, BinaryBothEndiansColoursAlphaAndAnyIndexTypes) {
  voxtest::TempDir dir;
  for (bool big : {false, true}) {
    std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment colours are sRGB bytes\nelement vertex 4\nproperty float x\nproperty float y\n"
                    "property float z\nproperty short extra\nproperty uchar red\nproperty uchar green\n"
                    "property uchar blue\nproperty uchar alpha\nelement face 1\n"
                    "property int8 flags\nproperty list uint uint vertex_indices\n"
                    "element edge 1\nproperty int a\nproperty int b\nend_header\n";
    auto put = [&](auto v) { big ? putBE(s, v) : putLE(s, v); };
    const float xyz[4][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
    const uint8_t rgba[4][4] = {{255, 0, 0, 255}, {0, 188, 0, 128}, {0, 0, 255, 0}, {10, 20, 30, 255}};
    for (int i = 0; i < 4; ++i) {
      for (float c : xyz[i]) put(c);
      put(int16_t(-7));
      for (uint8_t c : rgba[i]) s.push_back(char(c));
    }
    s.push_back(char(1));  // flags
    put(uint32_t(4));
    for (uint32_t i : {0u, 1u, 2u, 3u}) put(i);
    put(int32_t(0));
    put(int32_t(1));
    voxtest::writeText(dir.file("b.ply"), s);
    const Mesh m = read(dir.file("b.ply"));
    ASSERT_EQ(m.triangleCount(), 2u) << big;
    EXPECT_EQ(m.positions[2], (std::array<double, 3>{2, 2, 0})) << big;
    ASSERT_EQ(m.colors.size(), 4u);
    EXPECT_NEAR(m.colors[1][1], srgbToLinear(188), 1e-5) << "sRGB byte decoded to linear";
    EXPECT_NEAR(m.colors[3][2], srgbToLinear(30), 1e-5);
    EXPECT_NEAR(m.colors[1][3], 128 / 255.0, 1e-5) << "alpha is linear";
    EXPECT_TRUE(m.hasColor());
    EXPECT_EQ(m.triangleMaterial.size(), 2u);
    EXPECT_EQ(m.trianglePart.size(), 2u);
  }
}

TEST(PlyIo, AsciiFloatColoursAndZeroFaces) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("f.ply"),
                     "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty double x\r\nproperty double y\r\n"
                     "property double z\r\nproperty float red\r\nproperty float green\r\nproperty float blue\r\n"
                     "element face 1\r\nproperty list uchar int vertex_index\r\nend_header\r\n"
                     "0 0 0 0.5 0 0\r\n1e0 0 0 0 0.25 0\r\n0 +1 0 0 0 1\r\n3 0 1 2\r\n");
  const Mesh f = read(dir.file("f.ply"));
  ASSERT_EQ(f.triangleCount(), 1u);
  ASSERT_EQ(f.colors.size(), 3u);
  EXPECT_FLOAT_EQ(f.colors[0][0], 0.5f) << "float colours are taken as linear";
  EXPECT_FLOAT_EQ(f.colors[0][3], 1.0f);
  EXPECT_EQ(f.positions[2][1], 1.0);

  voxtest::writeText(dir.file("p.ply"), "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                                        "end_header\n0 0 0\n1 1 1\n");
  const Mesh p = read(dir.file("p.ply"));
  EXPECT_EQ(p.triangleCount(), 0u) << "a point cloud is an empty mesh, not an error";
  voxtest::writeText(dir.file("bom.ply"), "\xEF\xBB\xBFply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                          "property float y\nproperty float z\nelement face 1\n"
                                          "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(read(dir.file("bom.ply")).triangleCount(), 1u) << "a byte-order mark before 'ply'";
  EXPECT_EQ(p.positions.size(), 2u);
}

TEST(PlyIo, TriangleStripsKeepTheirWindingAndRestart) {
  voxtest::TempDir dir;
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                             "property float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 1 0\n";
  // A strip of two triangles, a restart, then a strip whose last triangle is a
  // degenerate joint (4 4).
  voxtest::writeText(dir.file("s.ply"), header + "9 0 1 2 3 -1 3 1 4 4\n");
  const Mesh m = read(dir.file("s.ply"));
  ASSERT_EQ(m.triangleCount(), 3u);
  EXPECT_EQ(m.triangles[0], (std::array<uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (std::array<uint32_t, 3>{2, 1, 3})) << "every other triangle flipped";
  EXPECT_EQ(m.triangles[2], (std::array<uint32_t, 3>{3, 1, 4})) << "the restart starts a new strip";
  for (const auto& t : m.triangles) {  // all wound the same way: normals along +z
    const auto& a = m.positions[t[0]];
    const auto& b = m.positions[t[1]];
    const auto& c = m.positions[t[2]];
    EXPECT_GT((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]), 0.0);
  }
  voxtest::writeText(dir.file("bad.ply"), header + "4 0 1 2 7\n");
  EXPECT_TRUE(rejects(dir.file("bad.ply"), {"bad.ply", "tristrips 0", "vertex 7"}));
}

TEST(PlyIo, HeaderCommentMentioningEndHeader) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("c.ply"),
                     "ply\nformat ascii 1.0\ncomment the header stops at end_header, not here\nelement vertex 3\n"
                     "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                     "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(read(dir.file("c.ply")).triangleCount(), 1u);
}

TEST(PlyIo, ImpossibleCountsFailFastInsteadOfHanging) {
  voxtest::TempDir dir;
  // An element without properties and an absurd count has no body bytes: skipped at once.
  voxtest::writeText(dir.file("a.ply"), "ply\nformat binary_little_endian 1.0\nelement junk 18446744073709551613\n"
                                        "element vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                                        "end_header\n");
  EXPECT_EQ(read(dir.file("a.ply")).triangleCount(), 0u);
  voxtest::writeText(dir.file("b.ply"), "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\n"
                                        "property float x\nproperty float y\nproperty float z\nend_header\n\1\2\3");
  EXPECT_TRUE(rejects(dir.file("b.ply"), {"b.ply", "element 'vertex'", "1000000000", "truncated"}));
  voxtest::writeText(dir.file("c.ply"), "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                        "property float z\nend_header\n0 0 0\n1 1\n");
  EXPECT_TRUE(rejects(dir.file("c.ply"), {"c.ply", "element 'vertex' 1", "ends early"}));
  voxtest::writeText(dir.file("d.ply"), "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                        "end_header\n0 0 0\n3 0 0 -1\n");
  EXPECT_TRUE(rejects(dir.file("d.ply"), {"d.ply", "face 0", "vertex -1"}));
  voxtest::writeText(dir.file("e.ply"), "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n");
  EXPECT_TRUE(rejects(dir.file("e.ply"), {"e.ply", "end_header"}));
  voxtest::writeText(dir.file("f.ply"), "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                        "property float z\nend_header\nnan 0 0\n");
  EXPECT_TRUE(rejects(dir.file("f.ply"), {"f.ply", "1 vertex has NaN", "vertex 0 (counted from 0"}));
  // Float-typed index lists: NaN, fractions and numbers past any integer are
  // refused by value (they were cast to integers: NaN to garbage, 1e300 printed
  // as -9223372036854775808); so is a fractional list count.
  auto floatIndices = [&](const std::string& file, const std::string& type, const std::string& face) {
    voxtest::writeText(dir.file(file), "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                       "property float z\nelement face 1\nproperty list " + type +
                                       " vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n" + face + "\n");
    return dir.file(file);
  };
  EXPECT_TRUE(rejects(floatIndices("g.ply", "uchar float", "3 0 1 nan"), {"g.ply", "face 0", "vertex index nan",
                                                                          "not a whole number"}));
  EXPECT_TRUE(rejects(floatIndices("h.ply", "uchar float", "3 0 1 1.5"), {"face 0", "vertex index 1.5"}));
  EXPECT_TRUE(rejects(floatIndices("i.ply", "uchar double", "3 0 1 1e300"), {"face 0", "refers to vertex 1e+300",
                                                                             "there are 3"}));
  EXPECT_TRUE(rejects(floatIndices("j.ply", "float int", "2.5 0 1 2"), {"j.ply", "list of 2.5 entries"}));
  EXPECT_EQ(read(floatIndices("k.ply", "uchar float", "3 0 1 2")).triangleCount(), 1u) << "whole floats are indices";
}

// Faces of fewer than 3 vertices are refused like OBJ's, or dropped and counted
// with --drop-invalid; only PLY 1.0 is read; a vertex count the file cannot
// hold gets one message whatever its size.
TEST(PlyIo, ShortFacesVersionsAndCounts) {
  voxtest::TempDir dir;
  const std::string head = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 3\n"
                           "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  voxtest::writeText(dir.file("s.ply"), "ply\nformat ascii 1.0\n" + head + "3 0 1 2\n2 0 1\n1 2\n");
  EXPECT_TRUE(rejects(dir.file("s.ply"), {"s.ply", "face 1 has 2 vertices", "at least 3"}));
  EXPECT_EQ(voxtest::settingOfError([&] { read(dir.file("s.ply")); }), Setting::DropInvalid);
  MeshReadOptions drop;
  drop.dropInvalid = true;
  const Read r = readWith(dir.file("s.ply"), drop);
  EXPECT_EQ(r.mesh.triangleCount(), 1u);
  EXPECT_TRUE(anyContains(r.warnings, "dropped 2 faces of fewer than 3 vertices (the first is face 1)"));
  voxtest::writeText(dir.file("one.ply"), "ply\nformat ascii 1.0\n" + head + "3 0 1 2\n3 0 1 2\n1 2\n");
  EXPECT_TRUE(rejects(dir.file("one.ply"), {"face 2 has 1 vertex;"}));
  EXPECT_TRUE(anyContains(readWith(dir.file("one.ply"), drop).warnings, "dropped 1 face of"));
  for (const char* version : {"2.0", "0.9", "1.0.1", ""}) {
    voxtest::writeText(dir.file("v.ply"), std::string("ply\nformat ascii ") + version + "\n" + head + "3 0 1 2\n3 0 1 2\n3 0 1 2\n");
    EXPECT_TRUE(rejects(dir.file("v.ply"), {"v.ply:2", "only 1.0"})) << version;
  }
  voxtest::writeText(dir.file("v1.ply"), "ply\nformat ascii 1\n" + head + "3 0 1 2\n3 0 1 2\n3 0 1 2\n");
  EXPECT_EQ(read(dir.file("v1.ply")).triangleCount(), 3u) << "'1' is 1.0";
  for (const char* count : {"100000000", "2000000000", "4000000000", "18446744073709551615"}) {
    voxtest::writeText(dir.file("c.ply"), std::string("ply\nformat binary_little_endian 1.0\nelement vertex ") + count +
                                              "\nproperty float x\nproperty float y\nproperty float z\nend_header\n\1\2\3");
    EXPECT_TRUE(rejects(dir.file("c.ply"), {"c.ply", "element 'vertex' announces", count, "only 3 bytes follow"})) << count;
  }
  voxtest::writeText(dir.file("b1.ply"), "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
                                         "property float y\nproperty float z\nend_header\n\1");
  EXPECT_TRUE(rejects(dir.file("b1.ply"), {"announces 2 items but only 1 byte follows"}));
}

// ============================== STL ==============================

TEST(StlIo, AsciiAndBinaryDetection) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("a.stl"), "  solid two\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
                                        "   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n facet normal 0 0 1\n"
                                        "  outer loop\n   vertex 1 0 0\n   vertex 1 1 0\n   vertex -1e-3 1 0\n  endloop\n"
                                        " endfacet\nendsolid two\n");
  const Mesh a = read(dir.file("a.stl"));
  ASSERT_EQ(a.triangleCount(), 2u);
  EXPECT_EQ(a.positions[5][0], -1e-3);
  // One facet in the usual lower-case keywords: its solid line, three vertex lines' numbers, its end line.
  auto facet = [](const std::string& solid, const char* a, const char* b, const char* c, const std::string& end) {
    return solid + "\nfacet normal 0 0 1\nouter loop\nvertex " + a + "\nvertex " + b + "\nvertex " + c +
           "\nendloop\nendfacet\n" + end + "\n";
  };
  voxtest::writeText(dir.file("bom.stl"), facet("\xEF\xBB\xBFsolid b", "0 0 0", "1 0 0", "0 1 0", "endsolid b"));
  EXPECT_EQ(read(dir.file("bom.stl")).triangleCount(), 1u) << "a byte-order mark before 'solid'";
  voxtest::writeText(dir.file("upper.stl"), "SOLID PART\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\n"
                                            "VERTEX 0 1 0\nENDLOOP\nENDFACET\nEndSolid PART\n");
  const Read upper = readWith(dir.file("upper.stl"));
  EXPECT_EQ(upper.mesh.triangleCount(), 1u) << "keywords in upper case, as some CAD exporters write them";
  EXPECT_TRUE(upper.warnings.empty()) << "'EndSolid' ends it";
  voxtest::writeText(dir.file("named.stl"), facet("solid facet vertex endsolid", "0 0 0", "1 0 0", "0 1 0",
                                                  "endsolid facet vertex endsolid"));
  EXPECT_EQ(read(dir.file("named.stl")).triangleCount(), 1u) << "the solid's name is a name, whatever its words";
  voxtest::writeText(dir.file("oneline.stl"), "solid x facet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 0 0 "
                                              "vertex 0 1 0 endloop endfacet endsolid x");
  EXPECT_EQ(read(dir.file("oneline.stl")).triangleCount(), 1u) << "an STL written on one line";
  // Some exporters write an explicit '+'; the OBJ and PLY readers take it too.
  voxtest::writeText(dir.file("plus.stl"), facet("solid p", "+0 0 0", "+1.5 0 0", "0 +2E+0 0", "endsolid p"));
  const Mesh plus = read(dir.file("plus.stl"));
  ASSERT_EQ(plus.triangleCount(), 1u);
  EXPECT_EQ(plus.positions[1][0], 1.5);
  EXPECT_EQ(plus.positions[2][1], 2.0);
  voxtest::writeText(dir.file("plusminus.stl"), facet("solid p", "+-1 0 0", "1 0 0", "0 1 0", "endsolid p"));
  EXPECT_TRUE(rejects(dir.file("plusminus.stl"), {"plusminus.stl:4", "expected 3 numbers after 'vertex'"}));

  auto binary = [](const std::string& header, uint32_t announced, uint32_t written) {
    std::string s = header;
    s.resize(80, ' ');
    putLE(s, announced);
    for (uint32_t t = 0; t < written; ++t) {
      for (float f : {0.f, 0.f, 1.f, 0.f, 0.f, float(t), 1.f, 0.f, float(t), 0.f, 1.f, float(t)}) putLE(s, f);
      putLE(s, uint16_t(0));
    }
    return s;
  };
  voxtest::writeText(dir.file("b.stl"), binary("solid exported by a tool that writes binary", 3, 3));
  const Mesh b = read(dir.file("b.stl"));
  ASSERT_EQ(b.triangleCount(), 3u) << "binary despite the 'solid' header: the size matches";
  EXPECT_EQ(b.positions[8][2], 2.0);
  voxtest::writeText(dir.file("e.stl"), binary("", 0, 0));
  EXPECT_EQ(read(dir.file("e.stl")).triangleCount(), 0u);
}

TEST(StlIo, TruncatedOrPaddedBinaryIsNotSilentlyEmpty) {
  voxtest::TempDir dir;
  std::string s = "solid but binary";
  s.resize(80, '\0');
  putLE(s, uint32_t(2));
  s.append(50 + 20, '\0');
  voxtest::writeText(dir.file("t.stl"), s);
  EXPECT_TRUE(rejects(dir.file("t.stl"), {"t.stl", "announces 2 triangles", "truncated"}));
  s.append(30 + 4, '\0');
  voxtest::writeText(dir.file("p.stl"), s);
  const Read p = readWith(dir.file("p.stl"));
  EXPECT_EQ(p.mesh.triangleCount(), 2u);
  EXPECT_TRUE(anyContains(p.warnings, "4 bytes after"));
  voxtest::writeText(dir.file("n.stl"), "solid x\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 nan 0\nendloop\n"
                                        "endfacet\nendsolid x\n");
  EXPECT_TRUE(rejects(dir.file("n.stl"), {"n.stl", "1 vertex has NaN", "vertex 3 (counted from 1"}));
}

TEST(StlIo, TruncatedAsciiIsRefusedNotReadShort) {
  voxtest::TempDir dir;
  const std::string facet = "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";
  const std::string whole = "solid t\n" + facet + facet + "endsolid t\n";
  EXPECT_EQ(read((voxtest::writeText(dir.file("w.stl"), whole), dir.file("w.stl"))).triangleCount(), 2u);
  // Cut inside the second facet (after its second vertex, after its endloop).
  for (const std::string& cut : {"solid t\n" + facet + facet.substr(0, 62), "solid t\n" + facet + facet.substr(0, 88)}) {
    voxtest::writeText(dir.file("c.stl"), cut);
    EXPECT_TRUE(rejects(dir.file("c.stl"), {"c.stl", "ends inside the facet of line 9", "truncated"})) << cut;
  }
  // Cut at a facet boundary: read, with a warning.
  voxtest::writeText(dir.file("b.stl"), "solid t\n" + facet);
  const Read b = readWith(dir.file("b.stl"));
  EXPECT_EQ(b.mesh.triangleCount(), 1u);
  EXPECT_TRUE(anyContains(b.warnings, "no 'endsolid'"));
  voxtest::writeText(dir.file("n.stl"), "solid t\n" + facet.substr(0, 60) + facet);
  EXPECT_TRUE(rejects(dir.file("n.stl"), {"n.stl", "before the facet of line 2 ended"}));
}

// CAD exporters write one solid per body or colour, one after the other: every
// solid is read, and text after the last one that is not another solid is refused.
TEST(StlIo, EverySolidOfAFileIsRead) {
  voxtest::TempDir dir;
  auto solid = [](const std::string& name, int z) {
    const std::string zs = std::to_string(z);
    return "solid " + name + "\nfacet normal 0 0 1\nouter loop\nvertex 0 0 " + zs + "\nvertex 1 0 " + zs +
           "\nvertex 0 1 " + zs + "\nendloop\nendfacet\nendsolid " + name + "\n";
  };
  voxtest::writeText(dir.file("m.stl"), solid("t", 0) + solid("u", 5) + "\n  \n" + solid("endsolid v", 9));
  const Read m = readWith(dir.file("m.stl"));
  ASSERT_EQ(m.mesh.triangleCount(), 3u) << "every solid, not only the first";
  EXPECT_EQ(m.mesh.positions[3][2], 5.0);
  EXPECT_EQ(m.mesh.positions[8][2], 9.0);
  EXPECT_TRUE(m.warnings.empty());
  voxtest::writeText(dir.file("one.stl"), "solid a facet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 0 0 vertex 0 1 0 "
                                          "endloop endfacet endsolid a solid b facet normal 0 0 1 outer loop vertex 0 0 1 "
                                          "vertex 1 0 1 vertex 0 1 1 endloop endfacet endsolid b");
  EXPECT_EQ(read(dir.file("one.stl")).triangleCount(), 2u) << "two solids on one line";
  voxtest::writeText(dir.file("junk.stl"), solid("t", 0) + "\nexported by SomeCAD 3.1\n");
  EXPECT_TRUE(rejects(dir.file("junk.stl"), {"junk.stl:11", "'exported' after the 'endsolid' of line 9", "only another 'solid'"}));
  voxtest::writeText(dir.file("open.stl"), solid("t", 0) + "solid u\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                                        "endsolid u\n");
  EXPECT_TRUE(rejects(dir.file("open.stl"), {"open.stl:14", "'endsolid' inside the facet of line 11", "1 of its 3"}));
  voxtest::writeText(dir.file("cut.stl"), solid("t", 0) + "solid u\n" + "facet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                                       "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n");
  const Read cut = readWith(dir.file("cut.stl"));
  EXPECT_EQ(cut.mesh.triangleCount(), 2u);
  EXPECT_TRUE(anyContains(cut.warnings, "no 'endsolid'")) << "the last solid without its end";
}

// ============================== glTF ==============================

TEST(GltfIo, HierarchyMatrixTrsFansStripsAndSkippedModes) {
  voxtest::TempDir dir;
  std::string bin;
  // 4 positions of a unit square (48 bytes) then ushort fan indices 0 1 2 3 (8 bytes).
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.f}) putLE(bin, f);
  for (uint16_t i : {0, 1, 2, 3}) putLE(bin, i);
  for (uint16_t i : {0, 1, 3, 2}) putLE(bin, i);  // the same square as a strip
  // Root: matrix translating by (0, 0, 5). Child: TRS, rotation 90 deg about z, scale 2.
  const double h = std::sqrt(0.5);
  const std::string gltf = kGltfHead + R"("scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"name":"root","matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5,1],"children":[1]},
             {"name":"arm","rotation":[0,0,)" + std::to_string(h) + "," + std::to_string(h) + R"(],"scale":[2,2,2],"mesh":0},
             {"name":"unreferenced","mesh":0}],
    "meshes":[{"name":"sq","primitives":[
        {"attributes":{"POSITION":0},"indices":1,"mode":6},
        {"attributes":{"POSITION":0},"indices":2,"mode":5},
        {"attributes":{"POSITION":0},"mode":1},
        {"attributes":{"POSITION":0},"indices":3}]}],
    "buffers":[{"byteLength":64,"uri":")" + dataUri(bin) + R"("}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":16}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                 {"bufferView":1,"componentType":5123,"count":4,"type":"SCALAR"},
                 {"bufferView":1,"byteOffset":8,"componentType":5123,"count":4,"type":"SCALAR"},
                 {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
  voxtest::writeText(dir.file("h.gltf"), gltf);
  const Read r = readWith(dir.file("h.gltf"));
  const Mesh& m = r.mesh;
  ASSERT_EQ(m.triangleCount(), 2u + 2u + 1u) << "fan 2, strip 2, lines skipped, 3 indices as TRIANGLES give 1";
  EXPECT_TRUE(anyContains(r.warnings, "mode 1")) << "the LINES primitive is reported";
  // Vertex (1,0,0) -> scale 2 -> rotate 90 about z -> (0,2,0) -> translate -> (0,2,5).
  const auto& p = m.positions[m.triangles[0][1]];
  EXPECT_NEAR(p[0], 0.0, 1e-5);
  EXPECT_NEAR(p[1], 2.0, 1e-5);
  EXPECT_NEAR(p[2], 5.0, 1e-12);
  EXPECT_EQ(m.parts[m.trianglePart[0]].nodeName, "root/arm");
  EXPECT_EQ(m.parts[m.trianglePart[0]].meshName, "sq");
  for (size_t t = 0; t < 5; ++t) EXPECT_GT(normal(m, t)[2], 0) << "fans and strips keep counter-clockwise winding " << t;
  EXPECT_EQ(m.materials[m.triangleMaterial[0]].name, "") << "no material: the default white one";
  EXPECT_FALSE(m.hasColor());
}

TEST(GltfIo, MirroredNodeKeepsOutwardWinding) {
  voxtest::TempDir dir;
  voxtest::writeText(dir.file("m.gltf"), kGltfHead + R"("scenes":[{"nodes":[0,1]}],"scene":0,
    "nodes":[{"mesh":0},{"scale":[-1,1,1],"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)" +
                                             triangleBuffers() + "}");
  const Mesh m = read(dir.file("m.gltf"));
  ASSERT_EQ(m.triangleCount(), 2u);
  EXPECT_GT(normal(m, 0)[2], 0);
  EXPECT_GT(normal(m, 1)[2], 0) << "a negative-determinant node flips the triangle order (glTF 3.7.4)";
}

TEST(GltfIo, SparseNormalizedColoursStrideAndTexture) {
  voxtest::TempDir dir;
  std::string bin;
  // view 0 (interleaved, stride 20): position float3 + COLOR_0 ubyte4 normalized.
  const float pos[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const uint8_t col[3][4] = {{255, 0, 0, 255}, {0, 255, 0, 51}, {0, 0, 255, 255}};
  for (int i = 0; i < 3; ++i) {
    for (float f : pos[i]) putLE(bin, f);
    for (uint8_t c : col[i]) bin.push_back(char(c));
    putLE(bin, uint32_t(0));  // padding to the stride
  }
  const size_t sparseIdx = bin.size();  // view 1: sparse indices (ubyte) {2}
  bin.push_back(char(2));
  pad4(bin);
  const size_t sparseVal = bin.size();  // view 2: sparse values float3 {(0, 3, 0)}
  for (float f : {0.f, 3.f, 0.f}) putLE(bin, f);
  const size_t uvOff = bin.size();  // view 3: TEXCOORD_1 ushort2 normalized
  for (uint16_t u : {0, 0, 65535, 0, 0, 65535}) putLE(bin, u);
  const size_t col3 = bin.size();  // view 4: COLOR_0 ushort3 normalized (second primitive)
  for (uint16_t c : {65535, 0, 0, 0, 65535, 0, 0, 0, 65535}) putLE(bin, c);
  pad4(bin);
  const std::string uri = dataUri(bin);
  auto s = [](size_t v) { return std::to_string(v); };
  const std::string gltf = kGltfHead + R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"primitives":[
       {"attributes":{"POSITION":0,"COLOR_0":1,"TEXCOORD_1":2},"material":0},
       {"attributes":{"POSITION":3,"COLOR_0":4}}]}],
    "materials":[{"name":"painted","pbrMetallicRoughness":{"baseColorFactor":[0.5,0.5,0.5,1],
                  "baseColorTexture":{"index":0,"texCoord":1}}}],
    "textures":[{"source":0,"sampler":0}],
    "samplers":[{"magFilter":9728,"wrapS":33071,"wrapT":33648}],
    "images":[{"uri":"data:image/png;base64,)" + std::string(kPng2x2) + R"("}],
    "buffers":[{"byteLength":)" + s(bin.size()) + R"(,"uri":")" + uri + R"("}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":60,"byteStride":20},
                   {"buffer":0,"byteOffset":)" + s(sparseIdx) + R"(,"byteLength":1},
                   {"buffer":0,"byteOffset":)" + s(sparseVal) + R"(,"byteLength":12},
                   {"buffer":0,"byteOffset":)" + s(uvOff) + R"(,"byteLength":12},
                   {"buffer":0,"byteOffset":)" + s(col3) + R"(,"byteLength":18}],
    "accessors":[
      {"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,3,0],
       "sparse":{"count":1,"indices":{"bufferView":1,"componentType":5121},"values":{"bufferView":2}}},
      {"bufferView":0,"byteOffset":12,"componentType":5121,"normalized":true,"count":3,"type":"VEC4"},
      {"bufferView":3,"componentType":5123,"normalized":true,"count":3,"type":"VEC2"},
      {"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[0,3,0],
       "sparse":{"count":1,"indices":{"bufferView":1,"componentType":5121},"values":{"bufferView":2}}},
      {"bufferView":4,"componentType":5123,"normalized":true,"count":3,"type":"VEC3"}]})";
  voxtest::writeText(dir.file("s.gltf"), gltf);
  const Read r = readWith(dir.file("s.gltf"));
  const Mesh& m = r.mesh;
  ASSERT_EQ(m.triangleCount(), 2u);
  EXPECT_EQ(m.positions[m.triangles[0][2]], (std::array<double, 3>{0, 3, 0})) << "sparse value substituted";
  EXPECT_EQ(m.positions[m.triangles[0][1]], (std::array<double, 3>{1, 0, 0})) << "stride 20 respected";
  EXPECT_EQ(m.positions[m.triangles[1][0]], (std::array<double, 3>{0, 0, 0})) << "sparse without bufferView: zeros";
  EXPECT_EQ(m.positions[m.triangles[1][2]], (std::array<double, 3>{0, 3, 0}));
  ASSERT_EQ(m.colors.size(), m.positions.size());
  EXPECT_FLOAT_EQ(m.colors[m.triangles[0][1]][1], 1.0f) << "normalized ubyte, linear (no sRGB decoding)";
  EXPECT_NEAR(m.colors[m.triangles[0][1]][3], 0.2f, 1e-6);
  EXPECT_FLOAT_EQ(m.colors[m.triangles[1][2]][2], 1.0f) << "normalized ushort vec3";
  EXPECT_FLOAT_EQ(m.colors[m.triangles[1][2]][3], 1.0f) << "vec3 colours are opaque";
  ASSERT_EQ(m.uv1.size(), m.positions.size());
  EXPECT_FLOAT_EQ(m.uv1[m.triangles[0][1]][0], 1.0f);
  const MeshMaterial& mat = m.materials[m.triangleMaterial[0]];
  EXPECT_EQ(mat.name, "painted");
  EXPECT_EQ(mat.texCoordSet, 1);
  EXPECT_FLOAT_EQ(mat.baseColorFactor[0], 0.5f);
  ASSERT_GE(mat.texture, 0);
  const MeshTexture& tex = m.textures[size_t(mat.texture)];
  EXPECT_EQ(tex.width, 2u);
  EXPECT_EQ(tex.rgba[0], 255);
  EXPECT_EQ(tex.rgba[15], 128);
  EXPECT_TRUE(tex.nearest);
  EXPECT_EQ(tex.wrapS, MeshTexture::Wrap::ClampToEdge);
  EXPECT_EQ(tex.wrapT, MeshTexture::Wrap::MirroredRepeat);
  EXPECT_TRUE(m.hasColor());
  EXPECT_EQ(m.filesRead.size(), 1u) << "data URIs are not files";
}

TEST(GltfIo, GlbAndExternalFilesAreRecorded) {
  voxtest::TempDir dir;
  std::string bin;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) putLE(bin, f);
  std::string json = kGltfHead + R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
    "buffers":[{"byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})";
  while (json.size() % 4) json.push_back(' ');
  std::string glb = "glTF";
  putLE(glb, uint32_t(2));
  putLE(glb, uint32_t(12 + 8 + json.size() + 8 + bin.size()));
  putLE(glb, uint32_t(json.size()));
  glb += "JSON" + json;
  putLE(glb, uint32_t(bin.size()));
  glb += std::string("BIN\0", 4) + bin;
  voxtest::writeText(dir.file("t.GLB"), glb);
  const Mesh g = read(dir.file("t.GLB"));
  EXPECT_EQ(g.triangleCount(), 1u) << "upper-case extension";
  EXPECT_EQ(g.filesRead.size(), 1u);

  voxtest::writeText(dir.file("ext.bin"), bin);
  voxtest::writeText(dir.file("tex.png"), pngBytes());
  voxtest::writeText(dir.file("e.gltf"), kGltfHead + R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
    "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
    "textures":[{"source":0}],"images":[{"uri":"tex.png"}],
    "buffers":[{"byteLength":36,"uri":"ext.bin"}],"bufferViews":[{"buffer":0,"byteLength":36}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})");
  const Mesh e = read(dir.file("e.gltf"));
  EXPECT_EQ(e.triangleCount(), 1u);
  ASSERT_EQ(e.filesRead.size(), 3u);
  EXPECT_EQ(std::filesystem::path(e.filesRead[1]).filename(), "ext.bin");
  EXPECT_EQ(std::filesystem::path(e.filesRead[2]).filename(), "tex.png");
  EXPECT_EQ(e.textures.size(), 1u);
  std::filesystem::remove(dir.file("ext.bin"));
  EXPECT_TRUE(rejects(dir.file("e.gltf"), {"e.gltf", "ext.bin"}));
}

// Inputs that are not regular files are refused up front by name; a texture
// image that cannot be read is an error (as a missing OBJ map_Kd is), or a
// warning with ignoreMissingMaterials.
TEST(MeshInput, DirectoriesDevicesFifosAndMissingImagesAreRefusedByName) {
  voxtest::TempDir dir;
  std::filesystem::create_directory(dir.file("d.obj"));
  EXPECT_TRUE(rejects(dir.file("d.obj"), {"d.obj", "is a directory"}));
  ASSERT_EQ(mkfifo(dir.file("f.stl").c_str(), 0600), 0);
  EXPECT_TRUE(rejects(dir.file("f.stl"), {"f.stl", "FIFO"}));  // never blocks waiting for a writer
  voxtest::writeText(dir.file("z.obj"), "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_TRUE(rejects(dir.file("z.obj"), {"z.obj", "/dev/zero", "is a device"}));

  std::string bin;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) putLE(bin, f);
  voxtest::writeText(dir.file("t.bin"), bin);
  const auto gltf = [&](const std::string& image, const std::string& buffer) {
    return kGltfHead + R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
    "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
    "textures":[{"source":0}],"images":[{"uri":")" + image + R"("}],
    "buffers":[{"byteLength":36,"uri":")" + buffer + R"("}],"bufferViews":[{"buffer":0,"byteLength":36}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})";
  };
  voxtest::writeText(dir.file("b.gltf"), gltf("missing.png", "d.obj"));  // a buffer naming a directory
  EXPECT_TRUE(rejects(dir.file("b.gltf"), {"b.gltf", "d.obj", "is a directory"}));
  voxtest::writeText(dir.file("m.gltf"), gltf("missing.png", "t.bin"));
  EXPECT_TRUE(rejects(dir.file("m.gltf"), {"m.gltf", "image 0 'missing.png'", "no such file"}));
  voxtest::writeText(dir.file("i.gltf"), gltf("d.obj", "t.bin"));  // an image naming a directory
  EXPECT_TRUE(rejects(dir.file("i.gltf"), {"i.gltf", "image 0 'd.obj'", "is a directory"}));
  MeshReadOptions lenient;
  lenient.ignoreMissingMaterials = true;
  const Read r = readWith(dir.file("m.gltf"), lenient);
  EXPECT_EQ(r.mesh.triangleCount(), 1u);
  EXPECT_TRUE(r.mesh.textures.empty());
  EXPECT_TRUE(anyContains(r.warnings, "missing.png"));
}

TEST(GltfIo, CompressionExtensionsRequiredByPlainPrimitivesAreRead) {
  // Both compression extensions are decoded (test_gltf_ext.cpp, gltfext_test.sh);
  // a file that requires one but compresses nothing reads as a plain file.
  voxtest::TempDir dir;
  for (const std::string ext : {"KHR_draco_mesh_compression", "EXT_meshopt_compression"}) {
    voxtest::writeText(dir.file("c.gltf"), kGltfHead + R"("extensionsUsed":[")" + ext + R"("],"extensionsRequired":[")" +
                                               ext + R"("],"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)" + triangleBuffers() + "}");
    EXPECT_EQ(read(dir.file("c.gltf")).triangleCount(), 1u) << ext;
  }
}

TEST(GltfIo, MalformedFilesNameTheElement) {
  voxtest::TempDir dir;
  const std::string scene = R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)";
  // An index past the vertex count.
  std::string bin;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) putLE(bin, f);
  for (uint16_t i : {0, 1, 7, 0}) putLE(bin, i);
  voxtest::writeText(dir.file("i.gltf"), kGltfHead + scene + R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
    "buffers":[{"byteLength":44,"uri":")" + dataUri(bin) + R"("}],
    "bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                 {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})");
  EXPECT_TRUE(rejects(dir.file("i.gltf"), {"i.gltf", "accessor 1 (indices)", "vertex 7"}));
  // An accessor that reads past its bufferView.
  voxtest::writeText(dir.file("o.gltf"), kGltfHead + scene + R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
    "buffers":[{"byteLength":44,"uri":")" + dataUri(bin) + R"("}],
    "bufferViews":[{"buffer":0,"byteLength":36}],
    "accessors":[{"bufferView":0,"byteOffset":4,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})");
  EXPECT_TRUE(rejects(dir.file("o.gltf"), {"o.gltf", "accessor 0 (POSITION)", "past"}));
  // A count no buffer can hold: a clear error, not an allocation failure.
  voxtest::writeText(dir.file("c.gltf"), kGltfHead + scene + R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
    "buffers":[{"byteLength":44,"uri":")" + dataUri(bin) + R"("}],
    "bufferViews":[{"buffer":0,"byteLength":36}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":4611686018427387904,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})");
  EXPECT_TRUE(rejects(dir.file("c.gltf"), {"c.gltf", "accessors[0].count", "above its limit"}));
  // What tinygltf would coerce or never check, each refused by its element
  // (a negative byteOffset used to read the normals as positions).
  const std::string buffers = R"("buffers":[{"byteLength":44,"uri":")" + dataUri(bin) + R"("}],)";
  const std::string prim = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)";
  const std::string position = R"("componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0])";
  struct Case {
    const char* file;
    std::string body;
    std::vector<std::string> says;
  };
  const std::vector<Case> cases = {
      {"neg_offset.gltf", prim + buffers + R"("bufferViews":[{"buffer":0,"byteLength":36}],
        "accessors":[{"bufferView":0,"byteOffset":-12,)" + position + "}]}",
       {"accessors[0].byteOffset", "-12"}},
      {"stride.gltf", prim + buffers + R"("bufferViews":[{"buffer":0,"byteLength":36,"byteStride":8}],
        "accessors":[{"bufferView":0,)" + position + "}]}",
       {"accessor 0 (POSITION)", "byteStride 8", "12-byte element"}},
      {"stride_odd.gltf", prim + buffers + R"("bufferViews":[{"buffer":0,"byteLength":36,"byteStride":14}],
        "accessors":[{"bufferView":0,)" + position + "}]}",
       {"bufferViews[0].byteStride", "multiple of 4"}},
      {"material.gltf", R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":3}]}],"materials":[{}],)" +
                            buffers + R"("bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,)" + position + "}]}",
       {"meshes[0].primitives[0].material", "is 3", "0..0"}},
      {"texture.gltf", prim + R"("materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":2}}}],)" + buffers +
                           R"("bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,)" + position + "}]}",
       {"materials[0].pbrMetallicRoughness.baseColorTexture.index", "no", "textures"}},
      {"sparse.gltf", prim + buffers + R"("bufferViews":[{"buffer":0,"byteLength":36}],
        "accessors":[{"bufferView":0,)" + position + R"(,"sparse":{"count":4000000000,"indices":{"bufferView":0,"componentType":5125},"values":{"bufferView":0}}}]})",
       {"accessors[0].sparse.count", "4000000000"}},
      {"required.gltf", R"("extensionsRequired":["KHR_texture_basisu"],)" + prim + buffers +
                            R"("bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,)" + position + "}]}",
       {"KHR_texture_basisu", "could change the voxels"}},
  };
  for (const Case& c : cases) {
    voxtest::writeText(dir.file(c.file), kGltfHead + scene + c.body);
    EXPECT_TRUE(rejects(dir.file(c.file), {c.file})) << c.file;
    for (const std::string& needle : c.says) EXPECT_TRUE(rejects(dir.file(c.file), {needle})) << c.file;
  }
  // Required extensions that cannot change the voxels are read.
  voxtest::writeText(dir.file("unlit.gltf"), kGltfHead + scene + R"("extensionsUsed":["KHR_materials_unlit","KHR_mesh_quantization"],
    "extensionsRequired":["KHR_materials_unlit","KHR_mesh_quantization"],)" + prim + buffers +
                                               R"("bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,)" + position + "}]}");
  EXPECT_EQ(read(dir.file("unlit.gltf")).triangleCount(), 1u);
  // A node reached twice (two parents): an error, not an exponential walk.
  std::string nodes;
  for (int i = 0; i < 48; ++i)
    nodes += std::string(i ? "," : "") +
             (i < 47 ? R"({"children":[)" + std::to_string(i + 1) + "," + std::to_string(i + 1) + "]}" : R"({"mesh":0})");
  voxtest::writeText(dir.file("d.gltf"), kGltfHead + R"("scenes":[{"nodes":[0]}],"nodes":[)" + nodes +
                                             R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)" +
                                             triangleBuffers() + "}");
  EXPECT_TRUE(rejects(dir.file("d.gltf"), {"d.gltf", "node 47", "twice"}));
  // NaN and infinite positions: named by accessor with the count, or dropped.
  std::string nan;
  for (float f : {0.f, 0.f, 0.f, std::numeric_limits<float>::quiet_NaN(), 0.f, 0.f, 0.f,
                  std::numeric_limits<float>::infinity(), 0.f, 1.f, 1.f, 0.f})
    putLE(nan, f);
  for (uint16_t i : {0, 1, 2, 0, 2, 3}) putLE(nan, i);
  voxtest::writeText(dir.file("n.gltf"), kGltfHead + scene + R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
    "buffers":[{"byteLength":60,"uri":")" + dataUri(nan) + R"("}],
    "bufferViews":[{"buffer":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":12}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                 {"bufferView":1,"componentType":5123,"count":6,"type":"SCALAR"}]})");
  EXPECT_TRUE(rejects(dir.file("n.gltf"), {"n.gltf", "accessor 0 (POSITION)", "2 NaN or infinite", "drop their triangles"}));
  EXPECT_EQ(voxtest::settingOfError([&] { read(dir.file("n.gltf")); }), Setting::DropInvalid);
  MeshReadOptions drop;
  drop.dropInvalid = true;
  const Read r = readWith(dir.file("n.gltf"), drop);
  EXPECT_EQ(r.mesh.triangleCount(), 0u) << "both triangles touch a bad vertex";
  EXPECT_TRUE(anyContains(r.warnings, "dropped 2 triangles"));
  // Not glTF at all, and a missing file.
  voxtest::writeText(dir.file("x.glb"), "glTF but not really");
  EXPECT_TRUE(rejects(dir.file("x.glb"), {"x.glb"}));
  EXPECT_TRUE(rejects(dir.file("absent.gltf"), {"absent.gltf"}));
  voxtest::writeText(dir.file("model.fbx"), "Kaydara FBX Binary");
  EXPECT_TRUE(rejects(dir.file("model.fbx"), {"model.fbx", ".obj"}));
}

// What the glTF 2.0 specification requires of positions, node transforms, the
// default scene and triangle lists, which tinygltf does not check: each was
// read as something else (pairs as positions, an identity transform, every
// root node, a dropped vertex).
TEST(GltfIo, SpecificationRulesOnPositionsNodesScenesAndTriangleCounts) {
  voxtest::TempDir dir;
  std::string bin;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) putLE(bin, f);
  for (uint16_t i : {0, 1, 2, 0, 1, 0}) putLE(bin, i);
  const std::string buffers = R"("buffers":[{"byteLength":48,"uri":")" + dataUri(bin) + R"("}],
    "bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":12}],)";
  const std::string position = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]})";
  auto file = [&](const std::string& name, const std::string& nodes, const std::string& rest) {
    voxtest::writeText(dir.file(name), kGltfHead + R"("scenes":[{"nodes":[0]}],"nodes":[)" + nodes + "]," + rest + "}");
    return dir.file(name);
  };
  const std::string mesh = R"("meshes":[{"name":"m","primitives":[{"attributes":{"POSITION":0}}]}],)";
  auto plain = [&](const std::string& name, const std::string& node) {
    return file(name, node, mesh + buffers + R"("accessors":[)" + position + "]");
  };
  EXPECT_EQ(read(plain("ok.gltf", R"({"mesh":0})")).triangleCount(), 1u);
  // POSITION of the wrong type, or of bytes without KHR_mesh_quantization.
  const std::string vec2 = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC2"})";
  EXPECT_TRUE(rejects(file("vec2.gltf", R"({"mesh":0})", mesh + buffers + R"("accessors":[)" + vec2 + "]"),
                      {"vec2.gltf", "meshes[0].primitives[0].attributes.POSITION (accessor 0)", "\"VEC2\"",
                       "positions are VEC3"}));
  const std::string bytes = R"({"bufferView":0,"componentType":5121,"count":3,"type":"VEC3"})";
  EXPECT_TRUE(rejects(file("ubyte.gltf", R"({"mesh":0})", mesh + buffers + R"("accessors":[)" + bytes + "]"),
                      {"ubyte.gltf", "POSITION (accessor 0)", "componentType 5121", "KHR_mesh_quantization"}));
  EXPECT_EQ(read(file("quantized.gltf", R"({"mesh":0})", R"("extensionsUsed":["KHR_mesh_quantization"],
    "extensionsRequired":["KHR_mesh_quantization"],)" + mesh + buffers + R"("accessors":[)" + bytes + "]")).triangleCount(), 1u)
      << "the extension allows bytes";
  // Node transforms: arrays of 16, 3, 4 and 3 numbers.
  EXPECT_TRUE(rejects(plain("matrix.gltf", R"({"mesh":0,"matrix":[1,0,0,1]})"),
                      {"matrix.gltf", "nodes[0].matrix", "not an array of 16 numbers"}));
  EXPECT_TRUE(rejects(plain("scale.gltf", R"({"mesh":0,"scale":["a",1,1]})"),
                      {"scale.gltf", "nodes[0].scale[0]", "\"a\"", "not a number"}));
  EXPECT_TRUE(rejects(plain("translation.gltf", R"({"mesh":0,"translation":[1,2]})"), {"nodes[0].translation", "3 numbers"}));
  // Rotations: clearly not unit refused; within the validator's tolerance normalised.
  EXPECT_TRUE(rejects(plain("rot.gltf", R"({"mesh":0,"rotation":[0,0,10,0]})"),
                      {"rot.gltf", "nodes[0].rotation", "[0,0,10,0]", "not a unit quaternion"}));
  EXPECT_TRUE(rejects(plain("rot0.gltf", R"({"mesh":0,"rotation":[0,0,0,0]})"), {"nodes[0].rotation"}));
  const Mesh off = read(plain("near.gltf", R"({"mesh":0,"rotation":[0,0,0.7072,0.7072]})"));
  const Mesh unit = read(plain("unit.gltf", R"({"mesh":0,"rotation":[0,0,0.7071067811865476,0.7071067811865476]})"));
  ASSERT_EQ(off.positions.size(), 3u);
  for (size_t v = 0; v < 3; ++v)
    for (size_t k = 0; k < 3; ++k) EXPECT_NEAR(off.positions[v][k], unit.positions[v][k], 1e-15) << "normalised";
  EXPECT_NEAR(unit.positions[1][1], 1.0, 1e-15) << "(1,0,0) turned 90 degrees about z";
  // The default scene must exist.
  EXPECT_TRUE(rejects(file("scene.gltf", R"({"mesh":0})", R"("scene":5,)" + mesh + buffers + R"("accessors":[)" + position + "]"),
                      {"scene.gltf", "scene is 5", "scenes are 0..0"}));
  // TRIANGLES takes a multiple of 3 indices (or vertices).
  const std::string five = R"({"bufferView":1,"componentType":5123,"count":5,"type":"SCALAR"})";
  EXPECT_TRUE(rejects(file("five.gltf", R"({"mesh":0})",
                           R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)" + buffers +
                               R"("accessors":[)" + position + "," + five + "]"),
                      {"five.gltf", "meshes[0].primitives[0]", "TRIANGLES", "indices accessor 1 has 5 elements",
                       "multiple of 3"}));
  const std::string two = R"({"bufferView":0,"componentType":5126,"count":2,"type":"VEC3","min":[0,0,0],"max":[1,0,0]})";
  EXPECT_TRUE(rejects(file("two.gltf", R"({"mesh":0})", mesh + buffers + R"("accessors":[)" + two + "]"),
                      {"meshes[0].primitives[0]", "POSITION accessor 0 has 2 elements"}));
  EXPECT_GE(read(file("strip.gltf", R"({"mesh":0})", R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":5}]}],)" +
                                                         buffers + R"("accessors":[)" + position + "," + five + "]")).triangleCount(), 1u)
      << "a strip takes any count";
}

// ============================== Mesh ==============================

TEST(MeshStruct, AppendRebasesEverythingAndKeepsAttributesParallel) {
  Mesh a;
  a.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  a.triangles = {{0, 1, 2}};
  a.triangleMaterial = {0};
  a.trianglePart = {0};
  a.materials = {{"white", {1, 1, 1, 1}, -1, 0}};
  a.parts = {{"a", "a.obj"}};
  a.filesRead = {"a.obj"};
  EXPECT_FALSE(a.hasColor());
  Mesh b = a;
  b.colors.assign(3, {0.5f, 0.5f, 0.5f, 1});
  b.uv0.assign(3, {0.25f, 0.75f});
  b.textures.resize(1);
  b.materials[0].texture = 0;
  b.parts[0].nodeName = "b";
  b.filesRead = {"b.glb"};
  EXPECT_TRUE(b.hasColor());
  a.append(b);
  ASSERT_EQ(a.positions.size(), 6u);
  EXPECT_EQ(a.triangles[1], (std::array<uint32_t, 3>{3, 4, 5}));
  EXPECT_EQ(a.triangleMaterial, (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(a.trianglePart, (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(a.materials[1].texture, 0);
  EXPECT_EQ(a.colors.size(), 6u);
  EXPECT_EQ(a.colors[0], (std::array<float, 4>{1, 1, 1, 1})) << "padding is white";
  EXPECT_EQ(a.uv0.size(), 6u);
  EXPECT_EQ(a.uv1.size(), 0u);
  EXPECT_EQ(a.filesRead, (std::vector<std::string>{"a.obj", "b.glb"}));
  EXPECT_TRUE(a.hasColor());
  Mesh c;
  c.materials = {{"tinted", {1, 0.5f, 1, 1}, -1, 0}};
  EXPECT_TRUE(c.hasColor()) << "a non-white factor is colour";
}

// ============================== third-party files ==============================

TEST(MeshIoData, TriangleCountsOfTheSharedFiles) {
  if (!haveData()) GTEST_SKIP() << kData << " is absent: third-party mesh files not checked";
  MeshReadOptions ignore;
  ignore.ignoreMissingMaterials = true;
  struct Case {
    const char* file;
    size_t triangles;
    bool ignoreMissing;
  };
  // Counts from MANIFEST.md; glTF counts are per instance (MANIFEST counts each mesh once
  // for 2CylinderEngine, 75,730, and TextureTransformTest, 18: 121,496 and 24 instanced).
  const Case cases[] = {
      {"common-3d-test-models/beetle.obj", 2053, true},  // its VWBugMesh002.mtl is not shipped
      {"common-3d-test-models/fandisk.obj", 12946, false},
      {"common-3d-test-models/spot.obj", 5856, false},
      {"common-3d-test-models/stanford-bunny.obj", 69451, false},
      {"common-3d-test-models/suzanne.obj", 968, false},
      {"common-3d-test-models/teapot.obj", 6320, false},
      {"common-3d-test-models/woody.obj", 1267, false},
      {"cuda_voxelizer/bunny.OBJ", 5110, false},
      {"cgal-data/pig.stl", 16848, false},
      {"cgal-data/b9.ply", 0, false},
      {"mesh-misc/assimp/Spider_binary.stl", 1368, false},
      {"mesh-misc/assimp/sphereWithHole.stl", 285, false},
      {"mesh-misc/assimp/Wuson.ply", 3732, false},
      {"mesh-misc/assimp/WusonOBJ.obj", 3732, false},
      {"mesh-misc/assimp/concave_polygon.obj", 64, true},  // its .mtl is not shipped
      {"mesh-misc/assimp/cube_binary.ply", 12, false},
      {"mesh-misc/assimp/cube_with_vertexcolors.obj", 12, false},
      {"mesh-misc/assimp/float-color.ply", 1, false},
      {"mesh-misc/assimp/spider.obj", 1368, false},  // ".\\tex.jpg" paths in spider.mtl
      {"khronos-gltf-sample-models/SimpleSparseAccessor/SimpleSparseAccessor.gltf", 12, false},
      {"gltf/assimp/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", 121496, false},
      {"gltf/assimp/BoxTextured-glTF-Binary/BoxTextured.glb", 12, false},
      {"gltf/assimp/BoxTextured-glTF-Embedded/BoxTextured.gltf", 12, false},
      {"gltf/assimp/Triangle-Mesh-Quantized/triangle_mesh_quantized.gltf", 1, false},
      {"gltf/assimp/textureTransform/TextureTransformTest.gltf", 24, false},
      {"gltf/gltf-pipeline/box-textured-binary/box-textured-binary.glb", 12, false},
      {"gltf/gltf-pipeline/extensions/EXT_meshopt_compression/meshopt-fallback/meshopt-fallback.gltf", 60, false},
      {"gltf/gltf-pipeline/extensions/KHR_materials_transmission/KHR_materials_transmission.gltf", 12689, false},
      {"gltf/gltf-pipeline/multiple-boxes/multiple-boxes.gltf", 48, false},
      {"gltf/gltf-pipeline/triangle-without-indices/triangle-without-indices.gltf", 1, false},
      {"gltf/tinygltf/SparseMorphTargets-issue280/singleBlendshapeCube_sparse.glb", 12, false},
      {"gltf/tinygltf/regression/zero-sized-bin-chunk-issue-440.glb", 1, false},
  };
  for (const Case& c : cases) {
    const std::string path = kData + "/" + c.file;
    if (!std::filesystem::exists(path)) {
      ADD_FAILURE() << path << " is listed in MANIFEST.md but missing";
      continue;
    }
    try {
      EXPECT_EQ(read(path, c.ignoreMissing ? ignore : MeshReadOptions{}).triangleCount(), c.triangles) << c.file;
    } catch (const std::exception& e) {
      ADD_FAILURE() << c.file << ": " << e.what();
    }
  }
  EXPECT_EQ(read(kData + "/mesh-misc/assimp/spider.obj").textures.size(), 5u);
  EXPECT_TRUE(rejects(kData + "/common-3d-test-models/beetle.obj", {"beetle.obj:3", "VWBugMesh002.mtl"}));
}

TEST(MeshIoData, PrimitiveModesAndBadFiles) {
  if (!haveData()) GTEST_SKIP() << kData << " is absent: third-party glTF files not checked";
  const std::string dir = kData + "/gltf/assimp/glTF-Asset-Generator/Mesh_PrimitiveMode/";
  for (int i = 0; i <= 15; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "Mesh_PrimitiveMode_%02d.gltf", i);
    const bool triangles = (i >= 4 && i <= 6) || i >= 11;  // see the folder's README.md
    const Read r = readWith(dir + name);
    EXPECT_EQ(r.mesh.triangleCount(), triangles ? 2u : 0u) << name;
    EXPECT_EQ(anyContains(r.warnings, "skipped"), !triangles) << name;
  }
  const std::string a = kData + "/gltf/assimp/";
  EXPECT_TRUE(rejects(a + "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", {"accessor", "(POSITION)", "NaN or infinite"}));
  EXPECT_TRUE(rejects(a + "IndexOutOfRange/IndexOutOfRange.gltf", {"(indices)", "vertex 255"}));
  EXPECT_TRUE(rejects(a + "IndexOutOfRange/AllIndicesOutOfRange.gltf", {"(indices)"}));
  EXPECT_TRUE(rejects(a + "MissingBin/BoxTextured.gltf", {"BoxTextured0.bin"}));
  EXPECT_EQ(read(a + "draco/2CylinderEngine.gltf").triangleCount(), 110336u) << "Draco decoded";
  const std::string t = kData + "/gltf/tinygltf/BoundsChecking/";
  for (const char* f : {"integer-out-of-bounds.gltf", "invalid-buffer-index.gltf", "invalid-primitive-indices.gltf"})
    EXPECT_TRUE(rejects(t + f, {f})) << f;
  const Mesh box = read(a + "BoxTextured-glTF/BoxTextured.gltf");
  EXPECT_EQ(box.filesRead.size(), 3u) << "gltf, bin, png";
  EXPECT_EQ(box.textures.size(), 1u);
}

TEST(ObjIo, VertexColoursAreSrgbDecodedAndOptionalPerVertex) {
  voxtest::TempDir dir;
  // Vertex 1: sRGB 0.5 grey; vertex 2: red with alpha; vertex 3: x y z w (no colour: white).
  voxtest::writeText(dir.file("c.obj"), "v 0 0 0 0.5 0.5 0.5\nv 1 0 0 1 0 0 0.25\nv 0 1 0 1.0\nf 1 2 3\n");
  const Mesh m = read(dir.file("c.obj"));
  ASSERT_EQ(m.colors.size(), m.positions.size());
  const double half = std::pow((0.5 + 0.055) / 1.055, 2.4);  // the sRGB curve at 0.5: 0.214
  EXPECT_NEAR(m.colors[0][0], half, 1e-6);
  EXPECT_NEAR(m.colors[0][2], half, 1e-6);
  EXPECT_EQ(m.colors[0][3], 1.0f);
  EXPECT_EQ(m.colors[1], (std::array<float, 4>{1, 0, 0, 0.25f}));
  EXPECT_EQ(m.colors[2], (std::array<float, 4>{1, 1, 1, 1}));
  EXPECT_TRUE(m.hasColor());
  // The first colour on a later line: the plain vertices before it and after it are white.
  voxtest::writeText(dir.file("late.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0 0 0 1\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
  const Mesh late = read(dir.file("late.obj"));
  ASSERT_EQ(late.colors.size(), 4u);  // mesh vertices in corner order: v1, v2, v3, v4
  EXPECT_EQ(late.colors[0], (std::array<float, 4>{1, 1, 1, 1}));
  EXPECT_EQ(late.colors[1], (std::array<float, 4>{1, 1, 1, 1}));
  EXPECT_EQ(late.colors[2], (std::array<float, 4>{0, 0, 1, 1}));
  EXPECT_EQ(late.colors[3], (std::array<float, 4>{1, 1, 1, 1}));
  // Without colours nothing changes.
  voxtest::writeText(dir.file("n.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0 # comment\nf 1 2 3\n");
  EXPECT_TRUE(read(dir.file("n.obj")).colors.empty());
  // Malformed colours name the line.
  voxtest::writeText(dir.file("b.obj"), "v 0 0 0\nv 1 0 0 0.5 0.5\nv 0 1 0\nf 1 2 3\n");
  EXPECT_TRUE(rejects(dir.file("b.obj"), {"b.obj:2", "5 numbers"}));
  voxtest::writeText(dir.file("r.obj"), "v 0 0 0 2 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_TRUE(rejects(dir.file("r.obj"), {"r.obj:1", "outside [0, 1]"}));
}
