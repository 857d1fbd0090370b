// The OBJ reader with several threads reads the numbers of "v" and "f" lines
// ahead, in windows of whole lines, and builds the mesh in one pass: the mesh,
// its warnings and its errors must be those of the one-thread reader, for
// files longer than a window and lines the read-ahead leaves to the pass
// (colours, comments, bad numbers, bad indices).
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "formats/mesh/mesh_input.h"
#include "libvox/core/error.h"

using namespace vox;

namespace {

struct Read {
  Mesh mesh;
  std::vector<std::string> warnings;
  std::string error;
};

Read parse(const std::string& text, unsigned threads) {
  Read r;
  MeshReadOptions o;
  o.threads = threads;
  try {
    r.mesh = parseObj(text.data(), text.size(), "t.obj", o, r.warnings, ".");
  } catch (const Error& e) {
    r.error = e.what();
  }
  return r;
}

void expectSame(const Read& a, const Read& b, const std::string& what) {
  EXPECT_EQ(a.error, b.error) << what;
  EXPECT_EQ(a.warnings, b.warnings) << what;
  EXPECT_EQ(a.mesh.positions, b.mesh.positions) << what;
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles) << what;
  EXPECT_EQ(a.mesh.triangleMaterial, b.mesh.triangleMaterial) << what;
  EXPECT_EQ(a.mesh.trianglePart, b.mesh.trianglePart) << what;
  EXPECT_EQ(a.mesh.uv0, b.mesh.uv0) << what;
  EXPECT_EQ(a.mesh.colors, b.mesh.colors) << what;
  ASSERT_EQ(a.mesh.materials.size(), b.mesh.materials.size()) << what;
  for (size_t i = 0; i < a.mesh.materials.size(); ++i) EXPECT_EQ(a.mesh.materials[i].name, b.mesh.materials[i].name);
  ASSERT_EQ(a.mesh.parts.size(), b.mesh.parts.size()) << what;
  for (size_t i = 0; i < a.mesh.parts.size(); ++i) EXPECT_EQ(a.mesh.parts[i].nodeName, b.mesh.parts[i].nodeName);
}

/// About `lines` lines of every kind the reader knows, valid.
std::string randomObj(std::mt19937& rng, size_t lines, bool colours) {
  std::string s = "# read-ahead test\n";
  size_t v = 0, vt = 0;
  std::uniform_real_distribution<double> x(-100, 100);
  auto num = [&]() {
    char b[32];
    std::snprintf(b, sizeof b, rng() % 7 ? "%.6f" : "+%.3e", x(rng));
    return std::string(b);
  };
  for (size_t i = 0; i < lines; ++i) {
    const unsigned k = rng() % 100;
    const char* eol = rng() % 13 ? "\n" : "\r\n";
    if (k < 35 || v < 4) {
      s += (rng() % 9 ? "v " : "v\t ") + num() + " " + num() + " " + num();
      if (colours && rng() % 5 == 0) s += " 0.5 0.25 1";
      if (rng() % 17 == 0) s += " # note";
      s += eol, ++v;
    } else if (k < 45) {
      s += "vt 0." + std::to_string(rng() % 1000) + " 0." + std::to_string(rng() % 1000) + eol, ++vt;
    } else if (k < 90) {
      const int corners = 3 + int(rng() % 3);
      s += "f";
      for (int c = 0; c < corners; ++c) {
        const bool relative = rng() % 4 == 0;
        const int64_t i = relative ? -int64_t(1 + rng() % v) : int64_t(1 + rng() % v);
        s += (rng() % 5 ? " " : "  ") + std::to_string(i);
        const unsigned form = vt ? rng() % 4 : 0;
        if (form == 1) s += "/" + std::to_string(1 + rng() % vt);
        if (form == 2) s += "//" + std::to_string(1 + rng() % 9);
        if (form == 3) s += "/" + std::to_string(-int64_t(1 + rng() % vt)) + "/2";
      }
      s += eol;
    } else if (k < 93) {
      s += "o part" + std::to_string(i) + eol;
    } else if (k < 95) {
      s += "usemtl m" + std::to_string(rng() % 3) + eol;
    } else if (k < 97) {
      s += "# a comment\n";
    } else if (k < 98) {
      s += "   \n";
    } else {
      s += "s off\n";
    }
  }
  return s;
}

}  // namespace

TEST(ObjReadAhead, LongFilesMatchTheOneThreadReader) {
  std::mt19937 rng(2);
  // 400 000 lines: past the 8 MB window, so windows meet mid-file.
  for (bool colours : {false, true}) {
    const std::string text = randomObj(rng, colours ? 20000 : 400000, colours);
    const Read one = parse(text, 1);
    ASSERT_TRUE(one.error.empty()) << one.error;
    EXPECT_GT(one.mesh.triangles.size(), 1000u);
    for (unsigned threads : {2u, 3u}) expectSame(one, parse(text, threads), "threads " + std::to_string(threads));
  }
}

TEST(ObjReadAhead, ErrorsMatchTheOneThreadReader) {
  std::mt19937 rng(3);
  const std::string base = randomObj(rng, 3000, true);
  const std::vector<std::string> bad = {"v 1 2 zero\n",  "v 1 2\n",        "v 1 2 3 4 5\n", "f 1 2\n",    "f 1 2 999999\n",
                                        "f 0 1 2\n",     "f 1/0 2 3\n",    "f 1 2 x3\n",    "f 1/a 2 3\n", "v 1 2 nan\n",
                                        "f -999999 1 2\n", "v 1 2 3 2 0 0\n"};
  for (size_t i = 0; i < bad.size(); ++i) {
    // Insert at a line start somewhere in the middle.
    size_t at = base.find('\n', base.size() * (i + 1) / (bad.size() + 1)) + 1;
    const std::string text = base.substr(0, at) + bad[i] + base.substr(at);
    const Read one = parse(text, 1);
    EXPECT_FALSE(one.error.empty()) << "inserted " << bad[i];
    expectSame(one, parse(text, 2), "inserted " + bad[i]);
  }
}
