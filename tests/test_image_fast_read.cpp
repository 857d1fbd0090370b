// The image readers' fast paths (formats/mesh/png_fast_decode.h, and the
// scanline chunk reader in image_exr.cpp) against the libraries they stand in
// for: every PNG shape, filter and chunk layout libpng writes, read as images
// (against libpng) and as textures (against stb_image), and every EXR
// compression, sample type, channel set, data window and line order OpenEXR
// writes, read by vox and by the library itself here, must give the same
// pixels and text; files the fast paths do not take must still read as the
// library reads them.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <gtest/gtest.h>
#include <png.h>
#include <stb/stb_image.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "formats/core/file_util.h"
#include "formats/image/image.h"
#include "formats/mesh/png_fast_decode.h"
#include "formats/mesh/texture_image.h"
#include "formats/image/png_memory.h"
#include "libvox/core/error.h"
#include "test_util.h"

using namespace vox;

namespace {

// ------------------------------------------------------------------ PNG

struct PngSpec {
  uint32_t width = 300, height = 40;
  int colorType = PNG_COLOR_TYPE_RGBA;
  int depth = 8;
  int filters = PNG_ALL_FILTERS;
  int level = 6;
  size_t idatBytes = 8192;  // libpng's IDAT size: small values give many IDAT chunks
  bool interlace = false;
  bool textBefore = true, textAfter = true;
  bool compressedText = false;
  bool trns = false;
};

int channelsOf(int colorType) {
  switch (colorType) {
    case PNG_COLOR_TYPE_GRAY: return 1;
    case PNG_COLOR_TYPE_GRAY_ALPHA: return 2;
    case PNG_COLOR_TYPE_RGB: return 3;
    case PNG_COLOR_TYPE_PALETTE: return 1;
    default: return 4;
  }
}

// Smooth gradients with noise and flat runs: every filter finds something to do.
std::vector<uint8_t> samples(const PngSpec& s) {
  const size_t bytes = size_t(s.width) * s.height * channelsOf(s.colorType) * (s.depth == 16 ? 2 : 1);
  std::vector<uint8_t> v(bytes);
  uint32_t seed = 77;
  const size_t rowBytes = bytes / s.height;
  for (uint32_t y = 0; y < s.height; ++y)
    for (size_t i = 0; i < rowBytes; ++i) {
      seed = seed * 1664525u + 1013904223u;
      uint8_t b = uint8_t(y * 3 + i / 7);
      if ((y / 5) % 3 == 1) b = uint8_t(b + (seed >> 29));   // a little noise
      if ((y / 5) % 3 == 2 && i > rowBytes / 2) b = 200;     // a flat run
      if (s.colorType == PNG_COLOR_TYPE_PALETTE || s.depth < 8) b &= uint8_t((1 << std::min(s.depth, 8)) - 1);
      v[size_t(y) * rowBytes + i] = b;
    }
  return v;
}

bool writeWithLibpng(const PngSpec& s, const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  std::vector<uint8_t> px = samples(s);
  const size_t rowBytes = png_size_t(px.size() / s.height);
  bool ok = false;
  if (!setjmp(png_jmpbuf(png))) {
    png_init_io(png, f);
    png_set_filter(png, 0, s.filters);
    png_set_compression_level(png, s.level);
    png_set_compression_buffer_size(png, s.idatBytes);
    png_set_IHDR(png, info, s.width, s.height, s.depth, s.colorType,
                 s.interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_color palette[16];
    for (int i = 0; i < 16; ++i) palette[i] = {png_byte(i * 16), png_byte(255 - i * 16), png_byte(i * 7)};
    if (s.colorType == PNG_COLOR_TYPE_PALETTE) png_set_PLTE(png, info, palette, 16);
    if (s.trns) {
      png_color_16 key{};
      key.gray = 5, key.red = 5, key.green = 6, key.blue = 7;
      png_set_tRNS(png, info, nullptr, 0, &key);
    }
    png_text before[2] = {};
    before[0].compression = s.compressedText ? PNG_TEXT_COMPRESSION_zTXt : PNG_TEXT_COMPRESSION_NONE;
    before[0].key = const_cast<char*>("vox:canonical");
    before[0].text = const_cast<char*>("{\"mode\": \"class\", \"dims\": [1, 2, 3]}");
    before[1].compression = PNG_TEXT_COMPRESSION_NONE;
    before[1].key = const_cast<char*>("Software");
    before[1].text = const_cast<char*>("");
    if (s.textBefore) png_set_text(png, info, before, 2);
    png_set_gAMA(png, info, 0.45455);
    png_write_info(png, info);
    if (s.depth == 16) png_set_swap(png);
    std::vector<png_bytep> rows(s.height);
    for (uint32_t y = 0; y < s.height; ++y) rows[y] = px.data() + y * rowBytes;
    png_write_image(png, rows.data());
    png_text after[1] = {};
    after[0].compression = PNG_TEXT_COMPRESSION_NONE;
    after[0].key = const_cast<char*>("Comment");
    after[0].text = const_cast<char*>("written after the pixels");
    if (s.textAfter) png_set_text(png, info, after, 1);
    png_write_end(png, info);
    ok = true;
  }
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
  return ok;
}

// libpng's own reading, with the transforms vox's reader asks for.
Image readWithLibpng(const std::string& path) {
  Image image;
  FILE* f = std::fopen(path.c_str(), "rb");
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(f);
    ADD_FAILURE() << "libpng could not read " << path;
    return Image();
  }
  png_init_io(png, f);
  png_read_info(png, info);
  const int colorType = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
  if (colorType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (colorType == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (depth == 16) png_set_swap(png);
  const int passes = png_set_interlace_handling(png);
  (void)passes;
  png_read_update_info(png, info);
  image.width = png_get_image_width(png, info);
  image.height = png_get_image_height(png, info);
  image.channels = png_get_channels(png, info);
  image.type = png_get_bit_depth(png, info) == 16 ? SampleType::U16 : SampleType::U8;
  image.pixels.assign(image.rowBytes() * image.height, 0);
  std::vector<png_bytep> rows(image.height);
  for (uint32_t y = 0; y < image.height; ++y) rows[y] = image.pixels.data() + y * image.rowBytes();
  png_read_image(png, rows.data());
  png_read_end(png, info);
  png_textp texts = nullptr;
  int count = 0;
  png_get_text(png, info, &texts, &count);
  for (int i = 0; i < count; ++i) image.text.emplace_back(texts[i].key, std::string(texts[i].text, texts[i].text_length));
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(f);
  return image;
}

void expectSameImage(const Image& a, const Image& b, const std::string& what) {
  EXPECT_EQ(a.width, b.width) << what;
  EXPECT_EQ(a.height, b.height) << what;
  EXPECT_EQ(a.channels, b.channels) << what;
  EXPECT_EQ(a.type, b.type) << what;
  EXPECT_TRUE(a.pixels == b.pixels) << what;
  EXPECT_EQ(a.text, b.text) << what;
}

bool fastPathTakes(const std::string& path) {
  const std::string bytes = readFileBytes(path);
  DecodedPng image;
  return decodePngFast(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), image);
}

}  // namespace

TEST(ImageFastRead, PngEveryShapeAndFilterReadsAsLibpngReadsIt) {
  voxtest::TempDir dir;
  int taken = 0, cases = 0;
  const int filterSets[] = {PNG_FILTER_NONE, PNG_FILTER_SUB, PNG_FILTER_UP, PNG_FILTER_AVG, PNG_FILTER_PAETH,
                            PNG_ALL_FILTERS};
  for (int colorType : {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGBA})
    for (int depth : {8, 16})
      for (int filters : filterSets)
        for (uint32_t width : {1u, 5u, 600u}) {
          PngSpec s;
          s.colorType = colorType, s.depth = depth, s.filters = filters, s.width = width;
          s.height = width == 1 ? 1 : width == 5 ? 40 : 80;
          s.idatBytes = filters == PNG_FILTER_SUB ? 200 : 8192;  // many IDAT chunks in some cases
          s.textAfter = width != 5;
          const std::string what = "colour type " + std::to_string(colorType) + ", " + std::to_string(depth) +
                                   " bit, filters " + std::to_string(filters) + ", width " + std::to_string(width);
          const std::string path = dir.file("p.png");
          ASSERT_TRUE(writeWithLibpng(s, path)) << what;
          expectSameImage(readPng(path), readWithLibpng(path), what);
          const std::string bytes = readFileBytes(path);
          expectSameImage(readPngMemory(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), "p.png"),
                          readWithLibpng(path), what + " (from memory)");
          ++cases;
          if (fastPathTakes(path)) ++taken;
          else EXPECT_NE(width, 600u) << what << ": the fast path declined a plain image";
        }
  // The large images take the fast path; small ones (libpng writes them with
  // zlib windows under 32 KB) go to libpng.
  EXPECT_GE(taken, cases / 3);
}

// Textures: decodeTextureImage (the fast path, converted to RGBA8) against
// stb_image's own decoding of the same file.
TEST(ImageFastRead, PngTexturesDecodeAsStbImageDecodesThem) {
  voxtest::TempDir dir;
  int taken = 0;
  for (int colorType : {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGBA,
                        PNG_COLOR_TYPE_PALETTE})
    for (int depth : {8, 16})
      for (int filters : {PNG_FILTER_SUB, PNG_FILTER_PAETH, PNG_ALL_FILTERS})
        for (uint32_t width : {3u, 600u}) {
          if (colorType == PNG_COLOR_TYPE_PALETTE && depth == 16) continue;
          PngSpec s;
          s.colorType = colorType, s.depth = colorType == PNG_COLOR_TYPE_PALETTE ? 4 : depth, s.filters = filters;
          s.width = width, s.height = width == 3 ? 7 : 80;
          const std::string what = "colour type " + std::to_string(colorType) + ", " + std::to_string(s.depth) +
                                   " bit, filters " + std::to_string(filters) + ", width " + std::to_string(width);
          const std::string path = dir.file("t.png");
          ASSERT_TRUE(writeWithLibpng(s, path)) << what;
          const std::string bytes = readFileBytes(path);
          TextureImage ours;
          std::string why;
          ASSERT_TRUE(decodeTextureImage(bytes, ours, why)) << what << ": " << why;
          int w = 0, h = 0, n = 0;
          stbi_uc* ref = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &w, &h, &n, 4);
          ASSERT_NE(ref, nullptr) << what;
          EXPECT_EQ(ours.width, uint32_t(w)) << what;
          EXPECT_EQ(ours.height, uint32_t(h)) << what;
          EXPECT_TRUE(ours.rgba.size() == size_t(w) * h * 4 && std::memcmp(ours.rgba.data(), ref, ours.rgba.size()) == 0)
              << what;
          stbi_image_free(ref);
          if (fastPathTakes(path)) ++taken;
        }
  EXPECT_GE(taken, 24);  // the 600-wide images of the four colour types, both depths, three filter sets
}

TEST(ImageFastRead, PngShapesTheFastPathDeclinesStillRead) {
  voxtest::TempDir dir;
  struct Case {
    const char* name;
    PngSpec spec;
  };
  std::vector<Case> cases;
  PngSpec s;
  s.colorType = PNG_COLOR_TYPE_PALETTE, s.depth = 4;
  cases.push_back({"4-bit palette", s});
  s = PngSpec();
  s.colorType = PNG_COLOR_TYPE_GRAY, s.depth = 2;
  cases.push_back({"2-bit gray", s});
  s = PngSpec();
  s.interlace = true;
  cases.push_back({"interlaced", s});
  s = PngSpec();
  s.colorType = PNG_COLOR_TYPE_RGB, s.trns = true;
  cases.push_back({"RGB with tRNS", s});
  s = PngSpec();
  s.compressedText = true;
  cases.push_back({"zTXt", s});
  for (const Case& c : cases) {
    const std::string path = dir.file("d.png");
    ASSERT_TRUE(writeWithLibpng(c.spec, path)) << c.name;
    EXPECT_FALSE(fastPathTakes(path)) << c.name;
    expectSameImage(readPng(path), readWithLibpng(path), c.name);
  }
}

TEST(ImageFastRead, DamagedPngIsDeclinedAndRefusedByLibpng) {
  voxtest::TempDir dir;
  const std::string path = dir.file("ok.png");
  ASSERT_TRUE(writeWithLibpng(PngSpec(), path));
  ASSERT_TRUE(fastPathTakes(path));
  const std::string good = readFileBytes(path);
  const size_t idat = good.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  // A flipped bit in the pixel data: the CRC no longer matches.
  std::string bad = good;
  bad[idat + 40] = char(bad[idat + 40] ^ 0x10);
  writeFileBytes(dir.file("crc.png"), bad);
  EXPECT_FALSE(fastPathTakes(dir.file("crc.png")));
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readPng(dir.file("crc.png")); }, ErrorKind::BadInput,
                                      {"crc.png", "corrupt or truncated PNG"}));
  // IEND cut off.
  writeFileBytes(dir.file("cut.png"), good.substr(0, good.size() - 12));
  EXPECT_FALSE(fastPathTakes(dir.file("cut.png")));
}

// ------------------------------------------------------------------ EXR

namespace {

struct ExrSpec {
  Imf::Compression compression = Imf::ZIP_COMPRESSION;
  Imf::PixelType type = Imf::FLOAT;
  std::vector<std::string> channels = {"R"};
  Imath::Box2i window{Imath::V2i(0, 0), Imath::V2i(36, 20)};
  Imf::LineOrder order = Imf::INCREASING_Y;
  bool noise = false;  // incompressible samples: chunks stored as they are
};

size_t bytesOf(Imf::PixelType t) { return t == Imf::HALF ? 2 : 4; }

void writeWithImf(const ExrSpec& s, const std::string& path) {
  const int w = s.window.max.x - s.window.min.x + 1, h = s.window.max.y - s.window.min.y + 1;
  Imf::Header header(s.window, s.window);
  header.compression() = s.compression;
  header.lineOrder() = s.order;
  header.insert("vox:canonical", Imf::StringAttribute("{\"mode\": \"depth\"}"));
  header.insert("comment", Imf::StringAttribute("fast read test"));
  for (const std::string& c : s.channels) header.channels().insert(c, Imf::Channel(s.type));
  const size_t sb = bytesOf(s.type);
  std::vector<std::vector<uint8_t>> planes(s.channels.size(), std::vector<uint8_t>(size_t(w) * h * sb));
  uint32_t seed = 99;
  for (size_t c = 0; c < planes.size(); ++c)
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      seed = seed * 1664525u + 1013904223u;
      const float v = s.noise ? float(seed >> 8) : float((i % size_t(w)) / 4 + c * 100 + (i / size_t(w)) * 0.5);
      if (s.type == Imf::FLOAT) std::memcpy(&planes[c][i * 4], &v, 4);
      else if (s.type == Imf::UINT) {
        const uint32_t u = s.noise ? seed : uint32_t(v * 2);
        std::memcpy(&planes[c][i * 4], &u, 4);
      } else {
        const uint16_t bits = s.noise ? uint16_t(seed >> 16) & 0x7bff : Imath::half(v).bits();
        std::memcpy(&planes[c][i * 2], &bits, 2);
      }
    }
  Imf::FrameBuffer fb;
  for (size_t c = 0; c < planes.size(); ++c) {
    char* base = reinterpret_cast<char*>(planes[c].data()) - (size_t(s.window.min.x) + size_t(s.window.min.y) * w) * sb;
    fb.insert(s.channels[c], Imf::Slice(s.type, base, sb, sb * size_t(w)));
  }
  Imf::OutputFile out(path.c_str(), header);
  out.setFrameBuffer(fb);
  out.writePixels(h);
}

// OpenEXR's own reading of what readExr returns: R, G, B, A up to the first
// missing one, interleaved.
std::vector<uint8_t> readWithImf(const std::string& path, uint32_t channels, Imf::PixelType type) {
  Imf::InputFile in(path.c_str());
  const Imath::Box2i dw = in.header().dataWindow();
  const size_t w = size_t(dw.max.x - dw.min.x + 1), h = size_t(dw.max.y - dw.min.y + 1), sb = bytesOf(type);
  std::vector<uint8_t> px(w * h * channels * sb, 0);
  Imf::FrameBuffer fb;
  static const char* const kNames[4] = {"R", "G", "B", "A"};
  char* base = reinterpret_cast<char*>(px.data()) - (size_t(dw.min.x) * channels * sb + size_t(dw.min.y) * w * channels * sb);
  for (uint32_t c = 0; c < channels; ++c)
    fb.insert(kNames[c], Imf::Slice(type, base + c * sb, channels * sb, w * channels * sb));
  in.setFrameBuffer(fb);
  in.readPixels(dw.min.y, dw.max.y);
  return px;
}

}  // namespace

TEST(ImageFastRead, ExrEveryCompressionTypeAndLayoutReadsAsOpenExrReadsIt) {
  voxtest::TempDir dir;
  const std::vector<std::vector<std::string>> channelSets = {
      {"R"}, {"R", "G", "B"}, {"R", "G", "B", "A"}, {"Z", "R"}, {"A", "B", "G", "R", "depth"}, {"R", "B"}};
  const std::vector<Imath::Box2i> windows = {
      Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(36, 20)), Imath::Box2i(Imath::V2i(-3, 5), Imath::V2i(60, 21)),
      Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(0, 0)), Imath::Box2i(Imath::V2i(2, -7), Imath::V2i(130, 40))};
  int cases = 0;
  for (Imf::Compression compression :
       {Imf::NO_COMPRESSION, Imf::ZIPS_COMPRESSION, Imf::ZIP_COMPRESSION, Imf::RLE_COMPRESSION, Imf::PIZ_COMPRESSION})
    for (Imf::PixelType type : {Imf::HALF, Imf::FLOAT, Imf::UINT})
      for (size_t cs = 0; cs < channelSets.size(); ++cs)
        for (size_t wi = 0; wi < windows.size(); ++wi)
          for (bool noise : {false, true}) {
            if (noise && wi != 3) continue;
            ExrSpec s;
            s.compression = compression, s.type = type, s.channels = channelSets[cs], s.window = windows[wi];
            s.noise = noise;
            s.order = (cs + wi) % 2 ? Imf::DECREASING_Y : Imf::INCREASING_Y;
            const std::string what = "compression " + std::to_string(int(compression)) + ", type " +
                                     std::to_string(int(type)) + ", channel set " + std::to_string(cs) +
                                     ", window " + std::to_string(wi) + (noise ? ", noise" : "");
            const std::string path = dir.file("e.exr");
            writeWithImf(s, path);
            const Image image = readExr(path);
            const uint32_t expectedChannels = cs == 5 ? 1 : cs == 3 ? 1 : uint32_t(std::min<size_t>(4, channelSets[cs].size()));
            ASSERT_EQ(image.channels, expectedChannels) << what;
            EXPECT_TRUE(image.pixels == readWithImf(path, image.channels, type)) << what;
            EXPECT_EQ(image.textValue("vox:canonical"), "{\"mode\": \"depth\"}") << what;
            EXPECT_EQ(image.textValue("comment"), "fast read test") << what;
            ++cases;
          }
  EXPECT_EQ(cases, 5 * 3 * 6 * 5);
}
