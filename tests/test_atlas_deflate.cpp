// build-atlas's encoders (issue 14): atlases and packed bitmaps written through
// the row-slice PNG writer decode to the same texels as the one-stream libpng
// writer, and the PNG and EXR bytes do not depend on the thread count.
#include <gtest/gtest.h>

#include "formats/core/file_util.h"
#include "formats/image/image.h"
#include "test_util.h"

using namespace vox;

namespace {

/// An atlas as build-atlas fills it: mostly zero texels, occupied ones in
/// tile-shaped runs, and bands of empty rows. `channels` 1 with a width of side / 8 or side / 4 is a
/// packed 1- or 2-bit bitmap (8 or 4 texels per byte along x).
Image atlasLike(uint32_t w, uint32_t h, uint32_t c, SampleType t) {
  Image img(w, h, c, t);
  const size_t sb = sampleBytes(t), px = size_t(c) * sb;
  uint32_t seed = 7;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      if (((x / 61) + (y / 47)) % 3 != 0 || (x * 7 + y * 3) % 11 < 4) continue;  // empty texels
      if ((y / 40) % 3 == 1) continue;  // empty bands of rows: quiet runs of several KiB (Z_RLE)
      for (size_t b = 0; b < px; ++b) {
        seed = seed * 1664525u + 1013904223u;
        img.pixels[(size_t(y) * w + x) * px + b] = uint8_t((seed >> 24) & (b % 4 == 0 ? 0x0f : 0xff));
      }
    }
  img.text = {{"vox:atlas", "{\"layout\":1}"}};
  return img;
}

}  // namespace

TEST(AtlasDeflate, SlicedPngDecodesToTheSameTexelsAsLibpngAtAnyThreadCount) {
  voxtest::TempDir dir;
  struct Shape {
    uint32_t w, h, c;
    SampleType t;
  };
  // RGBA8 summary/colour, RGBA16 identity, R8/R16 votes, 1- and 2-bit bitmaps
  // packed 8 and 4 texels per byte (odd widths: a partial last byte).
  for (const Shape& s : {Shape{1024, 1024, 4, SampleType::U8}, Shape{700, 333, 4, SampleType::U16},
                         Shape{1000, 517, 1, SampleType::U8}, Shape{1000, 517, 1, SampleType::U16},
                         Shape{(1000 + 7) / 8, 1000, 1, SampleType::U8}, Shape{(1000 + 3) / 4, 1000, 1, SampleType::U8}}) {
    const Image img = atlasLike(s.w, s.h, s.c, s.t);
    const std::string what = std::to_string(s.w) + "x" + std::to_string(s.h) + "x" + std::to_string(s.c) + " " +
                             sampleTypeName(s.t);
    writePng(img, dir.file("serial.png"));
    const Image serial = readPng(dir.file("serial.png"));
    ASSERT_TRUE(serial.pixels == img.pixels) << what;
    std::string first;
    for (unsigned threads : {1u, 2u, 3u}) {
      const std::string path = dir.file("t" + std::to_string(threads) + ".png");
      writePngParallel(img, path, kDefaultPngZlibLevel, threads);
      const std::string bytes = readFileBytes(path);
      if (threads == 1) first = bytes;
      else EXPECT_EQ(bytes, first) << what << ": threads " << threads;
      const Image back = readPng(path);
      ASSERT_EQ(back.width, img.width) << what;
      ASSERT_EQ(back.height, img.height) << what;
      ASSERT_EQ(back.channels, img.channels) << what;
      ASSERT_EQ(back.type, img.type) << what;
      EXPECT_TRUE(back.pixels == serial.pixels) << what << ": threads " << threads;
      EXPECT_EQ(back.textValue("vox:atlas"), "{\"layout\":1}") << what;
    }
  }
}

TEST(AtlasDeflate, ExrBytesDoNotDependOnThreads) {
  voxtest::TempDir dir;
  for (SampleType t : {SampleType::U32, SampleType::F16, SampleType::F32})
    for (uint32_t c : {1u, 4u}) {
      const Image img = atlasLike(300, 517, c, t);
      std::string first;
      for (unsigned threads : {1u, 2u, 3u}) {
        const std::string path = dir.file("e" + std::to_string(threads) + ".exr");
        writeExr(img, path, ExrCompression::Zip, threads);
        const std::string bytes = readFileBytes(path);
        if (threads == 1) first = bytes;
        else EXPECT_EQ(bytes, first) << sampleTypeName(t) << " x" << c << ": threads " << threads;
        const Image back = readExr(path);
        EXPECT_TRUE(back.pixels == img.pixels) << sampleTypeName(t) << " x" << c << ": threads " << threads;
      }
    }
}
