// Texture decoding for meshes (formats/mesh/texture_image.h): JPEGs written
// here with libjpeg decode back to their pixels within JPEG's loss, the same
// bytes on every call; CMYK, corrupt and oversized JPEGs are refused with a
// reason before pixel memory is taken; PNG and WebP still decode.
#include <gtest/gtest.h>

#include <jpeglib.h>
#include <libdeflate.h>
#include <webp/encode.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "formats/mesh/texture_image.h"

using namespace vox;

namespace {

// A smooth RGB gradient with a few hard edges, w x h.
std::vector<uint8_t> testPattern(int w, int h) {
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = &rgb[(size_t(y) * w + x) * 3];
      p[0] = uint8_t(x * 255 / (w - 1));
      p[1] = uint8_t(y * 255 / (h - 1));
      p[2] = (x / 16 + y / 16) % 2 ? 200 : 40;
    }
  return rgb;
}

std::string encodeJpeg(const std::vector<uint8_t>& pixels, int w, int h, int components, J_COLOR_SPACE space,
                       int quality, bool subsampled = false, bool progressive = false) {
  jpeg_compress_struct c{};
  jpeg_error_mgr err{};
  c.err = jpeg_std_error(&err);
  jpeg_create_compress(&c);
  unsigned char* out = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&c, &out, &size);
  c.image_width = JDIMENSION(w);
  c.image_height = JDIMENSION(h);
  c.input_components = components;
  c.in_color_space = space;
  jpeg_set_defaults(&c);
  jpeg_set_quality(&c, quality, TRUE);
  // 4:4:4 unless asked: the loss is the quantisation only.
  if (!subsampled) c.comp_info[0].h_samp_factor = c.comp_info[0].v_samp_factor = 1;
  if (progressive) jpeg_simple_progression(&c);
  jpeg_start_compress(&c, TRUE);
  while (c.next_scanline < c.image_height) {
    JSAMPROW row = const_cast<uint8_t*>(&pixels[size_t(c.next_scanline) * w * components]);
    jpeg_write_scanlines(&c, &row, 1);
  }
  jpeg_finish_compress(&c);
  jpeg_destroy_compress(&c);
  std::string bytes(reinterpret_cast<char*>(out), size);
  free(out);
  return bytes;
}

/// libjpeg's whole-image decode with the settings the decoder documents
/// (RGBA out, exact integer IDCT), independently of TextureRowDecoder.
std::vector<uint8_t> libjpegRgba(const std::string& jpeg) {
  jpeg_decompress_struct d{};
  jpeg_error_mgr err{};
  d.err = jpeg_std_error(&err);
  jpeg_create_decompress(&d);
  jpeg_mem_src(&d, reinterpret_cast<const unsigned char*>(jpeg.data()), static_cast<unsigned long>(jpeg.size()));
  jpeg_read_header(&d, TRUE);
  d.out_color_space = JCS_EXT_RGBA;
  d.dct_method = JDCT_ISLOW;
  jpeg_start_decompress(&d);
  std::vector<uint8_t> rgba(size_t(d.output_width) * d.output_height * 4);
  while (d.output_scanline < d.output_height) {
    JSAMPROW row = &rgba[size_t(d.output_scanline) * d.output_width * 4];
    jpeg_read_scanlines(&d, &row, 1);
  }
  jpeg_finish_decompress(&d);
  jpeg_destroy_decompress(&d);
  return rgba;
}

}  // namespace

TEST(TextureImage, RowsComeOutAsTheWholeDecodeInAnyChunks) {
  const int w = 97, h = 61;
  const std::vector<uint8_t> rgb = testPattern(w, h);
  for (const auto& [subsampled, progressive] : {std::pair{false, false}, {true, false}, {true, true}}) {
    const std::string jpeg = encodeJpeg(rgb, w, h, 3, JCS_RGB, 90, subsampled, progressive);
    const std::vector<uint8_t> expected = libjpegRgba(jpeg);
    for (uint32_t chunk : {1u, 7u, 16u, 61u}) {
      TextureRowDecoder decoder;
      std::string why;
      ASSERT_TRUE(decoder.open(jpeg, why)) << why;
      ASSERT_EQ(decoder.width(), uint32_t(w));
      ASSERT_EQ(decoder.height(), uint32_t(h));
      std::vector<uint8_t> got(expected.size());
      for (uint32_t y = 0; y < uint32_t(h); y += chunk) {
        const uint32_t n = std::min(chunk, uint32_t(h) - y);
        ASSERT_TRUE(decoder.read(got.data() + size_t(y) * w * 4, n, why)) << why;
        EXPECT_EQ(decoder.rowsRead(), y + n);
      }
      EXPECT_EQ(got, expected) << "subsampled " << subsampled << ", progressive " << progressive << ", chunks of "
                               << chunk;
    }
    TextureImage whole;
    std::string why;
    ASSERT_TRUE(decodeTextureImage(jpeg, whole, why)) << why;
    EXPECT_EQ(whole.rgba, expected) << "decodeTextureImage reads the same rows";
    // The decoder's memory: a baseline JPEG's row buffers, a progressive one's coefficients.
    EXPECT_EQ(textureDecoderBytes(jpeg), progressive ? uint64_t(w) * h * 3 * 2 : uint64_t(w) * 4 * 32);
  }
  // What decodeTextureImage refuses, open() refuses with the same reason.
  TextureRowDecoder bad;
  std::string why;
  EXPECT_FALSE(bad.open("not an image at all", why));
  EXPECT_NE(why.find("not a PNG, JPEG or WebP"), std::string::npos) << why;
}

TEST(TextureImage, JpegDecodesToItsPixelsWithinTheLoss) {
  const int w = 96, h = 64;
  const std::vector<uint8_t> rgb = testPattern(w, h);
  const std::string jpeg = encodeJpeg(rgb, w, h, 3, JCS_RGB, 95);
  TextureImage image;
  std::string why;
  ASSERT_TRUE(decodeTextureImage(jpeg, image, why)) << why;
  ASSERT_EQ(image.width, uint32_t(w));
  ASSERT_EQ(image.height, uint32_t(h));
  ASSERT_EQ(image.rgba.size(), size_t(w) * h * 4);
  double sumError = 0;
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    EXPECT_EQ(image.rgba[i * 4 + 3], 255);
    for (int c = 0; c < 3; ++c) sumError += std::abs(int(image.rgba[i * 4 + c]) - int(rgb[i * 3 + c]));
  }
  EXPECT_LT(sumError / (double(w) * h * 3), 3.0);  // quality 95: a few levels on average
  // Row 0 is the top row: the green channel grows downwards.
  EXPECT_LT(image.rgba[1], 20);
  EXPECT_GT(image.rgba[(size_t(h - 1) * w) * 4 + 1], 235);
  TextureImage again;
  ASSERT_TRUE(decodeTextureImage(jpeg, again, why));
  EXPECT_EQ(again.rgba, image.rgba);
}

TEST(TextureImage, GrayscaleJpegBecomesGrayRgba) {
  const int w = 32, h = 16;
  std::vector<uint8_t> gray(size_t(w) * h);
  for (size_t i = 0; i < gray.size(); ++i) gray[i] = uint8_t(i % w * 8);
  TextureImage image;
  std::string why;
  ASSERT_TRUE(decodeTextureImage(encodeJpeg(gray, w, h, 1, JCS_GRAYSCALE, 100), image, why)) << why;
  for (size_t i = 0; i < gray.size(); ++i) {
    EXPECT_EQ(image.rgba[i * 4], image.rgba[i * 4 + 1]);
    EXPECT_EQ(image.rgba[i * 4], image.rgba[i * 4 + 2]);
    EXPECT_LE(std::abs(int(image.rgba[i * 4]) - int(gray[i])), 3);
  }
}

TEST(TextureImage, CmykCorruptAndOversizedJpegsAreRefused) {
  TextureImage image;
  std::string why;
  std::vector<uint8_t> cmyk(16 * 16 * 4, 100);
  EXPECT_FALSE(decodeTextureImage(encodeJpeg(cmyk, 16, 16, 4, JCS_CMYK, 90), image, why));
  EXPECT_NE(why.find("CMYK"), std::string::npos) << why;

  const std::string garbage = std::string("\xFF\xD8\xFF", 3) + std::string(200, '\x42');
  EXPECT_FALSE(decodeTextureImage(garbage, image, why));
  EXPECT_EQ(why.rfind("JPEG:", 0), 0u) << why;

  // A valid JPEG whose frame header claims 65500 x 65500 pixels (4.3 G pixels).
  std::string huge = encodeJpeg(testPattern(16, 16), 16, 16, 3, JCS_RGB, 90);
  const size_t sof = huge.find("\xFF\xC0", 0, 2);
  ASSERT_NE(sof, std::string::npos);
  huge[sof + 5] = huge[sof + 7] = char(0xFF);
  huge[sof + 6] = huge[sof + 8] = char(0xDC);
  EXPECT_FALSE(decodeTextureImage(huge, image, why));
  EXPECT_NE(why.find("2^28"), std::string::npos) << why;

  EXPECT_FALSE(decodeTextureImage("", image, why));
  EXPECT_FALSE(decodeTextureImage("not an image at all", image, why));
  EXPECT_NE(why.find("not a PNG, JPEG or WebP"), std::string::npos) << why;
}

TEST(TextureImage, WebpStillDecodes) {
  const int w = 20, h = 12;
  std::vector<uint8_t> rgba(size_t(w) * h * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t(i * 7);
  for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;
  uint8_t* out = nullptr;
  const size_t size = WebPEncodeLosslessRGBA(rgba.data(), w, h, w * 4, &out);
  ASSERT_GT(size, 0u);
  const std::string webp(reinterpret_cast<char*>(out), size);
  WebPFree(out);
  TextureImage image;
  std::string why;
  ASSERT_TRUE(decodeTextureImage(webp, image, why)) << why;
  EXPECT_EQ(image.rgba, rgba);  // lossless
  // Decoded whole when opened, then handed out by rows.
  TextureRowDecoder rows;
  ASSERT_TRUE(rows.open(webp, why)) << why;
  std::vector<uint8_t> got(rgba.size());
  ASSERT_TRUE(rows.read(got.data(), 5, why)) << why;
  ASSERT_TRUE(rows.read(got.data() + size_t(w) * 5 * 4, h - 5, why)) << why;
  EXPECT_EQ(got, rgba);
  EXPECT_EQ(textureDecoderBytes(webp), uint64_t(w) * h * 4 * 2);
}

TEST(TextureImage, DamagedJpegDecodesWithAWarning) {
  // A JPEG cut short decodes as far as its data go (libjpeg fills the rest,
  // as viewers and stb_image show it), and says so: decodeTextureImage's
  // warning and the row decoder's are libjpeg's first complaint.
  const int w = 64, h = 48;
  const std::string jpeg = encodeJpeg(testPattern(w, h), w, h, 3, JCS_RGB, 95);
  TextureImage sound;
  std::string why;
  ASSERT_TRUE(decodeTextureImage(jpeg, sound, why)) << why;
  EXPECT_TRUE(sound.warning.empty()) << sound.warning;

  const std::string cut = jpeg.substr(0, jpeg.size() * 2 / 3);
  TextureImage damaged;
  ASSERT_TRUE(decodeTextureImage(cut, damaged, why)) << why;
  ASSERT_EQ(damaged.rgba.size(), sound.rgba.size());
  EXPECT_EQ(damaged.warning.rfind("JPEG: ", 0), 0u) << damaged.warning;
  EXPECT_NE(damaged.warning.find("remature end"), std::string::npos) << damaged.warning;  // libjpeg: "Premature end of JPEG file"
  EXPECT_TRUE(std::equal(damaged.rgba.begin(), damaged.rgba.begin() + w * 4 * 8, sound.rgba.begin()))
      << "the rows before the cut are the sound image's";

  TextureRowDecoder rows;
  ASSERT_TRUE(rows.open(cut, why)) << why;
  std::vector<uint8_t> buffer(size_t(w) * 4 * h);
  ASSERT_TRUE(rows.read(buffer.data(), uint32_t(h), why)) << why;
  EXPECT_EQ(rows.warning(), damaged.warning);
  EXPECT_EQ(buffer, damaged.rgba);

  // A warning that leaves the pixels alone is not one: a JFIF revision
  // libjpeg does not know (APP0's major version byte set to 2).
  std::string revised = jpeg;
  const size_t jfif = revised.find(std::string("JFIF\0", 5));
  ASSERT_NE(jfif, std::string::npos);
  revised[jfif + 5] = 2;
  TextureImage unusual;
  ASSERT_TRUE(decodeTextureImage(revised, unusual, why)) << why;
  EXPECT_TRUE(unusual.warning.empty()) << unusual.warning;
  EXPECT_EQ(unusual.rgba, sound.rgba);

  const std::string message = damagedImageWarning("model.glb: image 2", damaged.warning);
  EXPECT_EQ(message.rfind("model.glb: image 2: damaged image data", 0), 0u) << message;
  EXPECT_NE(message.find(damaged.warning), std::string::npos) << message;
}

namespace {

/// A PNG of `w` x `h` pixels of colour type `type` (3: palette, 6: RGBA8),
/// its rows `raw` (filter byte first) in one stored deflate block; `badIdatCrc`
/// flips a bit of the IDAT chunk's CRC.
std::string storedPng(uint32_t w, uint32_t h, uint8_t type, const std::string& raw, const std::string& palette,
                      bool badIdatCrc) {
  auto be32 = [](uint32_t v) { return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; };
  auto chunk = [&](const std::string& kind, const std::string& data, bool bad) {
    const std::string body = kind + data;
    const uint32_t crc = libdeflate_crc32(0, body.data(), body.size()) ^ (bad ? 1u : 0u);
    return be32(uint32_t(data.size())) + body + be32(crc);
  };
  std::string zlib = "\x78\x01";
  zlib += char(1);  // the final block, stored
  const uint16_t n = uint16_t(raw.size());
  zlib += {char(n & 0xFF), char(n >> 8), char(~n & 0xFF), char((~n >> 8) & 0xFF)};
  zlib += raw;
  zlib += be32(libdeflate_adler32(1, raw.data(), raw.size()));
  std::string ihdr = be32(w) + be32(h);
  ihdr += {char(8), char(type), 0, 0, 0};
  std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr, false);
  if (!palette.empty()) png += chunk("PLTE", palette, false);
  return png + chunk("IDAT", zlib, badIdatCrc) + chunk("IEND", "", false);
}

}  // namespace

TEST(TextureImage, PngWithAFailedCrcDecodesWithAWarning) {
  // stb_image checks no CRC: a PNG whose IDAT CRC fails decodes as before
  // (palette: the fast path never takes it; RGBA: the fast path declines it
  // for the CRC), and now says so; the sound files say nothing.
  const uint32_t w = 8, h = 4;
  std::string paletteRows, rgbaRows;
  for (uint32_t y = 0; y < h; ++y) {
    paletteRows += char(0), rgbaRows += char(0);
    for (uint32_t x = 0; x < w; ++x) {
      paletteRows += char((x + y) % 3);
      rgbaRows += {char(x * 30), char(y * 60), char(200), char(255)};
    }
  }
  const std::string palette = {char(255), 0, 0, 0, char(255), 0, 0, 0, char(255)};
  for (const bool rgba : {false, true}) {
    const std::string& rows = rgba ? rgbaRows : paletteRows;
    const std::string plt = rgba ? "" : palette;
    TextureImage sound, damaged;
    std::string why;
    ASSERT_TRUE(decodeTextureImage(storedPng(w, h, rgba ? 6 : 3, rows, plt, false), sound, why)) << why;
    EXPECT_TRUE(sound.warning.empty()) << sound.warning;
    ASSERT_TRUE(decodeTextureImage(storedPng(w, h, rgba ? 6 : 3, rows, plt, true), damaged, why)) << why;
    EXPECT_EQ(damaged.warning, "PNG: chunk 'IDAT' at byte " + std::to_string(rgba ? 33 : 54) + " fails its CRC");
    EXPECT_EQ(damaged.rgba, sound.rgba) << "the pixels are stb_image's, CRC or not";
    const std::string bytes = storedPng(w, h, rgba ? 6 : 3, rows, plt, true);  // outlives the decoder
    TextureRowDecoder decoder;
    ASSERT_TRUE(decoder.open(bytes, why)) << why;
    EXPECT_EQ(decoder.warning(), damaged.warning);
  }
}
