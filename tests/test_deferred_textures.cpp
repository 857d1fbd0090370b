// Textures read by rows after the geometry (VoxelizeSettings::textureRows,
// libvox/mesh/texture_rows.h; formats/mesh/deferred_textures.h for glTF):
// the colours equal, bit for bit, those of a bake with the pixels in the mesh
// from the start, at any thread count, for bilinear and nearest samplers,
// every wrap mode, several textures on one image and images of a few bands;
// every image is read once, top to bottom, to its end; the first image in
// index order that cannot be read ends the bake with its error.
#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <tuple>

#include "formats/mesh/deferred_textures.h"
#include "formats/mesh/gltf_reader.h"
#include "formats/mesh/texture_image.h"
#include "libvox/core/error.h"
#include "libvox/mesh/texture_sampling.h"
#include "libvox/scene/voxelize_scene.h"
#include "test_util.h"
#include "voxelize_test_meshes.h"

using namespace vox;

namespace {

MeshTexture noiseTexture(uint32_t w, uint32_t h, unsigned seed) {
  MeshTexture t;
  t.width = w, t.height = h;
  std::mt19937 rng(seed);
  t.rgba.resize(size_t(w) * h * 4);
  for (size_t i = 0; i < t.rgba.size(); ++i) t.rgba[i] = i % 4 == 3 ? 255 : uint8_t(rng() & 0xFF);
  return t;
}

/// Four 24 x 24 voxel squares side by side at z = 0.5:
///  0: image 0 (37 x 53 texels: four bands, the last partial) bilinear, Repeat,
///     texture coordinates from -0.7 to 1.6 (wrapping both ways, samples on the
///     last row whose second row is row 0);
///  1: image 0 again through another texture: nearest, MirroredRepeat x ClampToEdge;
///  2: image 1 (5 x 33: two bands and a last row alone, so the row after the
///     second band is the image's last) bilinear, ClampToEdge, coordinates beyond [0, 1];
///  3: texture 3, whose pixels are in the mesh (sampled by its tile as the geometry ends).
/// Squares 0 and 1 share the voxels of x = 24.
Mesh texturedSquares() {
  std::vector<std::array<double, 3>> pos;
  std::vector<std::array<uint32_t, 3>> tris;
  const double x0[4] = {0, 24, 50, 76};
  for (int q = 0; q < 4; ++q) {
    const uint32_t b = uint32_t(pos.size());
    pos.push_back({x0[q], 0, 0.5}), pos.push_back({x0[q] + 24, 0, 0.5}), pos.push_back({x0[q] + 24, 24, 0.5}),
        pos.push_back({x0[q], 24, 0.5});
    tris.push_back({b, b + 1, b + 2}), tris.push_back({b, b + 2, b + 3});
  }
  Mesh m = voxtest::meshOf(pos, tris);
  m.uv0 = {{-0.7, 1.6}, {1.6, 1.6}, {1.6, -0.7}, {-0.7, -0.7},  // square 0
           {-1.2, 1.3}, {1.9, 1.3}, {1.9, -0.4}, {-1.2, -0.4},  // square 1
           {-0.2, 1.2}, {1.2, 1.2}, {1.2, -0.2}, {-0.2, -0.2},  // square 2
           {0, 1}, {1, 1}, {1, 0}, {0, 0}};                     // square 3
  const MeshTexture image0 = noiseTexture(37, 53, 1), image1 = noiseTexture(5, 33, 2);
  m.textures.push_back(image0);
  m.textures.push_back(image0);
  m.textures[1].nearest = true;
  m.textures[1].wrapS = MeshTexture::Wrap::MirroredRepeat, m.textures[1].wrapT = MeshTexture::Wrap::ClampToEdge;
  m.textures.push_back(image1);
  m.textures[2].wrapS = m.textures[2].wrapT = MeshTexture::Wrap::ClampToEdge;
  m.textures.push_back(noiseTexture(8, 8, 3));
  m.materials.clear();
  for (int q = 0; q < 4; ++q) m.materials.push_back({"m" + std::to_string(q), {1, 0.75f, 0.5f, 1}, q, 0});
  m.triangleMaterial = {0, 0, 1, 1, 2, 2, 3, 3};
  return m;
}

/// Images in memory handed out by rows, image i the pixels of the mesh
/// textures texturesOf[i]; what was read is recorded (a read out of order, two
/// reads of one image at once), and a header or a read can be made to fail.
class MemoryRows final : public TextureRowSource {
 public:
  MemoryRows(std::vector<MeshTexture> pixels, std::vector<std::vector<size_t>> texturesOf)
      : opened(pixels.size(), 0), rowsRead(pixels.size(), 0), failOpen(pixels.size(), false),
        failAtRow(pixels.size(), ~0u), pixels_(std::move(pixels)), textures_(std::move(texturesOf)),
        reading_(pixels_.size()) {}
  /// Images 0 (textures 0 and 1) and 1 (texture 2) of texturedSquares.
  static std::vector<MeshTexture> squaresImages(const Mesh& m) { return {m.textures[0], m.textures[2]}; }
  static std::vector<std::vector<size_t>> squaresTextures() { return {{0, 1}, {2}}; }

  size_t images() const override { return pixels_.size(); }
  const std::vector<size_t>& texturesOf(size_t image) const override { return textures_[image]; }
  std::array<uint32_t, 2> size(size_t image) const override { return {pixels_[image].width, pixels_[image].height}; }
  std::unique_ptr<TextureRowReader> open(size_t image) override {
    ++opened[image];
    if (failOpen[image]) throwBadInput("image " + std::to_string(image) + " has no header");
    return std::make_unique<Reader>(*this, image);
  }

  std::vector<int> opened;
  std::vector<uint32_t> rowsRead;
  std::vector<char> failOpen;
  std::vector<uint32_t> failAtRow;
  std::atomic<bool> outOfOrder{false}, overlapping{false};

 private:
  struct Reader final : TextureRowReader {
    Reader(MemoryRows& s, size_t i) : src(s), image(i) {}
    uint32_t width() const override { return src.pixels_[image].width; }
    uint32_t height() const override { return src.pixels_[image].height; }
    void read(uint8_t* rgba, uint32_t count) override {
      if (src.reading_[image]++ != 0) src.overlapping = true;
      const MeshTexture& t = src.pixels_[image];
      uint32_t& next = src.rowsRead[image];
      if (count == 0 || next + count > t.height) src.outOfOrder = true;
      if (next + count > src.failAtRow[image]) {
        --src.reading_[image];
        throwBadInput("image " + std::to_string(image) + " is truncated");
      }
      std::memcpy(rgba, t.rgba.data() + size_t(next) * t.width * 4, size_t(count) * t.width * 4);
      next += count;
      --src.reading_[image];
    }
    MemoryRows& src;
    size_t image;
  };
  std::vector<MeshTexture> pixels_;
  std::vector<std::vector<size_t>> textures_;
  std::vector<std::atomic<int>> reading_;
};

/// The mesh as a reader leaves it: no pixels in the textures read by rows.
Mesh withoutPixels(Mesh m) {
  for (size_t t : {0, 1, 2}) {
    m.textures[t].width = m.textures[t].height = 0;
    m.textures[t].rgba.clear();
  }
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

/// `n` squares of 12 x 12 voxels side by side, square i on texture i of its
/// own image (heights 16..150: one band to ten, widths 3..40), bilinear,
/// Repeat, texture coordinates from -0.3 to 1.4.
Mesh squaresOfImages(size_t n) {
  std::vector<std::array<double, 3>> pos;
  std::vector<std::array<uint32_t, 3>> tris;
  for (size_t q = 0; q < n; ++q) {
    const uint32_t b = uint32_t(pos.size());
    const double x0 = 14.0 * double(q);
    pos.push_back({x0, 0, 0.5}), pos.push_back({x0 + 12, 0, 0.5}), pos.push_back({x0 + 12, 12, 0.5}),
        pos.push_back({x0, 12, 0.5});
    tris.push_back({b, b + 1, b + 2}), tris.push_back({b, b + 2, b + 3});
  }
  Mesh m = voxtest::meshOf(pos, tris);
  m.materials.clear();
  for (size_t q = 0; q < n; ++q) {
    m.uv0.insert(m.uv0.end(), {{-0.3, 1.4}, {1.4, 1.4}, {1.4, -0.3}, {-0.3, -0.3}});
    m.textures.push_back(noiseTexture(uint32_t(3 + (q * 7) % 38), uint32_t(16 + (q * 37) % 135), unsigned(10 + q)));
    m.materials.push_back({"m" + std::to_string(q), {1, 1, 1, 1}, int(q), 0});
    m.triangleMaterial.push_back(uint32_t(q)), m.triangleMaterial.push_back(uint32_t(q));
  }
  return m;
}

}  // namespace

TEST(DeferredTextures, RowsGiveTheColoursOfPixelsInTheMesh) {
  const Mesh ready = texturedSquares();
  const std::vector<uint8_t> cls(ready.triangles.size(), 1);
  const SceneHeader header = voxtest::twoClassHeader({100, 24, 1});
  const Colours expected = colours(voxelizeMesh(ready, cls, header, VoxelizeSettings{}));
  ASSERT_EQ(expected.size(), size_t(100 * 24)) << "every voxel of the squares is coloured";

  for (unsigned threads : {1u, 2u, 3u}) {
    const Mesh late = withoutPixels(ready);
    MemoryRows rows(MemoryRows::squaresImages(ready), MemoryRows::squaresTextures());
    VoxelizeSettings s;
    s.threads = threads;
    s.textureRows = &rows;
    const Colours got = colours(voxelizeMesh(late, cls, header, s));
    EXPECT_EQ(got, expected) << "threads " << threads << ": colours differ from the bake with pixels from the start";
    for (int i = 0; i < 2; ++i) {
      EXPECT_EQ(rows.opened[i], 1) << "image " << i << " opened once";
      EXPECT_EQ(rows.rowsRead[i], ready.textures[i == 0 ? 0 : 2].height) << "image " << i << " read to its end";
    }
    EXPECT_FALSE(rows.outOfOrder) << "a read of no rows or past the end";
    EXPECT_FALSE(rows.overlapping) << "two workers read one image at once";
  }
  // The textures make the colours: without them (white) other colours come out.
  Mesh white = withoutPixels(ready);
  EXPECT_NE(colours(voxelizeMesh(white, cls, header, VoxelizeSettings{})), expected);
}


TEST(DeferredTextures, ManyImagesSharedBetweenWorkersGiveTheSameColours) {
  // More images than workers, of different sizes and band counts: every image
  // is read once, top to bottom, by one worker at a time, and the colours are
  // those of a bake with the pixels in the mesh, at any thread count.
  for (size_t n : {3u, 5u, 7u, 12u}) {
    const Mesh ready = squaresOfImages(n);
    const std::vector<uint8_t> cls(ready.triangles.size(), 1);
    const SceneHeader header = voxtest::twoClassHeader({uint32_t(14 * n), 12, 1});
    const Colours expected = colours(voxelizeMesh(ready, cls, header, VoxelizeSettings{}));
    ASSERT_GE(expected.size(), size_t(n * 12 * 12)) << "every voxel of the squares is coloured";
    for (unsigned threads : {1u, 2u, 3u, 4u}) {
      Mesh late = ready;
      for (MeshTexture& t : late.textures) t.width = t.height = 0, t.rgba.clear();
      std::vector<std::vector<size_t>> own(n);
      for (size_t i = 0; i < n; ++i) own[i] = {i};
      MemoryRows rows(ready.textures, own);
      VoxelizeSettings s;
      s.threads = threads;
      s.textureRows = &rows;
      const Colours got = colours(voxelizeMesh(late, cls, header, s));
      EXPECT_EQ(got, expected) << n << " images, threads " << threads;
      for (size_t i = 0; i < n; ++i) {
        EXPECT_EQ(rows.opened[i], 1) << "image " << i << " opened once";
        EXPECT_EQ(rows.rowsRead[i], ready.textures[i].height) << "image " << i << " read to its end";
      }
      EXPECT_FALSE(rows.outOfOrder) << "a read of no rows or past the end";
      EXPECT_FALSE(rows.overlapping) << "two workers read one image at once";
    }
  }
}

TEST(DeferredTextures, ImagesNoPieceSamplesAreStillRead) {
  Mesh m = texturedSquares();
  m.triangleMaterial = {3, 3, 3, 3, 3, 3, 3, 3};  // every square on the texture with pixels
  MemoryRows rows(MemoryRows::squaresImages(m), MemoryRows::squaresTextures());
  VoxelizeSettings s;
  s.textureRows = &rows;
  voxelizeMesh(withoutPixels(m), std::vector<uint8_t>(8, 1), voxtest::twoClassHeader({100, 24, 1}), s);
  EXPECT_EQ(rows.rowsRead[0], 53u);
  EXPECT_EQ(rows.rowsRead[1], 33u);
}

TEST(DeferredTextures, TheFirstImageThatCannotBeReadEndsTheBake) {
  const Mesh ready = texturedSquares();
  const std::vector<uint8_t> cls(ready.triangles.size(), 1);
  for (unsigned threads : {1u, 2u}) {
    MemoryRows rows(MemoryRows::squaresImages(ready), MemoryRows::squaresTextures());
    rows.failAtRow[0] = 40;  // image 0 fails in its third band, image 1 at its header
    rows.failOpen[1] = true;
    VoxelizeSettings s;
    s.threads = threads;
    s.textureRows = &rows;
    try {
      voxelizeMesh(withoutPixels(ready), cls, voxtest::twoClassHeader({100, 24, 1}), s);
      ADD_FAILURE() << "the bake went on";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), "image 0 is truncated") << "threads " << threads;
    }
    EXPECT_EQ(rows.opened[1], 1) << "every image is tried";
  }
}

TEST(DeferredTextures, AGltfReadLeavesItsImagesToTheBake) {
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
  EXPECT_EQ(later.textures[0].width, 0u) << "no pixels in the mesh";
  ASSERT_EQ(deferred.images(), 1u);
  EXPECT_EQ(deferred.texturesOf(0), std::vector<size_t>{0});
  EXPECT_EQ(deferred.size(0), (std::array<uint32_t, 2>{2, 2})) << "from the header";
  EXPECT_GT(deferred.readingBytes(2), 0u);
  const std::unique_ptr<TextureRowReader> reader = deferred.open(0);
  std::vector<uint8_t> rows(16);
  reader->read(rows.data(), 1);
  reader->read(rows.data() + 8, 1);
  EXPECT_EQ(rows, now.textures[0].rgba) << "the rows are the pixels a decoding read gives";
  EXPECT_THROW(deferred.open(0), Error) << "an image is read once";
  deferred.finish();
  EXPECT_EQ(deferred.decodedImages(), 1u);

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
  EXPECT_EQ(failing.size(0), (std::array<uint32_t, 2>{0, 0})) << "no header to read";
  try {
    failing.open(0);
    ADD_FAILURE() << "open() accepted an undecodable image";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), direct) << "the error a decoding read gives";
  }
  DeferredTextures unread;
  readGltf(dir.file("bad.gltf"), {}, warnings, &unread);
  try {
    unread.finish();
    ADD_FAILURE() << "finish() accepted an undecodable image";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), direct);
    EXPECT_EQ(e.kind, ErrorKind::BadInput);
  }
}

TEST(TextureSampling, Q16RoundsAsLround) {
  // q16 replaced std::lround(clamp(x) * 65535) (checked over every float in
  // [0, 1] when it was written); here every 61st float and the neighbours of
  // every half-way point k + 0.5.
  auto reference = [](float x) { return uint64_t(std::lround(std::clamp(x, 0.0f, 1.0f) * 65535.0f)); };
  size_t checked = 0;
  for (uint32_t bits = 0; bits <= std::bit_cast<uint32_t>(1.0f); bits += 61, ++checked)
    ASSERT_EQ(q16(std::bit_cast<float>(bits)), reference(std::bit_cast<float>(bits))) << std::bit_cast<float>(bits);
  for (int k = 0; k < 65535; ++k) {
    float x = float((k + 0.5) / 65535.0);
    for (int step = 0; step < 4; ++step) x = std::nextafter(x, 0.0f);
    for (int step = 0; step < 8; ++step, x = std::nextafter(x, 1.0f), ++checked) ASSERT_EQ(q16(x), reference(x)) << x;
  }
  EXPECT_GT(checked, size_t(17000000));
  EXPECT_EQ(q16(-0.5f), 0u);
  EXPECT_EQ(q16(2.0f), 65535u);
  EXPECT_EQ(q16(std::numeric_limits<float>::quiet_NaN()), 0u) << "NaN is black, not lround's unspecified value";
}

TEST(TextureSampling, RepeatWrapsAsTheModulo) {
  // texelSpot wraps Repeat indices by a branch where i is in [-1, n]; the
  // definition is ((i mod n) + n) mod n of the texel below (bilinear) or
  // nearest the wrapped coordinate, and i + 1 wrapped.
  auto wrapped = [](int64_t i, uint32_t n) { return uint32_t(((i % n) + n) % n); };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-3.0, 3.0);
  std::vector<double> values = {0.0, 1.0, -1.0, 2.0, -1e-20, 1e-20, 1.0 - 1e-17, 0.5, -0.5};
  for (int k = 0; k < 20000; ++k) values.push_back(coord(rng));
  for (uint32_t n : {1u, 2u, 7u, 2048u}) {
    for (bool nearest : {false, true}) {
      TextureSampling t{n, n, MeshTexture::Wrap::Repeat, MeshTexture::Wrap::Repeat, nearest};
      for (double s : values) {
        const double x = (s - std::floor(s)) * n - 0.5;
        const int64_t i = int64_t(std::floor(nearest ? x + 0.5 : x));
        const TexelSpot p = texelSpot(t, s, s);
        ASSERT_EQ(p.x0, wrapped(i, n)) << "s " << s << ", n " << n << ", nearest " << nearest;
        ASSERT_EQ(p.x1, wrapped(i + 1, n)) << "s " << s << ", n " << n;
        ASSERT_EQ(p.y0, p.x0);
      }
    }
  }
}

TEST(TextureSampling, PackedSpotsGiveBackEverySpot) {
  // A piece keeps its spot packed (x1 and y1 as 2-bit codes: x0 + 1, 0 or x0);
  // every spot texelSpot makes, in every wrap mode, at the edges and beyond,
  // must come back whole, and the piece must stay 32 bytes.
  static_assert(sizeof(TexturedPiece) == 32);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(-2.5, 3.5);
  std::vector<double> values = {0.0, 1.0, -1.0, 2.0, 1e-20, -1e-20, 1.0 - 1e-17, 0.5, -0.5, 1.5, 0.999, 0.001};
  for (int k = 0; k < 4000; ++k) values.push_back(coord(rng));
  const MeshTexture::Wrap modes[] = {MeshTexture::Wrap::Repeat, MeshTexture::Wrap::ClampToEdge,
                                     MeshTexture::Wrap::MirroredRepeat};
  size_t checked = 0;
  std::map<std::tuple<int, int>, size_t> codes;  // (x code, y code) -> count: every code is reached
  for (uint32_t n : {1u, 2u, 5u, 2048u, 65537u})
    for (const auto ws : modes)
      for (const auto wt : modes)
        for (bool nearest : {false, true}) {
          const TextureSampling t{n, n + 3, ws, wt, nearest};
          for (size_t k = 0; k < values.size(); ++k) {
            const TexelSpot a = texelSpot(t, values[k], values[(k * 7 + 3) % values.size()]);
            const PackedSpot packed = packSpot(a);
            const TexelSpot b = unpackSpot(packed);
            ASSERT_EQ(std::tie(a.x0, a.x1, a.y0, a.y1), std::tie(b.x0, b.x1, b.y0, b.y1))
                << "n " << n << ", wrap " << int(ws) << "/" << int(wt) << ", nearest " << nearest << ", s "
                << values[k];
            ASSERT_EQ(std::bit_cast<uint32_t>(a.fx), std::bit_cast<uint32_t>(b.fx));
            ASSERT_EQ(std::bit_cast<uint32_t>(a.fy), std::bit_cast<uint32_t>(b.fy));
            ++codes[{packed.next & 3, packed.next >> 2}];
            ++checked;
          }
        }
  EXPECT_GT(checked, size_t(350000));
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y) EXPECT_GT((codes[{x, y}]), 0u) << "code pair " << x << ", " << y << " never made";
}
